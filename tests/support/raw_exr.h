// Shared by tests: writes an OpenEXR file with arbitrary FLOAT channels and no checks, to make
// the bad environment maps (wrong channels, NaN, negative values) the readers must refuse.
#pragma once

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include <filesystem>
#include <string>
#include <vector>

namespace testsupport {

// The named FLOAT channels, values interleaved per pixel (w·h·channels values).
inline void writeRawExr(const std::filesystem::path& path, int w, int h,
                        const std::vector<std::string>& channels, const std::vector<float>& data) {
    Imf::Header header(w, h);
    for (const auto& c : channels)
        header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    Imf::FrameBuffer fb;
    const size_t nc = channels.size();
    const size_t xs = nc * sizeof(float), ys = xs * static_cast<size_t>(w);
    char* base = reinterpret_cast<char*>(const_cast<float*>(data.data()));
    for (size_t c = 0; c < nc; ++c)
        fb.insert(channels[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys));
    Imf::OutputFile file(path.string().c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(h);
}

} // namespace testsupport
