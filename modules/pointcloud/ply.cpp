// Point-cloud cache: binary little-endian PLY (x y z nx ny nz area as float32, the triangle as
// uint32, total area in a comment printed with %.17g so it round-trips exactly), strict header
// validation, and the cache key (FNV-1a 64 via core::hashHex over the mesh bytes, the parameters
// and the cache format).
#include "pointcloud/pointcloud.h"

#include "core/core.h"
#include "core/text.h"

#include <bit>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>

namespace pointcloud {

static_assert(std::endian::native == std::endian::little, "PLY I/O assumes a little-endian host");

namespace {
const char* const kProps[7] = {"x", "y", "z", "nx", "ny", "nz", "area"};
// The optional eighth property: the triangle each point lies on (written always, so a cloud read
// back is the cloud written; a file without it, e.g. from another program, reads kNoTriangle).
const char* const kTriangleProp = "triangle";
} // namespace

void writePly(const std::filesystem::path& path, const PointCloud& cloud) {
    std::string out = "ply\nformat binary_little_endian 1.0\ncomment bw_pointcloud\n";
    out += "comment total_area " + core::formatNumber(cloud.totalArea, 17) + "\n";
    out += "element vertex " + std::to_string(cloud.points.size()) + "\n";
    for (const char* p : kProps)
        out += std::string("property float ") + p + "\n";
    out += std::string("property uint ") + kTriangleProp + "\n";
    out += "end_header\n";
    size_t header = out.size();
    out.resize(header + cloud.points.size() * (7 * sizeof(float) + sizeof(uint32_t)));
    char* dst = out.data() + header;
    for (const Point& p : cloud.points) {
        float v[7] = {p.p[0], p.p[1], p.p[2], p.n[0], p.n[1], p.n[2], p.area};
        std::memcpy(dst, v, sizeof v);
        dst += sizeof v;
        std::memcpy(dst, &p.triangle, sizeof p.triangle);
        dst += sizeof p.triangle;
    }
    core::writeFile(path, out);
}

PointCloud readPly(const std::filesystem::path& path) {
    const std::string name = path.string();
    const std::string bytes = core::readFile(path);
    auto fail = [&](const std::string& msg) { throw core::Error(name, 0, "PLY: " + msg); };
    size_t pos = 0;
    auto nextLine = [&](std::string& line) {
        size_t eol = bytes.find('\n', pos);
        if (eol == std::string::npos) fail("header not terminated by end_header");
        line = bytes.substr(pos, eol - pos);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        pos = eol + 1;
    };
    std::string line;
    if (bytes.compare(0, 4, "ply\n") != 0 && bytes.compare(0, 5, "ply\r\n") != 0)
        fail("not a PLY file (missing 'ply' magic)");
    nextLine(line);
    nextLine(line);
    if (line != "format binary_little_endian 1.0")
        fail("unsupported format line '" + line + "' (expected binary_little_endian 1.0)");
    bool haveTotal = false, haveElement = false;
    double total = 0;
    uint64_t count = 0;
    int prop = 0;
    bool haveTriangle = false;
    for (;;) {
        nextLine(line);
        if (line == "end_header") break;
        std::istringstream ss(line);
        std::string word;
        ss >> word;
        if (word == "comment") {
            std::string key;
            ss >> key;
            if (key == "total_area") {
                std::string v;
                ss >> v;
                char* endp = nullptr;
                total = std::strtod(v.c_str(), &endp);
                if (v.empty() || *endp != '\0' || !(total >= 0))
                    fail("bad total_area comment '" + line + "'");
                haveTotal = true;
            }
        } else if (word == "element") {
            std::string what, num;
            ss >> what >> num;
            if (haveElement || what != "vertex") fail("unexpected element line '" + line + "'");
            char* endp = nullptr;
            count = std::strtoull(num.c_str(), &endp, 10);
            if (num.empty() || *endp != '\0' || num[0] == '-')
                fail("bad vertex count in '" + line + "'");
            haveElement = true;
        } else if (word == "property") {
            std::string type, pname, extra;
            ss >> type >> pname >> extra;
            if (haveElement && prop == 7 && !haveTriangle && type == "uint" &&
                pname == kTriangleProp && extra.empty()) {
                haveTriangle = true;
                continue;
            }
            if (!haveElement || prop >= 7 || type != "float" || pname != kProps[prop] ||
                !extra.empty())
                fail("unexpected property line '" + line + "' (expected 'property float " +
                     std::string(prop < 7 ? kProps[prop] : "<none>") + "')");
            ++prop;
        } else {
            fail("unexpected header line '" + line + "'");
        }
    }
    if (!haveElement) fail("no 'element vertex' line");
    if (prop != 7) fail("expected 7 float properties x y z nx ny nz area");
    const uint64_t stride = 7 * sizeof(float) + (haveTriangle ? sizeof(uint32_t) : 0);
    const uint64_t avail = bytes.size() - pos;
    if (count > avail / stride || avail != count * stride)
        fail("data size " + std::to_string(avail) + " bytes does not match " +
             std::to_string(count) + " vertices of " + std::to_string(stride) + " bytes");
    PointCloud cloud;
    cloud.points.resize(size_t(count));
    const char* src = bytes.data() + pos;
    double sum = 0;
    for (Point& p : cloud.points) {
        float v[7];
        std::memcpy(v, src, sizeof v);
        src += sizeof v;
        for (int k = 0; k < 3; ++k)
            p.p[k] = v[k], p.n[k] = v[3 + k];
        p.area = v[6];
        p.triangle = kNoTriangle;
        if (haveTriangle) {
            std::memcpy(&p.triangle, src, sizeof p.triangle);
            src += sizeof p.triangle;
        }
        sum += v[6];
    }
    cloud.totalArea = haveTotal ? total : sum;
    return cloud;
}

std::string cacheKey(const mesh::Mesh& m, size_t n, const std::string& method, uint64_t seed) {
    std::string bytes;
    bytes.append(reinterpret_cast<const char*>(m.vertices.data()),
                 m.vertices.size() * sizeof(m.vertices[0]));
    bytes.append(reinterpret_cast<const char*>(m.triangles.data()),
                 m.triangles.size() * sizeof(m.triangles[0]));
    for (const std::string& part :
         {std::to_string(n), method, std::to_string(seed), std::string(kCacheFormat)}) {
        bytes.push_back('|');
        bytes.append(part);
    }
    std::string h = core::hashHex(bytes);
    size_t colon = h.find(':');
    return colon == std::string::npos ? h : h.substr(colon + 1);
}

} // namespace pointcloud
