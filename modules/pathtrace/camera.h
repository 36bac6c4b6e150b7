// pathtrace/camera: the camera, pixels, per-pixel tallies and the deterministic chunked runner
// shared by the lit-sphere and lit-mesh path tracers (sphere_tracer.h, mesh_tracer.h). The
// picture is the one of lit_sphere.h: orthographic camera along −z, image square
// [−extent, extent]² (x right, y up), pixel (0, 0) top left; pixel value = radiant exitance M
// at the pixel-centre ray's first surface point, 0 (variance 0) where that ray misses.
//   Estimator of a pixel (both tracers): N paths, each carrying power A_src/N (A_src: the area
//   over which light-plane entry points are sampled uniformly, irradiance 1 W/mm²). A path that
//   leaves the object at a camera-visible point xo with weight w adds w to the pixel that xo
//   projects into (at most one pixel, once: a path exits once). With A_pix the visible surface
//   area whose projection lies in the pixel (its footprint),
//       M_pix = (A_src / A_pix) · Σ_paths w / N,
//   variance of the mean (A_src/A_pix)² · (Σw²/N − (Σw/N)²)/(N − 1) from the per-path second
//   moments. A pixel whose centre ray misses is 0 (the power that lands in it is not shown).
//   Determinism: paths are traced in chunks of kImageChunkPaths (whatever the thread count),
//   channel c of path i uses the stream Pcg32::forPath(seed, c·2^56 + i), and the calling thread
//   adds the per-path records into the tally in path order, so the image is bitwise identical
//   for any thread count (as runSlab).
#pragma once

#include "pathtrace/lit_sphere.h"
#include "pathtrace/pathtrace.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pathtrace {

// Estimator settings of the image tracers (the slab tracer's defaults, see pathtrace.h).
struct TraceOptions {
    Termination termination;     // weight roulette and event limit, as the slab tracer
    int footprintSubsamples = 8; // mesh: k×k camera rays per pixel for the footprint areas
};
// Throws core::Error("trace options", 0, ...) naming the field.
void validate(const TraceOptions& o);
// Throws core::Error("lit sphere setup", 0, ...) naming the field: radius finite > 0, light
// direction finite and non-zero, 1 <= width, height <= 16384, 1 <= samplesPerPixel <= 10^7,
// threads >= 0.
void validate(const LitSphereSetup& s);
// The light direction of the setup, normalised (validate first).
std::array<double, 3> unitLight(const LitSphereSetup& s);

// Pixel geometry of the orthographic camera for an object of radius `radius` (the image
// spans ±1.1·radius; radius in mm for the sphere, normalised units for meshes).
struct OrthoCamera {
    int width = 0, height = 0;
    double extent = 0, dx = 0, dy = 0; // half side, pixel width and height
    OrthoCamera(const LitSphereSetup& s, double radius);
    double centreX(int i) const { return -extent + (i + 0.5) * dx; }
    double centreY(int j) const { return extent - (j + 0.5) * dy; }
    // Index j·width + i of the pixel containing (x, y), −1 outside the image.
    int pixelOf(double x, double y) const;
};

// Per pixel of a tracer's camera: footprint area A_pix (same units² as the source area; 0
// where the centre ray misses) and n·lightDir at the centre ray's surface point (0 on a miss).
struct PixelGeometry {
    std::vector<double> footprint;
    std::vector<float> cosLight;
};

constexpr int kChannels = 3;
constexpr uint64_t kImageChunkPaths = 4096;
// Stream index of channel c of path i.
constexpr uint64_t streamIndex(int c, uint64_t path) {
    return (static_cast<uint64_t>(c) << 56) | path;
}

// What one channel of one path did. Weights are per unit of source power per path (A_src/N).
// Per path: hit = specular + exited + absorbed + truncated + rouletteLoss + leaked (up to
// rounding).
struct ExitRecord {
    int32_t pixel = -1;      // pixel of a camera-visible exit in a covered pixel, else −1
    uint32_t events = 0;     // interactions
    double hit = 0;          // 1 when the entry ray hit the object
    double specular = 0;     // Fresnel reflectance at entry (not subsurface exitance)
    double exited = 0;       // weight that left the object (anywhere)
    double absorbed = 0;     // expected absorbed weight (implicit absorption)
    double rouletteLoss = 0; // weight removed minus weight added by roulettes (expectation 0)
    double leaked = 0;       // weight lost to a numerical leak through the surface (meshes)
    double truncated = 0;    // weight of a path truncated at the event limit
};

struct ChannelTally {
    std::vector<double> pixSum, pixSumSq; // Σw, Σw² per pixel
    double hitSum = 0, specSum = 0, specSumSq = 0, exitSum = 0, exitSumSq = 0;
    double absSum = 0, absSumSq = 0, rouletteSum = 0, rouletteSumSq = 0, leakSum = 0;
    double truncSum = 0, truncSumSq = 0;
    uint64_t events = 0, leaks = 0, truncatedPaths = 0;
};
struct ImageTally {
    uint64_t paths = 0;
    std::array<ChannelTally, kChannels> channel;
    explicit ImageTally(size_t pixels = 0);
    // Adds path `i` of a chunk whose records are laid out channel-major: rec[c·count + i].
    void add(const ExitRecord* rec, uint64_t count, uint64_t i);
};

// Per channel totals in W (irradiance 1 W/mm²): mean over paths × source power, with standard
// errors from the per-path second moments.
struct ChannelStats {
    double incident = 0, incidentStderr = 0; // power that hit the object
    double specular = 0, specularStderr = 0; // reflected at entry (excluded from the image)
    double exited = 0, exitedStderr = 0;     // left the object anywhere, visible or not
    double absorbed = 0, absorbedStderr = 0;
    double rouletteNet = 0, rouletteNetStderr = 0; // expected 0
    double truncated = 0, truncatedStderr = 0;     // truncated at the event limit: bias bound
    double leaked = 0;                             // numerical leaks (meshes), W
    uint64_t leaks = 0, events = 0, truncatedPaths = 0;
};
struct ImageStats {
    uint64_t paths = 0;        // paths per channel
    double seconds = 0;        // wall time of the trace
    double sourceAreaMm2 = 0;  // A_src (mm²): paths sample entry points uniformly on it
    double incidentPowerW = 0; // power on the object; sphere: πR², meshes: estimated
    std::array<ChannelStats, kChannels> channel;
    PixelGeometry pixels; // in mm² / unitless
};

// The energy check of one channel (as energyProblem(SlabResult) in pathtrace.h): empty when it
// holds, else a sentence: incident = specular + exited + absorbed + truncated + roulette +
// leaked off by more than 1e-6 relative, mean roulette change inconsistent with 0 (|z| >
// kEnergyZ), or truncated power above the standard error of the exited power.
std::string energyProblem(const ChannelStats& s);

// Traces paths [first, first + count) of every channel into out[c·count + i]; returns the
// number of paths traced (fewer than count only when `cancel` was set).
using ChunkTracer = std::function<uint64_t(uint64_t first, uint64_t count, ExitRecord* out,
                                           const std::atomic<bool>* cancel)>;
// Runs `paths` paths on `threads` workers (0: all hardware threads) in chunks of
// kImageChunkPaths merged in path order (bitwise the same tally for any thread count).
// progress(done) is called from the calling thread about every 50 ms; on cancel the tally
// holds the completed prefix of chunks.
ImageTally runImageChunks(uint64_t paths, int threads, size_t pixels, const ChunkTracer& trace,
                          const std::function<void(uint64_t done)>& progress,
                          const std::atomic<bool>* cancel);

// The image (see the estimator above) and the totals. `sourceArea` and the pixel footprints
// in the same units (mm² for the result's statistics: `areaToMm2` converts).
Image finalizeImage(const ImageTally& t, const PixelGeometry& px, int width, int height,
                    double sourceArea, double areaToMm2, ImageStats* stats);

} // namespace pathtrace
