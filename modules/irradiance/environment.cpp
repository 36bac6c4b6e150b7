// irradiance/environment: lat-long maps, EXR I/O, quadrature nodes, default sky (see
// environment.h).
#include "irradiance/environment.h"

#include "core/core.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <numbers>
#include <string>
#include <string_view>

namespace irradiance {
namespace {
const char* kChannels[3] = {"R", "G", "B"};

std::string texelText(size_t i, int width) {
    const size_t texel = i / 3, x = texel % static_cast<size_t>(width),
                 y = texel / static_cast<size_t>(width);
    std::string s = "texel (";
    s += std::to_string(x);
    s += ", ";
    s += std::to_string(y);
    s += ") channel ";
    s += kChannels[i % 3];
    return s;
}

// 2 × 2 box filter, solid-angle weighted across the two rows (exact for ∫ L dω per cell).
EnvironmentMap halve(const EnvironmentMap& env) {
    EnvironmentMap out;
    out.width = env.width / 2;
    out.height = env.height / 2;
    out.rgb.assign(3 * static_cast<size_t>(out.width) * out.height, 0.0f);
    for (int y = 0; y < out.height; ++y) {
        const double wa = texelSolidAngle(2 * y, env.width, env.height);
        const double wb = texelSolidAngle(2 * y + 1, env.width, env.height);
        for (int x = 0; x < out.width; ++x) {
            const glm::dvec3 a =
                glm::dvec3(env.texel(2 * x, 2 * y)) + glm::dvec3(env.texel(2 * x + 1, 2 * y));
            const glm::dvec3 b = glm::dvec3(env.texel(2 * x, 2 * y + 1)) +
                                 glm::dvec3(env.texel(2 * x + 1, 2 * y + 1));
            const glm::dvec3 m = (wa * a + wb * b) / (2.0 * (wa + wb));
            const size_t i = 3 * (static_cast<size_t>(y) * out.width + x);
            for (int c = 0; c < 3; ++c)
                out.rgb[i + c] = static_cast<float>(m[c]);
        }
    }
    return out;
}
// Walks the attributes of the first header of an EXR (name, type, 32-bit size, value; an empty
// name ends the header) and refuses a size past the end of the file before OpenEXR allocates it:
// a few bytes must not make the library reserve and clear gigabytes.
void checkExrHeader(std::string_view bytes, const std::string& name) {
    auto fail = [&](const std::string& msg) {
        throw core::Error(name, 0, "cannot read EXR environment: header: " + msg);
    };
    if (bytes.size() < 8 || bytes.substr(0, 4) != std::string_view("\x76\x2f\x31\x01", 4))
        fail("not an OpenEXR file (no magic number)");
    size_t pos = 8;
    auto text = [&](const char* what) {
        const size_t end = bytes.find('\0', pos);
        if (end == std::string_view::npos || end - pos > 255)
            fail(std::string("truncated ") + what);
        std::string_view t = bytes.substr(pos, end - pos);
        pos = end + 1;
        return t;
    };
    for (;;) {
        const std::string_view attr = text("attribute name");
        if (attr.empty()) return;
        text("attribute type");
        if (bytes.size() - pos < 4) fail("truncated size of attribute '" + std::string(attr) + "'");
        int32_t size = 0;
        std::memcpy(&size, bytes.data() + pos, 4); // little-endian file, little-endian host
        pos += 4;
        if (size < 0 || size_t(size) > bytes.size() - pos)
            fail("attribute '" + std::string(attr) + "' claims " + std::to_string(size) +
                 " bytes; the file has " + std::to_string(bytes.size() - pos) + " after it");
        pos += size_t(size);
    }
}
} // namespace

glm::vec3 latLongDirection(double theta, double phi) {
    return glm::vec3(static_cast<float>(std::sin(theta) * std::cos(phi)),
                     static_cast<float>(std::cos(theta)),
                     static_cast<float>(std::sin(theta) * std::sin(phi)));
}

glm::mat3 worldFromEnvironment(float a) {
    const float c = std::cos(a), s = std::sin(a);
    return glm::mat3(glm::vec3(c, 0, -s), glm::vec3(0, 1, 0), glm::vec3(s, 0, c)); // columns
}

double texelSolidAngle(int y, int width, int height) {
    const double t0 = std::numbers::pi * y / height, t1 = std::numbers::pi * (y + 1) / height;
    return 2.0 * std::numbers::pi / width * (std::cos(t0) - std::cos(t1));
}

void validateEnvironment(const EnvironmentMap& env, const std::string& name) {
    if (env.width < 1 || env.height < 1 || env.width > 16384 || env.height > 16384)
        throw core::Error(name, 0,
                          "environment size " + std::to_string(env.width) + "x" +
                              std::to_string(env.height) + " is outside 1..16384");
    if (env.rgb.size() != 3 * static_cast<size_t>(env.width) * env.height)
        throw core::Error(name, 0, "environment data does not match its size");
    for (size_t i = 0; i < env.rgb.size(); ++i) {
        const float v = env.rgb[i];
        if (!std::isfinite(v))
            throw core::Error(name, 0, "non-finite radiance at " + texelText(i, env.width));
        if (v < 0.0f) throw core::Error(name, 0, "negative radiance at " + texelText(i, env.width));
    }
}

// Most texels readEnvironment accepts (8192x4096, 384 MiB of float RGB).
constexpr long long kMaxReadTexels = 8192LL * 4096LL;

EnvironmentMap readEnvironment(const std::filesystem::path& path) {
    const std::string name = path.string();
    const std::string bytes = core::readFile(path); // names the path when missing
    checkExrHeader(bytes, name);
    EnvironmentMap env;
    try {
        Imf::StdISStream is;
        is.str(bytes);
        Imf::InputFile file(is);
        const Imath::Box2i dw = file.header().dataWindow();
        const long long w = static_cast<long long>(dw.max.x) - dw.min.x + 1;
        const long long h = static_cast<long long>(dw.max.y) - dw.min.y + 1;
        if (w < 1 || h < 1 || w > 16384 || h > 16384)
            throw core::Error(name, 0, "EXR data window is empty or larger than 16384");
        // The header alone sets the allocation: a few bytes must not claim gigabytes.
        if (w * h > kMaxReadTexels)
            throw core::Error(name, 0,
                              "EXR data window " + std::to_string(w) + "x" + std::to_string(h) +
                                  " has more than 8192x4096 texels");
        const Imf::ChannelList& ch = file.header().channels();
        for (const char* c : kChannels)
            if (!ch.findChannel(c))
                throw core::Error(name, 0,
                                  std::string("EXR has no channel '") + c +
                                      "' (an environment needs R, G and B)");
        env.width = static_cast<int>(w);
        env.height = static_cast<int>(h);
        env.rgb.assign(3 * static_cast<size_t>(w * h), 0.0f);
        const size_t xs = 3 * sizeof(float), ys = xs * static_cast<size_t>(w);
        char* base = reinterpret_cast<char*>(env.rgb.data());
        Imf::FrameBuffer fb;
        for (int c = 0; c < 3; ++c)
            fb.insert(kChannels[c],
                      Imf::Slice::Make(Imf::FLOAT, base + c * sizeof(float), dw, xs, ys));
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
    } catch (const core::Error&) {
        throw;
    } catch (const std::exception& e) {
        throw core::Error(name, 0, std::string("cannot read EXR environment: ") + e.what());
    }
    validateEnvironment(env, name);
    return env;
}

void writeEnvironment(const std::filesystem::path& path, const EnvironmentMap& env) {
    const std::string name = path.string();
    validateEnvironment(env, name);
    std::string bytes;
    try {
        Imf::Header header(env.width, env.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        for (const char* c : kChannels)
            header.channels().insert(c, Imf::Channel(Imf::FLOAT));
        Imf::FrameBuffer fb;
        const size_t xs = 3 * sizeof(float), ys = xs * static_cast<size_t>(env.width);
        // OpenEXR only reads through this pointer when writing.
        char* base = reinterpret_cast<char*>(const_cast<float*>(env.rgb.data()));
        for (int c = 0; c < 3; ++c)
            fb.insert(kChannels[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys));
        Imf::StdOSStream os;
        {
            Imf::OutputFile file(os, header);
            file.setFrameBuffer(fb);
            file.writePixels(env.height);
        }
        bytes = os.str();
    } catch (const std::exception& e) {
        throw core::Error(name, 0, std::string("cannot encode EXR: ") + e.what());
    }
    core::writeFile(path, bytes);
}

EnvironmentMap makeDefaultSky(int width, int height) {
    EnvironmentMap env;
    env.width = width;
    env.height = height;
    env.rgb.resize(3 * static_cast<size_t>(width) * height);
    const glm::dvec3 zenith(0.20, 0.35, 0.85), horizon(0.85, 0.90, 1.00), ground(0.10, 0.08, 0.06);
    const glm::dvec3 sunColour(1.0, 0.85, 0.6);
    const double sunPeak = 30.0, sigma = 4.0 * std::numbers::pi / 180.0;
    const glm::dvec3 sun(latLongDirection(std::numbers::pi / 2 - 35.0 * std::numbers::pi / 180.0,
                                          30.0 * std::numbers::pi / 180.0));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const double theta = std::numbers::pi * (y + 0.5) / height,
                         phi = 2.0 * std::numbers::pi * (x + 0.5) / width;
            const glm::dvec3 w(latLongDirection(theta, phi));
            glm::dvec3 L;
            if (w.y > 0) {
                const double t = std::sqrt(w.y);
                L = horizon * (1.0 - t) + zenith * t;
            } else {
                L = ground;
            }
            const double a = std::acos(std::clamp(glm::dot(glm::normalize(w), sun), -1.0, 1.0));
            L += sunColour * (sunPeak * std::exp(-a * a / (2.0 * sigma * sigma)));
            const size_t i = 3 * (static_cast<size_t>(y) * width + x);
            for (int c = 0; c < 3; ++c)
                env.rgb[i + c] = static_cast<float>(L[c]);
        }
    return env;
}

void writeDefaultEnvironment(const std::filesystem::path& path) {
    writeEnvironment(path, makeDefaultSky());
}

std::vector<QuadratureNode> quadratureNodes(const EnvironmentMap& input, int sub, int maxWidth) {
    validateEnvironment(input, "environment");
    EnvironmentMap reduced;
    const EnvironmentMap* env = &input;
    while (env->width > maxWidth && env->width % 2 == 0 && env->height % 2 == 0) {
        reduced = halve(*env);
        env = &reduced;
    }
    std::vector<QuadratureNode> nodes;
    const int W = env->width, H = env->height;
    for (int y = 0; y < H; ++y) {
        const double mu0 = std::cos(std::numbers::pi * y / H),
                     mu1 = std::cos(std::numbers::pi * (y + 1) / H);
        for (int x = 0; x < W; ++x) {
            const glm::vec3 L = env->texel(x, y);
            if (L == glm::vec3(0.0f)) continue;
            for (int sy = 0; sy < sub; ++sy) {
                const double a = mu0 + (mu1 - mu0) * sy / sub,
                             b = mu0 + (mu1 - mu0) * (sy + 1) / sub;
                const double mu = 0.5 * (a + b);
                const double omega =
                    2.0 * std::numbers::pi / (static_cast<double>(W) * sub) * (a - b);
                for (int sx = 0; sx < sub; ++sx) {
                    const double phi = 2.0 * std::numbers::pi * (x + (sx + 0.5) / sub) / W;
                    const double s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
                    QuadratureNode n;
                    n.direction =
                        glm::vec3(static_cast<float>(s * std::cos(phi)), static_cast<float>(mu),
                                  static_cast<float>(s * std::sin(phi)));
                    n.weight = L * static_cast<float>(omega);
                    nodes.push_back(n);
                }
            }
        }
    }
    return nodes;
}

} // namespace irradiance
