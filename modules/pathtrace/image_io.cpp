// pathtrace/image_io: OpenEXR writing and reading of Image (see image_io.h).
#include "pathtrace/image_io.h"

#include "core/core.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <ImfStringAttribute.h>

#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

namespace pathtrace {
namespace {
const char* kMean[3] = {"R", "G", "B"};
const char* kVar[3] = {"varR", "varG", "varB"};
} // namespace

void writeExr(const std::filesystem::path& path, const Image& img) {
    const std::string name = path.string();
    const size_t n = static_cast<size_t>(img.width) * static_cast<size_t>(img.height);
    if (img.width < 1 || img.height < 1)
        throw core::Error(name, 0,
                          "cannot write an empty image (" + std::to_string(img.width) + "x" +
                              std::to_string(img.height) + ")");
    if (img.mean.size() != 3 * n || img.variance.size() != 3 * n)
        throw core::Error(name, 0, "image buffers do not match its size");
    std::string bytes;
    try {
        Imf::Header header(img.width, img.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        for (int c = 0; c < 3; ++c) {
            header.channels().insert(kMean[c], Imf::Channel(Imf::FLOAT));
            header.channels().insert(kVar[c], Imf::Channel(Imf::FLOAT));
        }
        header.insert("bw.samples", Imf::StringAttribute(std::to_string(img.samples)));
        Imf::FrameBuffer fb;
        const size_t xs = 3 * sizeof(float), ys = xs * static_cast<size_t>(img.width);
        // OpenEXR only reads through these pointers when writing.
        char* mean = reinterpret_cast<char*>(const_cast<float*>(img.mean.data()));
        char* var = reinterpret_cast<char*>(const_cast<float*>(img.variance.data()));
        for (int c = 0; c < 3; ++c) {
            fb.insert(kMean[c], Imf::Slice(Imf::FLOAT, mean + c * sizeof(float), xs, ys));
            fb.insert(kVar[c], Imf::Slice(Imf::FLOAT, var + c * sizeof(float), xs, ys));
        }
        Imf::StdOSStream os;
        {
            Imf::OutputFile file(os, header);
            file.setFrameBuffer(fb);
            file.writePixels(img.height);
        }
        bytes = os.str();
    } catch (const std::exception& e) {
        throw core::Error(name, 0, std::string("cannot encode EXR: ") + e.what());
    }
    core::writeFile(path, bytes);
}

Image readExr(const std::filesystem::path& path) {
    const std::string name = path.string();
    const std::string bytes = core::readFile(path);
    Image img;
    try {
        Imf::StdISStream is;
        is.str(bytes);
        Imf::InputFile file(is);
        const Imath::Box2i dw = file.header().dataWindow();
        const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
        if (w < 1 || h < 1) throw core::Error(name, 0, "EXR has an empty data window");
        const Imf::ChannelList& ch = file.header().channels();
        for (int c = 0; c < 3; ++c)
            if (!ch.findChannel(kMean[c]))
                throw core::Error(name, 0, std::string("EXR has no channel '") + kMean[c] + "'");
        img.width = w;
        img.height = h;
        const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
        img.mean.assign(3 * n, 0.0f);
        img.variance.assign(3 * n, 0.0f);
        const size_t xs = 3 * sizeof(float), ys = xs * static_cast<size_t>(w);
        char* mean = reinterpret_cast<char*>(img.mean.data());
        char* var = reinterpret_cast<char*>(img.variance.data());
        Imf::FrameBuffer fb;
        for (int c = 0; c < 3; ++c) { // Slice::Make maps the data window's origin to index 0
            fb.insert(kMean[c], Imf::Slice::Make(Imf::FLOAT, mean + c * sizeof(float), dw, xs, ys));
            if (ch.findChannel(kVar[c]))
                fb.insert(kVar[c],
                          Imf::Slice::Make(Imf::FLOAT, var + c * sizeof(float), dw, xs, ys));
        }
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        if (const auto* s = file.header().findTypedAttribute<Imf::StringAttribute>("bw.samples"))
            img.samples = std::strtoull(s->value().c_str(), nullptr, 10);
    } catch (const core::Error&) {
        throw;
    } catch (const std::exception& e) {
        throw core::Error(name, 0, std::string("cannot read EXR: ") + e.what());
    }
    return img;
}

} // namespace pathtrace
