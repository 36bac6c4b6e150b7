// The bisection of thesis 3.4 on the CPU with a closed-form R_dr (thesis eq. 3.2), evaluated
// in float32 at the grid points exactly as a GPU would see them.
#include "core/core.h"
#include "material/material.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {
double classicRdr(double alphaPrime, double eta) { // thesis eq. (3.2), Jensen & Buhler 2002
    double fdr = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
    double A = (1 + fdr) / (1 - fdr);
    double t = std::sqrt(3 * (1 - alphaPrime));
    return alphaPrime * 0.5 * (1 + std::exp(-4.0 / 3.0 * A * t)) * std::exp(-t);
}
material::RdrBatch floatBatch(double eta, int* calls = nullptr) {
    return [eta, calls](const std::vector<glm::dvec3>& a) {
        if (calls) ++*calls;
        std::vector<glm::dvec3> r(a.size());
        for (size_t i = 0; i < a.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                float af = static_cast<float>(a[i][c]);
                EXPECT_EQ(double(af), a[i][c]) << "grid points must be exact floats";
                r[i][c] = static_cast<float>(classicRdr(af, eta));
            }
        return r;
    };
}
} // namespace

TEST(Inversion, RecoversAlphaPrimeAcrossTheRange) {
    int calls = 0;
    for (double a : {0.05, 0.3, 0.8, 0.99, 0.9999, 0.999973}) {
        glm::dvec3 alpha(a, a * 0.5, std::sqrt(a));
        glm::dvec3 target;
        for (int c = 0; c < 3; ++c)
            target[c] = classicRdr(alpha[c], 1.3);
        glm::dvec3 got = material::solveAlphaPrime(target, floatBatch(1.3, &calls));
        for (int c = 0; c < 3; ++c) {
            // relative accuracy in 1 − α′ is what σa inherits (eq. 3.5)
            EXPECT_NEAR((1 - got[c]) / (1 - alpha[c]), 1.0, 2e-5) << "alpha' " << alpha[c];
        }
    }
    EXPECT_EQ(calls, 6 * 3); // 3 rounds per solve, as in the thesis
}

TEST(Inversion, OutOfRangeTargetsAreClearErrors) {
    try {
        material::solveAlphaPrime({0.5, 1.2, 0.5}, floatBatch(1.3));
        FAIL();
    } catch (const core::Error& e) {
        std::string m = e.what();
        EXPECT_NE(m.find("outside the invertible range"), std::string::npos) << m;
        EXPECT_NE(m.find("channel G"), std::string::npos) << m;
    }
    EXPECT_THROW(material::solveAlphaPrime({-0.1, 0.5, 0.5}, floatBatch(1.3)), core::Error);
    EXPECT_THROW(material::solveAlphaPrime({NAN, 0.5, 0.5}, floatBatch(1.3)), core::Error);
}

TEST(Inversion, SigmaFromAlphaPrimeFollowsEqs33To35) {
    glm::dvec3 a(0.9, 0.99, 0.5), ld(2.0, 5.0, 0.5);
    auto s = material::sigmaFromAlphaPrime(a, ld, 0.3);
    for (int c = 0; c < 3; ++c) {
        double spt = 1.0 / (ld[c] * std::sqrt(3 * (1 - a[c])));
        EXPECT_NEAR(s.sigmaA[c], spt * (1 - a[c]), 1e-14 * spt);
        EXPECT_NEAR(s.sigmaS[c], a[c] * spt / 0.7, 1e-14 * spt);
        // round trip to l_d through the classical σtr = √(3 σa σ′t)
        double sigmaTr = std::sqrt(3 * s.sigmaA[c] * (s.sigmaA[c] + s.sigmaS[c] * 0.7));
        EXPECT_NEAR(1.0 / sigmaTr, ld[c], 1e-12 * ld[c]);
    }
    EXPECT_THROW(material::sigmaFromAlphaPrime({1.0, 0.5, 0.5}, ld, 0.0), core::Error);
    EXPECT_THROW(material::sigmaFromAlphaPrime(a, {1.0, -1.0, 1.0}, 0.0), core::Error);
    EXPECT_THROW(material::sigmaFromAlphaPrime(a, ld, 1.0), core::Error);
}
