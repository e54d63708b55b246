// The three models: invariants, closed forms, the bridge between the reference integrator and
// the 2002 closed form, the analytic zenith transmittance, the Chapman approximation.
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <glm/exponential.hpp>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"

namespace {

using aerial::Atmosphere;
using aerial::Model;
using aerial::View;
using glm::dvec3;

View view_at(dvec3 eye, dvec3 sun) {
    View v;
    v.eye = eye;
    v.sun_dir = glm::normalize(sun);
    return v;
}

aerial::Scattering<double> eval(Model m, const View& v, dvec3 p, const Atmosphere& a = {}) {
    const auto r = aerial::evaluate(a, v, m, p);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? *r : aerial::Scattering<double>{};
}

std::string name(Model m) { return std::string(aerial::model_name(m)); }

TEST(Models, NamesRoundTripAndUnknownNamesAreListed) {
    for (Model m : aerial::all_models()) EXPECT_EQ(*aerial::parse_model(aerial::model_name(m)), m);
    const auto bad = aerial::parse_model("preetham");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find(
                  "expected one of hoffman-preetham, height, single-scattering, reference, got "
                  "'preetham'"),
              std::string::npos)
        << bad.error().message;
}

TEST(Models, ZeroDistanceHasNoExtinctionAndNoInScattering) {
    const View v = view_at({10, 20, 300}, {0, 0.6, 0.8});
    for (Model m : aerial::all_models()) {
        const auto s = eval(m, v, v.eye);
        EXPECT_EQ(s.extinction, dvec3(1.0)) << name(m);
        EXPECT_EQ(s.in_scattering, dvec3(0.0)) << name(m);
    }
}

TEST(Models, ExtinctionFallsAndInScatteringGrowsWithDistance) {
    const View v = view_at({0, 0, 50}, {0.3, 0.5, 0.6});
    for (Model m : aerial::all_models()) {
        auto previous = eval(m, v, v.eye);
        for (double d = 100.0; d <= 60000.0; d *= 1.5) {
            const auto s = eval(m, v, {d * 0.6, d * 0.8, 50.0});
            for (int c = 0; c < 3; ++c) {
                EXPECT_LT(s.extinction[c], previous.extinction[c]) << name(m) << " d=" << d;
                EXPECT_GT(s.in_scattering[c], previous.in_scattering[c]) << name(m) << " d=" << d;
            }
            previous = s;
        }
    }
}

TEST(Models, HoffmanPreethamTendsToItsAsymptoteFarAway) {
    // L_in -> (beta_R P_R + beta_M P_M) / (beta_R + beta_M) * E_sun as s -> infinity.
    const Atmosphere a;
    const View v = view_at({0, 0, 0}, {0, 0.6, 0.8});
    const auto frame = aerial::prepare_frame<double>(a, v, Model::hoffman_preetham);
    ASSERT_TRUE(frame.ok());
    const dvec3 dir = glm::normalize(dvec3(1, 2, 0));
    const double cos_theta = glm::dot(dir, v.sun_dir);
    const dvec3 angular = a.rayleigh_scattering * aerial::rayleigh_phase(cos_theta) +
                          a.mie_scattering * aerial::henyey_greenstein_phase(cos_theta, a.mie_g);
    const dvec3 asymptote = angular / a.extinction() * frame->sun_irradiance_eye;
    const auto far = aerial::scatter(*frame, dir * 5e6);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(far.in_scattering[c], asymptote[c], 1e-12 * asymptote[c]) << c;
        EXPECT_LT(far.extinction[c], 1e-20);
    }
}

/// exp(-optical depth) from `eye` along `dir` to the top of the atmosphere (density zero above
/// it), up +Z, planet centre at -R: composite Simpson over 20 000 intervals, independent of the
/// module's integrator.
dvec3 transmittance_to_top_by_simpson(const Atmosphere& a, dvec3 eye, dvec3 dir) {
    const dvec3 centre(0, 0, -a.planet_radius_m);
    const dvec3 o = eye - centre;
    const double b = glm::dot(o, dir);
    const double c = glm::dot(o, o) - a.atmosphere_radius_m * a.atmosphere_radius_m;
    const double length = -b + std::sqrt(b * b - c);
    const int n = 20000;
    const double h = length / n;
    dvec3 depth(0.0);
    for (int i = 0; i <= n; ++i) {
        const double altitude = glm::length(o + dir * (i * h)) - a.planet_radius_m;
        const double weight = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        depth += weight * (a.rayleigh_scattering * std::exp(-altitude / a.rayleigh_scale_height_m) +
                           a.mie_extinction() * std::exp(-altitude / a.mie_scale_height_m) +
                           a.ozone_absorption * a.ozone_density(altitude));
    }
    return glm::exp(-depth * (h / 3.0));
}

TEST(Models, HoffmanPreethamMatchesItsClosedForm) {
    const Atmosphere a;
    const View v = view_at({5, -3, 12}, {0.2, -0.4, 0.9});
    const auto frame = aerial::prepare_frame<double>(a, v, Model::hoffman_preetham);
    ASSERT_TRUE(frame.ok());
    // E_sun = E_sun0 * T_sun(eye), T_sun from the optical depth along the ray to the sun
    // integrated here (Simpson) through the truncated spherical exponential atmosphere.
    const dvec3 t_eye = transmittance_to_top_by_simpson(a, v.eye, glm::normalize(v.sun_dir));
    for (int c = 0; c < 3; ++c) {
        // 2e-5: Simpson's error at the ozone tent's kinks (the model's column is exact).
        EXPECT_NEAR(frame->sun_irradiance_eye[c], a.sun_irradiance[c] * t_eye[c], 2e-5 * t_eye[c])
            << "channel " << c;
    }
    for (dvec3 p : {dvec3(300, 400, 0), dvec3(-9000, 2000, 40), dvec3(20000, 25000, 800)}) {
        const dvec3 d = p - v.eye;
        const double s = glm::length(d);
        const double cos_theta = glm::dot(d / s, glm::normalize(v.sun_dir));
        const dvec3 beta_ex = a.extinction();
        const dvec3 angular =
            a.rayleigh_scattering * (3.0 / (16.0 * aerial::kPi) * (1 + cos_theta * cos_theta)) +
            a.mie_scattering *
                ((1 - 0.64) / (4 * aerial::kPi * std::pow(1 + 0.64 - 1.6 * cos_theta, 1.5)));
        const auto got = aerial::scatter(*frame, p);
        for (int c = 0; c < 3; ++c) {
            const double f_ex = std::exp(-beta_ex[c] * s);
            const double l_in = angular[c] / beta_ex[c] * frame->sun_irradiance_eye[c] * (1 - f_ex);
            EXPECT_NEAR(got.extinction[c], f_ex, 1e-14);
            EXPECT_NEAR(got.in_scattering[c], l_in, 1e-12 * l_in);
        }
    }
}

TEST(Models, VanishingCoefficientsGiveTheLinearLimit) {
    // beta -> 0: F_ex -> 1 and L_in -> beta_sc(theta) E s, with no 0/0.
    Atmosphere a;
    a.rayleigh_scattering = dvec3(1e-30, 0.0, 1e-20);
    a.mie_scattering = dvec3(0.0);
    const View v = view_at({0, 0, 0}, {0, 0, 1});
    const auto frame = aerial::prepare_frame<float>(a, v, Model::hoffman_preetham);
    ASSERT_TRUE(frame.ok());
    const auto s = aerial::scatter(*frame, glm::vec3(1000, 0, 0));
    EXPECT_EQ(s.extinction.y, 1.0f);
    EXPECT_EQ(s.in_scattering.y, 0.0f);
    const double expected =
        1e-20 * aerial::rayleigh_phase(0.0) * frame->sun_irradiance_eye.z * 1000;
    EXPECT_NEAR(s.in_scattering.z, expected, 1e-6 * expected);
}

TEST(Reference, ConstantDensityWithoutSunAttenuationIsTheClosedForm) {
    // The bridge: the integrator, with sea-level density everywhere and E_sun = E_sun0, must
    // reproduce the 2002 closed form to 1e-6 relative.
    const Atmosphere a;
    aerial::ReferenceOptions options;
    options.constant_density = true;
    options.sun_attenuation = false;
    for (dvec3 sun : {dvec3(0, 0, 1), dvec3(0, 0.8, 0.2), dvec3(0.5, -0.5, 0.1)}) {
        const View v = view_at({0, 0, 100}, sun);
        const auto frame = aerial::prepare_frame<double>(a, v, Model::hoffman_preetham);
        for (dvec3 p : {dvec3(0, 500, 100), dvec3(3000, 4000, 300), dvec3(0, 30000, 50),
                        dvec3(-80000, 10000, 2000), dvec3(0, 800000, 100)}) {
            const auto ref = aerial::reference_scattering(a, v, p, options);
            const dvec3 d = p - v.eye;
            const double s = glm::length(d);
            const auto closed = aerial::hoffman_preetham_closed_form(
                *frame, s, glm::dot(d / s, v.sun_dir), a.sun_irradiance);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(ref.extinction[c], closed.extinction[c], 1e-6 * closed.extinction[c])
                    << "p=" << p.x << "," << p.y << " c=" << c;
                EXPECT_NEAR(ref.in_scattering[c], closed.in_scattering[c],
                            1e-6 * closed.in_scattering[c])
                    << "p=" << p.x << "," << p.y << " c=" << c;
            }
        }
    }
}

TEST(Reference, ZenithTransmittanceEqualsTheAnalyticColumn) {
    // From sea level straight up through the truncated exponential atmosphere and the ozone
    // tent (its column is the peak times half its width):
    // T = exp(-sum_i beta_i H_i (1 - exp(-h_top / H_i)) - beta_O3 w / 2).
    Atmosphere a;
    const double h_top = a.atmosphere_radius_m - a.planet_radius_m;
    const dvec3 tau =
        a.rayleigh_scattering * a.rayleigh_scale_height_m *
            (1 - std::exp(-h_top / a.rayleigh_scale_height_m)) +
        a.mie_extinction() * a.mie_scale_height_m * (1 - std::exp(-h_top / a.mie_scale_height_m));
    const dvec3 ozone = a.ozone_absorption * (0.5 * a.ozone_width_m);
    const dvec3 got = aerial::sun_transmittance(a, 0.0, 1.0);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], std::exp(-tau[c] - ozone[c]), 1e-9) << c;
    // Without ozone, the figures of docs/conventions.md at 680/550/440 nm.
    a.ozone_absorption = dvec3(0.0);
    const dvec3 air = aerial::sun_transmittance(a, 0.0, 1.0);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(air[c], std::exp(-tau[c]), 1e-9) << c;
    EXPECT_NEAR(air.x, 0.9501, 5e-5);
    EXPECT_NEAR(air.y, 0.8930, 5e-5);
    EXPECT_NEAR(air.z, 0.7638, 5e-5);
}

TEST(Ozone, ColumnInClosedFormMatchesTheNumericalIntegration) {
    // ozone_column_m against a brute-force midpoint sum (a million steps) along the ray, from
    // below, inside and above the layer, up to the horizon and below it as seen from altitude;
    // and the vertical column from the ground: the peak times half the width, exactly.
    Atmosphere a;
    EXPECT_NEAR(aerial::ozone_column_m(a, 0.0, 1.0), 0.5 * a.ozone_width_m, 1e-6);
    auto brute_force = [&](double h, double mu) {
        const double r0 = a.planet_radius_m + h, length = 3e6;
        const int steps = 1000000;
        double column = 0.0;
        for (int i = 0; i < steps; ++i) {
            const double t = (i + 0.5) * length / steps;
            const double r = std::sqrt(t * t + 2.0 * r0 * mu * t + r0 * r0);
            if (r <= a.atmosphere_radius_m)
                column += a.ozone_density(r - a.planet_radius_m) * length / steps;
        }
        return column;
    };
    for (double h : {0.0, 15000.0, 25000.0, 50000.0}) {
        const double horizon =
            -std::sqrt(1.0 - std::pow(a.planet_radius_m / (a.planet_radius_m + h), 2.0));
        for (double mu : {1.0, 0.1, 0.0, horizon + 1e-4}) {
            const double closed = aerial::ozone_column_m(a, h, mu);
            EXPECT_NEAR(closed, brute_force(h, mu), 1e-5 * closed + 1.0)
                << "h " << h << " mu " << mu;
            const dvec3 t = aerial::ozone_transmittance(a, h, mu);
            EXPECT_NEAR(t.y, std::exp(-a.ozone_absorption.y * closed), 1e-15);
        }
    }
    // Without ozone, 1; a blocked sun takes the horizon's column.
    Atmosphere none = a;
    none.ozone_absorption = dvec3(0.0);
    EXPECT_EQ(aerial::ozone_transmittance(none, 100.0, 0.3), dvec3(1.0));
    EXPECT_EQ(aerial::ozone_transmittance(a, 0.0, -0.5), aerial::ozone_transmittance(a, 0.0, 0.0));
}

TEST(Reference, ConvergedToATenthOfAPercent) {
    // Four times finer steps change nothing that matters: the default is converged.
    const Atmosphere a;
    aerial::ReferenceOptions fine;
    fine.steps_per_efold = 8.0;
    for (dvec3 sun : {dvec3(0, 0.6, 0.8), dvec3(0, 0.995, 0.0998), dvec3(0.6, 0.0, -0.02)}) {
        const View v = view_at({0, 0, 100}, sun);
        for (dvec3 p : {dvec3(0, 1000, 100), dvec3(0, 10000, 100), dvec3(0, 50000, 100),
                        dvec3(0, 14000, -9900), dvec3(30000, 0, 5000)}) {
            const auto coarse = aerial::reference_scattering(a, v, p);
            const auto ref = aerial::reference_scattering(a, v, p, fine);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(coarse.extinction[c], ref.extinction[c], 1e-3 * ref.extinction[c]);
                EXPECT_NEAR(coarse.in_scattering[c], ref.in_scattering[c],
                            1e-3 * ref.in_scattering[c] + 1e-15);
            }
        }
    }
}

TEST(Reference, PlanetShadowsTheSunBelowTheHorizon) {
    const Atmosphere a;
    // Sun 5 degrees below the horizon: dark at sea level, lit at 40 km.
    const double mu = std::sin(-5.0 * aerial::kPi / 180.0);
    EXPECT_EQ(aerial::sun_transmittance(a, 0.0, mu), dvec3(0.0));
    EXPECT_EQ(aerial::sun_transmittance(a, -300.0, mu), dvec3(0.0));
    EXPECT_GT(aerial::sun_transmittance(a, 40000.0, mu).x, 0.0);
    // The eye in the shadow still sees sunlit air above it.
    const View v = view_at({0, 0, 2}, {0, std::cos(0.0873), -std::sin(0.0873)});
    const auto looking_up = eval(Model::single_scattering, v, {0, 60000, 40000});
    EXPECT_GT(looking_up.in_scattering.z, 0.0);
    EXPECT_GT(looking_up.sun_irradiance.x, 0.0) << "the vertex at 40 km is lit";
    EXPECT_EQ(eval(Model::single_scattering, v, {0, 100, 2}).sun_irradiance, dvec3(0.0))
        << "no sun at a vertex beside the eye";
}

TEST(Chapman, SunTransmittanceWithinOnePercentInOpticalDepth) {
    // The height model's fast sun transmittance against the exact integration, from 0 to 20 km
    // and from the zenith to the horizon, plus sub-horizon angles seen from altitude; the
    // exponential profiles only (the model takes ozone's part from ozone_transmittance).
    Atmosphere a;
    a.ozone_absorption = dvec3(0.0);
    const View v = view_at({0, 0, 0}, {0, 0, 1});
    const auto frame = aerial::prepare_frame<double>(a, v, Model::height);
    ASSERT_TRUE(frame.ok());
    for (double h : {0.0, 500.0, 2000.0, 8000.0, 20000.0}) {
        for (double elevation_deg : {90.0, 45.0, 20.0, 10.0, 5.0, 2.0, 0.0, -0.5, -1.0, -2.0}) {
            const double mu = std::sin(elevation_deg * aerial::kPi / 180.0);
            const dvec3 exact = aerial::sun_transmittance(a, h, mu);
            const dvec3 fast = aerial::sun_transmittance_chapman(*frame, h, mu);
            for (int c = 0; c < 3; ++c) {
                if (exact[c] == 0.0) {
                    EXPECT_LT(fast[c], 1e-3) << "h=" << h << " elev=" << elevation_deg;
                    continue;
                }
                const double tau_exact = -std::log(exact[c]);
                const double tau_fast = -std::log(std::max(fast[c], 1e-300));
                EXPECT_NEAR(tau_fast, tau_exact, 0.01 * tau_exact + 1e-6)
                    << "h=" << h << " elev=" << elevation_deg << " c=" << c;
            }
        }
    }
}

TEST(Models, FloatAgreesWithDouble) {
    const Atmosphere a;
    const View v = view_at({100, -50, 300}, {0.1, 0.7, 0.3});
    for (Model m : {Model::hoffman_preetham, Model::height}) {
        const auto fd = aerial::prepare_frame<double>(a, v, m);
        const auto ff = aerial::prepare_frame<float>(a, v, m);
        for (dvec3 p : {dvec3(150, 0, 290), dvec3(5000, 3000, 0), dvec3(-40000, 2000, 1500),
                        dvec3(0, 200000, 20000)}) {
            const auto d = aerial::scatter(*fd, p);
            const auto f = aerial::scatter(*ff, glm::vec3(p));
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(f.extinction[c], d.extinction[c], 1e-5) << name(m);
                EXPECT_NEAR(f.in_scattering[c], d.in_scattering[c],
                            1e-4 * d.in_scattering[c] + 1e-9)
                    << name(m);
            }
        }
    }
}

TEST(Models, UnitsScaleConvertsEnginePositions) {
    // An engine in centimetres sets meters_per_unit = 0.01 and gets the same colours.
    View metres = view_at({0, 0, 30}, {0, 0.6, 0.8});
    View centimetres = metres;
    centimetres.eye *= 100.0;
    centimetres.meters_per_unit = 0.01;
    for (Model m : aerial::all_models()) {
        const auto x = eval(m, metres, {4000, 3000, 10});
        const auto y = eval(m, centimetres, {400000, 300000, 1000});
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(x.in_scattering[c], y.in_scattering[c], 1e-9 * x.in_scattering[c])
                << name(m);
        }
    }
}

TEST(Models, UpAxisIsAParameter) {
    // The same scene with +Y up gives the same colours as with +Z up.
    View z_up = view_at({0, 0, 30}, {0, 0.6, 0.8});
    View y_up = view_at({0, 30, 0}, {0, 0.8, 0.6});
    y_up.up = {0, 1, 0};
    for (Model m : aerial::all_models()) {
        const auto zz = eval(m, z_up, {100, 4000, 10});
        const auto yy = eval(m, y_up, {100, 10, 4000});
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(zz.extinction[c], yy.extinction[c], 1e-12) << name(m);
            EXPECT_NEAR(zz.in_scattering[c], yy.in_scattering[c], 1e-9 * zz.in_scattering[c])
                << name(m);
        }
    }
}

TEST(ViewValidate, NamesTheBadField) {
    View v;
    v.eye.x = std::nan("");
    EXPECT_EQ(aerial::validate(v)->field, "eye");
    v = {};
    v.sun_dir = {0, 0, 2};
    EXPECT_EQ(aerial::validate(v)->field, "sun_dir");
    EXPECT_NE(aerial::validate(v)->message.find("unit vector"), std::string::npos);
    v = {};
    v.up = {0, 0, 0};
    EXPECT_EQ(aerial::validate(v)->field, "up");
    v = {};
    v.meters_per_unit = 0.0;
    EXPECT_EQ(aerial::validate(v)->field, "meters_per_unit");
    // An eye the float paths cannot hold (found by fuzz_batch: an eye at -1.8e308 m gave NaN
    // L_in): beyond kMaxDistanceM in metres, or beyond float in engine units.
    v = {};
    v.eye.y = -1.79e308;
    ASSERT_TRUE(aerial::validate(v));
    EXPECT_EQ(aerial::validate(v)->field, "eye");
    v = {};
    v.eye.x = 2e12;
    EXPECT_EQ(aerial::validate(v)->field, "eye");
    v.meters_per_unit = 0.1;  // 2e11 m: fine
    EXPECT_FALSE(aerial::validate(v));
    v.eye.x = 1e39;  // 1e-27 m per unit keeps it near in metres, but no float holds 1e39
    v.meters_per_unit = 1e-27;
    EXPECT_EQ(aerial::validate(v)->field, "eye");
    Atmosphere bad;
    bad.mie_g = 2.0;
    const auto frame = aerial::prepare_frame<float>(bad, View{}, Model::height);
    ASSERT_FALSE(frame.ok());
    EXPECT_EQ(frame.error().field, "mie_g");
}

TEST(Models, NonPositionsAreNeutralNotNaN) {
    const auto frame = aerial::prepare_frame<float>(Atmosphere{}, View{}, Model::height);
    for (glm::vec3 p :
         {glm::vec3(std::nanf(""), 0, 0), glm::vec3(INFINITY, 0, 0), glm::vec3(1e30f, 0, 0)}) {
        const auto s = aerial::scatter(*frame, p);
        EXPECT_EQ(s.extinction, glm::vec3(1.0f));
        EXPECT_EQ(s.in_scattering, glm::vec3(0.0f));
    }
    const auto r = aerial::evaluate(Atmosphere{}, View{}, Model::height, {std::nan(""), 0, 0});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "vertex");
}

}  // namespace

namespace {

TEST(Names, EveryNameParsesBackAndUnknownNamesListTheKnownOnes) {
    for (Model m : aerial::all_models()) {
        const auto parsed = aerial::parse_model(aerial::model_name(m));
        ASSERT_TRUE(parsed.ok()) << aerial::model_name(m);
        EXPECT_EQ(*parsed, m);
    }
    const auto model = aerial::parse_model("fast");
    ASSERT_FALSE(model.ok());
    EXPECT_EQ(model.error().field, "model");
    EXPECT_EQ(model.error().message,
              "aerial::parse_model(): model: expected one of hoffman-preetham, height, "
              "single-scattering, reference, "
              "got 'fast'");
    for (auto curve : {aerial::ToneCurve::clamp, aerial::ToneCurve::exponential}) {
        EXPECT_EQ(*aerial::parse_tone_curve(aerial::tone_curve_name(curve)), curve);
    }
    const auto curve = aerial::parse_tone_curve("filmic");
    ASSERT_FALSE(curve.ok());
    EXPECT_EQ(curve.error().message,
              "aerial::parse_tone_curve(): tone_curve: expected one of clamp, exponential, got "
              "'filmic'");
}

}  // namespace
