// Phase functions: normalisation, peak direction, the 2002 sign convention, stability.
#include <cmath>

#include <gtest/gtest.h>

#include "aerial/phase.hpp"

namespace {

using aerial::kPi;

/// Integral over the sphere of a phase function of cos_theta: 2 pi * integral over mu in [-1, 1],
/// composite Gauss–Legendre (5 points) on many intervals clustered towards mu = 1 where sharp
/// forward lobes live.
template <class F>
double integrate_over_sphere(F phase) {
    const double nodes[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                             0.9061798459386640};
    const double weights[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                               0.4786286704993665, 0.2369268850561891};
    // Substitution mu = 1 - 2 w(u), w = u^4 / (u^4 + (1-u)^4), puts most samples near both
    // ends, where the forward (g > 0) or backward (g < 0) lobes live.
    const int intervals = 4000;
    double sum = 0.0;
    for (int i = 0; i < intervals; ++i) {
        const double a = double(i) / intervals, b = double(i + 1) / intervals;
        for (int j = 0; j < 5; ++j) {
            const double u = 0.5 * (a + b) + 0.5 * (b - a) * nodes[j];
            const double p = u * u * u * u, q = (1 - u) * (1 - u) * (1 - u) * (1 - u);
            const double mu = 1.0 - 2.0 * p / (p + q);
            const double dw_du =
                4.0 * u * u * u * (1 - u) * (1 - u) * (1 - u) / ((p + q) * (p + q));
            sum += weights[j] * 0.5 * (b - a) * phase(mu) * 2.0 * dw_du;
        }
    }
    return 2.0 * kPi * sum;
}

constexpr double kNormalisationTolerance = 1e-6;

TEST(PhaseFunction, RayleighIntegratesToOne) {
    EXPECT_NEAR(integrate_over_sphere([](double mu) { return aerial::rayleigh_phase(mu); }), 1.0,
                kNormalisationTolerance);
}

TEST(PhaseFunction, HenyeyGreensteinIntegratesToOneForEveryG) {
    for (double g : {-0.99, -0.8, -0.3, 0.0, 0.3, 0.76, 0.8, 0.9, 0.95, 0.99}) {
        const double integral = integrate_over_sphere(
            [g](double mu) { return aerial::henyey_greenstein_phase(mu, g); });
        EXPECT_NEAR(integral, 1.0, kNormalisationTolerance) << "g = " << g;
    }
}

TEST(PhaseFunction, CornetteShanksIntegratesToOneForEveryG) {
    for (double g : {-0.9, 0.0, 0.5, 0.8, 0.95, 0.99}) {
        const double integral =
            integrate_over_sphere([g](double mu) { return aerial::cornette_shanks_phase(mu, g); });
        EXPECT_NEAR(integral, 1.0, kNormalisationTolerance) << "g = " << g;
    }
}

TEST(PhaseFunction, HenyeyGreensteinPeaksTowardsTheSunForPositiveG) {
    for (double g : {0.1, 0.5, 0.8, 0.99}) {
        const double towards = aerial::henyey_greenstein_phase(1.0, g);
        const double away = aerial::henyey_greenstein_phase(-1.0, g);
        EXPECT_GT(towards, away) << "g = " << g << ": forward scattering must be brighter";
        // Strictly decreasing from cos = 1 to cos = -1.
        double previous = towards;
        for (double mu = 0.99; mu >= -1.0; mu -= 0.01) {
            const double p = aerial::henyey_greenstein_phase(mu, g);
            EXPECT_LT(p, previous) << "g = " << g << ", cos_theta = " << mu;
            previous = p;
        }
    }
}

TEST(PhaseFunction, HenyeyGreensteinZeroGIsIsotropic) {
    for (double mu : {-1.0, -0.3, 0.0, 0.7, 1.0}) {
        EXPECT_DOUBLE_EQ(aerial::henyey_greenstein_phase(mu, 0.0), 1.0 / (4.0 * kPi));
    }
}

TEST(PhaseFunction, RayleighIsSymmetricAndSmallestSideways) {
    EXPECT_DOUBLE_EQ(aerial::rayleigh_phase(0.6), aerial::rayleigh_phase(-0.6));
    EXPECT_LT(aerial::rayleigh_phase(0.0), aerial::rayleigh_phase(0.5));
    EXPECT_DOUBLE_EQ(aerial::rayleigh_phase(1.0), 2.0 * aerial::rayleigh_phase(0.0));
}

TEST(PhaseFunction, SlidesGMapsToOurConventionWithTheSamePeak) {
    // The 2002 slides: negative g scatters forwards. Their -0.75 is our 0.75, peaking at the sun.
    const double g = aerial::mie_g_from_2002_slides(-0.75);
    EXPECT_DOUBLE_EQ(g, 0.75);
    EXPECT_GT(aerial::henyey_greenstein_phase(1.0, g), aerial::henyey_greenstein_phase(-1.0, g));
}

TEST(PhaseFunction, SlidesNumeratorOneMinusGSquaredIsNotNormalised) {
    // The slides print (1-g)^2 where the normalised form has (1-g^2): document why we differ.
    const double g = 0.8;
    const double misprinted = integrate_over_sphere([g](double mu) {
        return aerial::henyey_greenstein_phase(mu, g) * (1.0 - g) * (1.0 - g) / (1.0 - g * g);
    });
    EXPECT_NEAR(misprinted, (1.0 - g) / (1.0 + g), 1e-6);
    EXPECT_GT(std::abs(misprinted - 1.0), 0.5);
}

TEST(PhaseFunction, FiniteAndPositiveNearTheLimitsInFloat) {
    for (float g : {-0.999f, -0.9f, 0.0f, 0.9f, 0.999f, 0.9999f}) {
        for (float mu : {-1.0f, -0.5f, 0.0f, 0.999999f, 1.0f, 1.0000001f, -1.0000001f}) {
            const float hg = aerial::henyey_greenstein_phase(mu, g);
            const float cs = aerial::cornette_shanks_phase(mu, g);
            EXPECT_TRUE(std::isfinite(hg) && hg > 0.0f) << "HG g=" << g << " mu=" << mu;
            EXPECT_TRUE(std::isfinite(cs) && cs > 0.0f) << "CS g=" << g << " mu=" << mu;
        }
    }
    // At |g| = 0.999 the peak is (1+|g|)/(4 pi (1-|g|)^2) = 1.59e5 /sr, forwards for g > 0 and
    // backwards for g < 0: float must get both (the naive 1 + g^2 - 2 g cos cancels).
    for (float g : {0.999f, -0.999f}) {
        const float peak = aerial::henyey_greenstein_phase(g > 0 ? 1.0f : -1.0f, g);
        const double exact = aerial::henyey_greenstein_phase(g > 0 ? 1.0 : -1.0, double(g));
        EXPECT_NEAR(peak, exact, 1e-4 * exact) << "g = " << g;
    }
}

}  // namespace
