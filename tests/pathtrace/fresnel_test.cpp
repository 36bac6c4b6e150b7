// pathtrace/fresnel.h: known values (normal incidence, Brewster's angle, grazing incidence,
// η = 1), total internal reflection past the critical angle, R + T = 1 per polarisation,
// reciprocity (the same reflectance seen from both sides of the interface).
#include "pathtrace/fresnel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace pathtrace;

TEST(Fresnel, NormalIncidence) {
    for (double eta : {1.3, 1.5, 1.0 / 1.3, 2.4}) {
        const double r = (eta - 1) / (eta + 1);
        EXPECT_NEAR(fresnelDielectric(1.0, eta), r * r, 1e-16) << eta;
    }
    EXPECT_NEAR(fresnelDielectric(1.0, 1.5), 0.04, 1e-16);
}

TEST(Fresnel, IndexMatchedReflectsNothing) {
    for (double c : {1.0, 0.7, 0.2, 1e-6})
        EXPECT_EQ(fresnelDielectric(c, 1.0), 0.0);
}

TEST(Fresnel, BrewsterAngleKillsP) {
    const double eta = 1.5, thetaB = std::atan(eta);
    const auto f = fresnelTerms(std::cos(thetaB), eta);
    EXPECT_NEAR(f.rp, 0.0, 1e-15);
    EXPECT_NEAR(fresnelDielectric(std::cos(thetaB), eta), 0.5 * f.rs, 1e-15);
    // A textbook value: glass (1.5) at 45°: Rs = 0.0920, Rp = 0.0085 (4 digits).
    const auto g = fresnelTerms(std::cos(std::numbers::pi / 4), 1.5);
    EXPECT_NEAR(g.rs, 0.0920, 5e-5);
    EXPECT_NEAR(g.rp, 0.0085, 5e-5);
}

TEST(Fresnel, TotalInternalReflectionPastCriticalAngle) {
    const double eta = 1.0 / 1.3; // leaving a medium of index 1.3
    const double cosCrit = std::sqrt(1 - eta * eta);
    EXPECT_EQ(fresnelDielectric(cosCrit * 0.999, eta), 1.0);
    EXPECT_EQ(fresnelDielectric(0.01, eta), 1.0);
    EXPECT_TRUE(fresnelTerms(cosCrit * 0.999, eta).tir);
    EXPECT_LT(fresnelDielectric(cosCrit * 1.001, eta), 1.0);
    EXPECT_GT(fresnelDielectric(cosCrit * 1.0001, eta), 0.9); // continuous towards 1
}

TEST(Fresnel, GrazingIncidenceReflectsAll) {
    EXPECT_NEAR(fresnelDielectric(1e-9, 1.5), 1.0, 1e-8);
}

TEST(Fresnel, EnergyConservedPerPolarisation) {
    for (double eta : {1.3, 1.0 / 1.3, 1.5, 1.0 / 1.5, 3.0})
        for (int i = 1; i <= 200; ++i) {
            const double c = i / 200.0;
            const auto f = fresnelTerms(c, eta);
            if (f.tir) {
                EXPECT_EQ(fresnelDielectric(c, eta), 1.0);
                continue;
            }
            EXPECT_NEAR(f.rs + f.ts, 1.0, 1e-14) << eta << " " << c;
            EXPECT_NEAR(f.rp + f.tp, 1.0, 1e-14) << eta << " " << c;
            EXPECT_NEAR(fresnelDielectric(c, eta), 0.5 * (f.rs + f.rp), 1e-15);
        }
}

TEST(Fresnel, ReciprocityOfThePolarisedAverage) {
    // R(θ_i; n_i → n_t) = R(θ_t; n_t → n_i), per polarisation and hence on average.
    for (double eta : {1.3, 1.5, 1.0 / 1.3})
        for (int i = 1; i <= 100; ++i) {
            const double c = i / 100.0;
            const auto f = fresnelTerms(c, eta);
            if (f.tir) continue;
            const auto b = fresnelTerms(f.cosT, 1.0 / eta);
            ASSERT_FALSE(b.tir);
            EXPECT_NEAR(b.cosT, c, 1e-12);
            EXPECT_NEAR(f.rs, b.rs, 1e-13);
            EXPECT_NEAR(f.rp, b.rp, 1e-13);
            EXPECT_NEAR(fresnelDielectric(c, eta), fresnelDielectric(f.cosT, 1.0 / eta), 1e-13);
        }
}
