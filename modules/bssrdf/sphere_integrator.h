// bssrdf sphere integrator: the BSSRDF-integrated lit sphere of thesis 3.5 / 3.6.2 as a
// progressive GPU pass (shaders/sphere_bssrdf.comp, a model consumer template).
//   Setup and pixel value are those of litsphere/litsphere.h: sphere of radius R (mm) at the
//   origin, directional light, orthographic camera along −z, extent 1.1·R; pixel value is the
//   radiant exitance
//     M(xo) = ∫_A Bssrdf(xi, wi, xo, wo) · Ft(η, cos θi) · max(0, n(xi)·lightDir) dA(xi),
//   wi = lightDir, wo = n(xo), at the pixel-centre ray's hit point xo, estimated by uniform area
//   sampling (pdf 1/(4πR²)); Ft is the exact unpolarised Fresnel transmittance into the medium.
//   Accumulation: every dispatch writes per pixel the float Σf and Σf² (Kahan-compensated) of
//   its ≤ kMaxSamplesPerDispatch samples; step() reads them back and adds them into double
//   sums on the host, so precision does not degrade however many samples are taken.
//   Random numbers are counter-based per (seed, pixel, sample index) (see the shader), so the
//   samples drawn depend only on (setup, seed, samples done); the image is bitwise a function
//   of (setup, model, uniforms, seed, sequence of step() sizes) on one device and driver, and
//   different splittings of the same sample count agree to float rounding.
//   Needs the same current OpenGL 4.5 context on the calling thread for every call.
//   The app must list "sphere_bssrdf.comp" among the ModelLibrary consumers to get the program.
#pragma once

#include "bssrdf/program.h"
#include "gl/gl.h"
#include "litsphere/litsphere.h"

#include <cstdint>
#include <vector>

namespace bssrdf {

class SphereIntegrator {
  public:
    // Samples per pixel in one dispatch (bounds its length and stays well below llvmpipe's
    // 65535 loop iterations per invocation); step() splits larger requests.
    static constexpr int kMaxSamplesPerDispatch = 4096;

    // Validates the setup (core::Error naming the field: radius > 0, 1 <= width, height <=
    // 8192, a non-zero light direction) and starts over with empty sums. `samplesPerPixel`
    // and `threads` of the setup are not used here (step() says how many samples to take).
    void reset(const litsphere::Setup& setup);
    // Takes `samplesPerPixel` more samples per pixel with `program` (from
    // buildModelProgram(model, "sphere_bssrdf.comp", sources)) and the model's current
    // uniforms; blocks until they are summed. Does nothing for samplesPerPixel <= 0 or before
    // reset(). The caller resets when the model, its values, the builtins or the program change.
    void step(GLuint program, const Model& m, const ParamValues& values, const Builtins& b,
              int samplesPerPixel);
    // Per pixel mean Σf/n and variance of the mean (Σf²/n − mean²)/(n − 1), n = samples per
    // pixel (variance 0 when n < 2 and the sums are 0, +inf when n < 2 otherwise); `samples`
    // is n · width · height.
    litsphere::Image image() const;
    uint64_t samplesPerPixelDone() const { return m_samples; }
    const litsphere::Setup& setup() const { return m_setup; }
    double seconds() const { return m_seconds; } // wall time spent in step() since reset

  private:
    litsphere::Setup m_setup;
    double m_lightDir[3] = {0.0, 0.0, 1.0}; // normalised
    gl::Buffer m_sums;                      // 2 vec4 per pixel: Σf, Σf² of the last dispatch
    std::vector<float> m_readback;
    std::vector<double> m_sum, m_sumSq; // 3 per pixel
    uint64_t m_samples = 0;
    // samples per dispatch: halved while the driver's loop limit cuts dispatches short (a model
    // with loops of its own), kept for the next steps
    int m_samplesPerDispatch = kMaxSamplesPerDispatch;
    double m_seconds = 0;
};

} // namespace bssrdf
