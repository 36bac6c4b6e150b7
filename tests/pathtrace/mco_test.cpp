// MCML .mco files (pathtrace/mco.h): MCML's own sample outputs are read with their numbers and
// written again byte for byte; the two independent runs of MCML's sample agree within the
// spread their difference implies and conserve energy as MCML states it; our slab reference
// goes through an .mco and back; bad files are refused naming the line.
#include "core/core.h"
#include "pathtrace/mco.h"
#include "pathtrace/pathtrace.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace fs = std::filesystem;

namespace {

fs::path data(const char* name) {
    return fs::path(BW_SOURCE_ROOT) / "tests/data/mcml" / name;
}

} // namespace

TEST(Mco, ReadsMcmlsSampleAndWritesItAgainByteForByte) {
    for (const char* name : {"sample_lhvwang.mco", "sample_kaseykwong.mco", "mc-lost-v1-0.mco"}) {
        SCOPED_TRACE(name);
        const std::string text = core::readFile(data(name));
        const pathtrace::McoFile m = pathtrace::parseMco(text, name);
        EXPECT_EQ(pathtrace::formatMco(m), text);
    }
    const pathtrace::McoFile m = pathtrace::readMco(data("sample_lhvwang.mco"));
    EXPECT_EQ(m.photons, 1000000);
    EXPECT_EQ(m.nz, 40);
    EXPECT_EQ(m.nr, 50);
    EXPECT_EQ(m.na, 1);
    EXPECT_DOUBLE_EQ(m.dr, 0.01);
    ASSERT_EQ(m.layers.size(), 3u);
    EXPECT_DOUBLE_EQ(m.layers[0].mus, 100);
    EXPECT_DOUBLE_EQ(m.layers[2].d, 0.2);
    EXPECT_DOUBLE_EQ(m.specular, 0.0243729);
    EXPECT_DOUBLE_EQ(m.diffuse, 0.237544);
    EXPECT_EQ(m.aRz.size(), 2000u);
    EXPECT_DOUBLE_EQ(m.aZ[0], 2.7990);
}

// MCML's own accounting: R_sp + R_d + A + T = 1, and its Rd_r integrates to R_d over the rings
// 2π (ir + ½) dr² (to the four digits Rd_r is printed with). Two independent runs of the same
// input share R_sp (Fresnel) but not R_d (Monte Carlo), and their mean comes with the standard
// error |a − b|/2, small against R_d.
TEST(Mco, TheTwoRunsOfMcmlsSampleAreConsistent) {
    const pathtrace::McoFile a = pathtrace::readMco(data("sample_lhvwang.mco"));
    const pathtrace::McoFile b = pathtrace::readMco(data("sample_kaseykwong.mco"));
    for (const pathtrace::McoFile* m : {&a, &b}) {
        EXPECT_NEAR(m->specular + m->diffuse + m->absorbed + m->transmittance, 1.0, 1e-5);
        double sum = 0;
        for (int i = 0; i < m->nr; ++i)
            sum += m->rdR[size_t(i)] * 2 * 3.1415926 * (i + 0.5) * m->dr * m->dr;
        EXPECT_NEAR(sum, m->diffuse, 1e-4 * m->diffuse);
    }
    EXPECT_EQ(a.specular, b.specular); // Fresnel, not Monte Carlo
    EXPECT_NE(a.diffuse, b.diffuse);   // two runs
    const pathtrace::SlabResult r = pathtrace::slabFromMco(a, &b);
    ASSERT_EQ(r.rd.size(), 49u);       // the overflow bin left out
    EXPECT_DOUBLE_EQ(r.rMid[0], 0.05); // (0 + ½) 0.01 cm in mm
    EXPECT_DOUBLE_EQ(r.rd[0], 0.5 * (a.rdR[0] + b.rdR[0]) / 100);
    EXPECT_GT(r.totalRdStderr, 0.0);
    EXPECT_LT(r.totalRdStderr, 0.01 * r.totalRd);
}

// Our slab reference as an .mco and back: the same R_d(r) (to the printed four digits), the
// medium in MCML's units, and MCML's energy identity holds in the file we write (up to the
// roulette's change, which is 0 in expectation).
TEST(Mco, TheSlabReferenceGoesThroughAnMcoAndBack) {
    const pathtrace::Medium med{0.01, 1.0, 0.0, 1.3};
    pathtrace::SlabSettings s;
    s.rMaxMm = 20;
    s.bins = 40;
    s.paths = 20000;
    const pathtrace::SlabResult r = pathtrace::runSlab(med, s);
    const pathtrace::McoFile m = pathtrace::mcoFromSlab(med, s, r, "slab.mco");
    const std::string text = pathtrace::formatMco(m);
    const pathtrace::McoFile back = pathtrace::parseMco(text, "slab.mco");
    EXPECT_EQ(pathtrace::formatMco(back), text);
    EXPECT_DOUBLE_EQ(back.layers[0].mua, 0.1);
    EXPECT_DOUBLE_EQ(back.layers[0].mus, 10);
    EXPECT_DOUBLE_EQ(back.layers[0].n, 1.3);
    EXPECT_DOUBLE_EQ(back.dr, 0.05);
    // our accounting adds the roulette's change (0 in expectation) to MCML's four terms
    EXPECT_NEAR(back.specular + back.diffuse + back.absorbed + back.transmittance, 1.0,
                5 * std::hypot(r.rouletteNetStderr, r.truncated) + 1e-5);
    const pathtrace::Medium again = pathtrace::mediumOfMco(back, "slab.mco");
    EXPECT_DOUBLE_EQ(again.sigmaA, 0.01);
    EXPECT_DOUBLE_EQ(again.eta, 1.3);
    const pathtrace::SlabResult from = pathtrace::slabFromMco(back);
    ASSERT_EQ(from.rd.size(), r.rd.size() - 1);
    for (size_t i = 0; i < from.rd.size(); ++i) {
        EXPECT_NEAR(from.rd[i], r.rd[i], 1e-4 * r.rd[i] + 1e-12) << "bin " << i;
        EXPECT_DOUBLE_EQ(from.rMid[i], r.rMid[i]);
    }
}

TEST(Mco, BadFilesNameTheLine) {
    const std::string good = core::readFile(data("sample_kaseykwong.mco"));
    auto fails = [&](std::string text, int line, const std::string& part) {
        try {
            pathtrace::parseMco(text, "bad.mco");
            ADD_FAILURE() << "accepted: " << part;
        } catch (const core::Error& e) {
            EXPECT_EQ(e.line(), line) << e.what();
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
        }
    };
    fails("hello\n", 1, "not an MCML output file");
    std::string t = good;
    t.replace(t.find("1000000 "), 7, "1e6x000");
    fails(t, 14, "photons: '1e6x000' is not a number");
    t = good;
    t.replace(t.find("1.37\t1\t100\t0.9\t0.1"), 18, "1.37\t1\t100");
    fails(t, 21, "layer 1 (n mua mus g d): expected 5 numbers, found 3");
    t = good;
    const size_t rd = t.find("Rd_r #");
    t.replace(t.find("\n", t.find("\n", rd) + 1) + 1, 12, "  nope      ");
    fails(t, 81, "Rd_r value 2 of 50: 'nope' is not a number");
    t = good;
    t.erase(t.find("Tt_ra\n"));
    fails(t, 0, "no section 'Tt_ra'");
    // not a semi-infinite single layer: refused as a reference, naming the file
    const pathtrace::McoFile m = pathtrace::parseMco(good, "sample.mco");
    try {
        pathtrace::mediumOfMco(m, "sample.mco");
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("sample.mco: a reference profile needs one layer"),
                  std::string::npos)
            << e.what();
    }
}
