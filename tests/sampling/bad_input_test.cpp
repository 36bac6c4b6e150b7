// Bad input to the radial distributions and the disk sampler: each is refused with a message
// that names the channel and, for a bad value, the radius; a profile whose energy does not
// converge within the table names the radius it reached.
#include "sampling_support.h"

#include "core/core.h"
#include "core/text.h"
#include "sampling/disk_sampling.h"
#include "sampling/gaussian_lobes.h"
#include "sampling/tabulated_radial.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

using namespace sampling;
using namespace samplingtest;

namespace {
#define EXPECT_HAS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << text
} // namespace

TEST(RadialBadInput, NanInfiniteNegativeValuesNameRadiusAndChannel) {
    Table t = dipoleTable(skin1(), 60.0, 256);
    auto withValue = [&](int k, int c, double v) {
        Table b = t;
        b.values[size_t(k)][c] = v;
        return errorOf([&] { tabulateChannels(b.radii, b.values, 1e-3, "skin.bssrdf"); });
    };
    const std::string nan = withValue(17, 1, std::nan(""));
    EXPECT_HAS(nan, "skin.bssrdf: channel 1: R(r) is NaN at r = ");
    EXPECT_HAS(nan, "(entry 17)");
    EXPECT_HAS(nan, core::formatNumber(t.radii[17], 6) + " mm");
    EXPECT_HAS(withValue(3, 2, std::numeric_limits<double>::infinity()),
               "channel 2: R(r) is infinite at r = ");
    const std::string neg = withValue(200, 0, -1e-9);
    EXPECT_HAS(neg, "channel 0: R(r) is negative (-1e-09) at r = ");
    EXPECT_HAS(neg, "(entry 200)");
}

TEST(RadialBadInput, ZeroEnergy) {
    const std::vector<double> r = profileGridRadii(10, 64), zero(64, 0.0);
    EXPECT_HAS(errorOf([&] { TabulatedRadial(r, zero, 1e-3, 2); }),
               "channel 2: the profile has no energy");
    EXPECT_HAS(errorOf([&] {
                   GaussianLobes({{0.0, 1.0}, {0.0, 2.0}}, 1e-3, 1);
               }),
               "channel 1: the profile has no energy (every weight is 0)");
}

TEST(RadialBadInput, EnergyThatDoesNotConvergeNamesTheRadiusReached) {
    // Skin1 red tabulated to 5 mm only: most of its energy lies beyond.
    const Table t = dipoleTable(skin1(), 5.0, 512);
    const std::string e = errorOf([&] { tabulateChannels(t.radii, t.values); });
    EXPECT_HAS(e, "channel 0: the energy does not converge within the tabulated range");
    EXPECT_HAS(e, "of it lies in the last 1 % of the radii (r > 4.95 mm)");
    EXPECT_HAS(e, "1 - eps of the energy is reached only at r = ");
    EXPECT_HAS(e, "mm of the table's 5 mm");
    // The same table converges for blue alone (R_m ~ 4 mm < 4.95 mm)...
    std::vector<double> blue;
    for (const auto& v : t.values)
        blue.push_back(v[2]);
    EXPECT_NO_THROW(TabulatedRadial(t.radii, blue, 1e-3, 2));
    // ... but not when eps asks for more of it.
    EXPECT_HAS(errorOf([&] { TabulatedRadial(t.radii, blue, 1e-6, 2); }),
               "channel 2: the energy does not converge");
    // A constant profile never decays.
    const std::vector<double> r = profileGridRadii(10, 64), one(64, 1.0);
    EXPECT_HAS(errorOf([&] { TabulatedRadial(r, one); }), "does not converge");
}

TEST(RadialBadInput, MalformedTables) {
    const std::vector<double> r = profileGridRadii(10, 8), v(8, 1.0);
    EXPECT_HAS(errorOf([&] { TabulatedRadial({0.0}, {1.0}); }), "at least 2 radii");
    EXPECT_HAS(errorOf([&] { TabulatedRadial(r, std::vector<double>(7, 1.0)); }),
               "radii and values differ in length (8 and 7)");
    EXPECT_HAS(errorOf([&] {
                   TabulatedRadial({0.5, 1.0}, {1.0, 0.0});
               }),
               "the first radius must be 0 (it is 0.5)");
    EXPECT_HAS(errorOf([&] {
                   TabulatedRadial({0.0, 1.0, 1.0}, {1.0, 0.5, 0.0});
               }),
               "radii must increase strictly (entry 2: 1 after 1)");
    EXPECT_HAS(errorOf([&] {
                   TabulatedRadial({0.0, std::nan("")}, {1.0, 0.0});
               }),
               "radius 1 is not finite");
    EXPECT_HAS(errorOf([&] { TabulatedRadial(r, v, 0.0); }), "eps must be in (0, 1) (it is 0)");
    EXPECT_HAS(errorOf([&] { TabulatedRadial(r, v, 1.0); }), "eps must be in (0, 1)");
}

TEST(RadialBadInput, BadLobes) {
    EXPECT_HAS(errorOf([] { GaussianLobes({}, 1e-3, 0); }), "channel 0: no lobes");
    EXPECT_HAS(errorOf([] {
                   GaussianLobes({{1, 1}, {std::nan(""), 1}}, 1e-3, 2);
               }),
               "channel 2: lobe 1: weight is NaN");
    EXPECT_HAS(errorOf([] { GaussianLobes({{-0.5, 1}}); }), "lobe 0: weight is negative (-0.5)");
    EXPECT_HAS(errorOf([] { GaussianLobes({{INFINITY, 1}}); }), "lobe 0: weight is infinite");
    EXPECT_HAS(errorOf([] {
                   GaussianLobes({{1, 0}});
               }),
               "lobe 0: variance must be finite and > 0 (it is 0)");
    EXPECT_HAS(errorOf([] { GaussianLobes({{1, -2}}); }), "variance must be finite and > 0");
    EXPECT_HAS(errorOf([] {
                   GaussianLobes({{1, std::nan("")}});
               }),
               "variance must be finite and > 0");
}

TEST(DiskSamplerBadInput, Probabilities) {
    const GaussianLobes g({{1, 1}});
    const std::array<const RadialDistribution*, 3> all{&g, &g, &g};
    EXPECT_HAS(errorOf([&] { DiskSampler(all, {0, 0, 0}); }), "axis probabilities sum to 0");
    EXPECT_HAS(errorOf([&] {
                   DiskSampler(all, {1, -1, 0});
               }),
               "axis probabilities must be finite and >= 0");
    EXPECT_HAS(errorOf([&] {
                   DiskSampler(all, {1, 0, 0}, {std::nan(""), 1, 1});
               }),
               "channel probabilities must be finite and >= 0");
    EXPECT_HAS(errorOf([&] {
                   DiskSampler({&g, nullptr, &g}, AxisScheme::Uniform);
               }),
               "channel 1 has a probability > 0 but no distribution");
    EXPECT_NO_THROW(DiskSampler({&g, nullptr, nullptr}, {1, 1, 1}, {1, 0, 0}));
}

#undef EXPECT_HAS // (a unity build puts the next file in the same translation unit)
