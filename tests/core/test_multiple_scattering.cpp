// The `reference` model's higher orders, checked against what does not depend on them: energy
// closure in conservative atmospheres over a black ground, the closed forms of the scattering
// step (a uniform radiance L scatters beta_s L; a uniform sky L gives a ground irradiance pi L),
// the single-scattering limit, and the convergence report.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "multiple_scattering.hpp"
#include "table_cache.hpp"

namespace {

using aerial::Atmosphere;
using aerial::Model;
using aerial::View;
using glm::dvec3;

constexpr double kPi = 3.14159265358979323846;

/// A conservative atmosphere (no absorption, no ozone) over a black ground on a planet 100 times
/// Earth's radius: nearly plane-parallel, so that what enters at the top must leave through the
/// top or reach the ground at every place.
Atmosphere conservative(double mie_per_m) {
    Atmosphere a;
    a.mie_scattering = dvec3(mie_per_m);
    a.mie_absorption = a.ozone_absorption = a.ground_albedo = dvec3(0.0);
    a.planet_radius_m *= 100.0;
    a.atmosphere_radius_m = a.planet_radius_m + 60e3;
    return a;
}

struct Fluxes {
    dvec3 direct, diffuse_down, up;
    /// (direct + diffuse down + up) / (mu0 E0): 1 when energy is conserved.
    dvec3 closure(double mu0) const { return (direct + diffuse_down + up) / mu0; }
};

dvec3 in_scattering(const Atmosphere& a, const View& view, Model model, const dvec3& p) {
    const auto s = aerial::evaluate(a, view, model, p);
    EXPECT_TRUE(s.ok());
    return s.ok() ? s->in_scattering : dvec3(0.0);
}

/// The fluxes through the ground and the top for a sun at `zenith_rad`, radiances from `model`:
/// hemispheres integrated in coordinates centred on the sun (Gauss in the angle from the sun,
/// midpoints in azimuth around it, mirrored), so that the Mie aureole is resolved.
Fluxes fluxes(const Atmosphere& a, Model model, double zenith_rad) {
    View view;
    view.sun_dir = dvec3(std::sin(zenith_rad), 0.0, std::cos(zenith_rad));
    const dvec3 across(std::cos(zenith_rad), 0.0, -std::sin(zenith_rad)), side(0.0, 1.0, 0.0);
    const double top = a.atmosphere_radius_m - a.planet_radius_m;
    std::vector<double> x, w;
    aerial::detail::gauss_legendre(48, 0.0, 1.0, x, w);
    const int azimuths = 16;
    Fluxes f{};
    for (std::size_t i = 0; i < x.size(); ++i) {
        const double angle = x[i] * kPi;
        for (int m = 0; m < azimuths; ++m) {
            const double phi = (m + 0.5) * kPi / azimuths;
            const double weight = w[i] * kPi * std::sin(angle) * 2.0 * kPi / azimuths;
            const dvec3 d = across * (std::sin(angle) * std::cos(phi)) +
                            side * (std::sin(angle) * std::sin(phi)) +
                            view.sun_dir * std::cos(angle);
            if (d.z > 0.0) {  // sky seen from the ground, up to the atmosphere's top
                view.eye = dvec3(0.0);
                const double ground = a.planet_radius_m, b = ground * d.z;
                const double length = -b + std::sqrt(b * b + (a.atmosphere_radius_m - ground) *
                                                                 (a.atmosphere_radius_m + ground));
                f.diffuse_down += in_scattering(a, view, model, d * length) * (d.z * weight);
            } else {  // the air seen from the top, down to the (black) ground
                view.eye = dvec3(0.0, 0.0, top);
                const double r = a.planet_radius_m + top;
                const double b = -r * d.z;
                const double disc = b * b - (r * r - a.planet_radius_m * a.planet_radius_m);
                const double length = disc > 0.0 ? b - std::sqrt(disc) : 1e7;
                f.up += in_scattering(a, view, model, view.eye + d * length) * (-d.z * weight);
            }
        }
    }
    f.direct = aerial::sun_transmittance(a, 0.0, std::cos(zenith_rad)) * std::cos(zenith_rad);
    return f;
}

/// How far `height`'s fluxes may be from closing: regression bounds, not targets (measured: at
/// most 0.48 % off in clear air, 2.2 % in haze, where the light field's shape is carried along
/// rays through the whole haze from 8 altitude rows).
constexpr double kHeightClosureClear = 0.006, kHeightClosureHaze = 0.03;

TEST(MultipleScattering, EnergyClosesInConservativeAtmospheresOverABlackGround) {
    // Clear air (earth's Mie) and haze (2e-4 /m of Mie, a 20 km visibility), sun 0-75 degrees from
    // the zenith: the reference's fluxes account for what the sun brings within 1 % per channel;
    // single scattering loses up to 6.5 % (clear) and 40 % (haze) of it.
    for (double mie : {3.996e-6, 2e-4}) {
        const Atmosphere a = conservative(mie);
        const auto report = aerial::reference_multiple_scattering(a);
        ASSERT_TRUE(report.ok());
        std::printf("mie %.3g /m: %d orders, remainder bound %.1e %.1e %.1e, %.1f s\n", mie,
                    report->orders, report->remainder_bound.x, report->remainder_bound.y,
                    report->remainder_bound.z, report->seconds);
        for (double zenith_deg : {0.0, 30.0, 60.0, 75.0}) {
            const double zenith = zenith_deg * kPi / 180.0;
            const dvec3 all = fluxes(a, Model::reference, zenith).closure(std::cos(zenith));
            const dvec3 single =
                fluxes(a, Model::single_scattering, zenith).closure(std::cos(zenith));
            EXPECT_LT(single.z, 0.94) << "single scattering loses blue light";
            // `height` with its higher orders from the coarser table, cut at the eye
            // (height_multiple_scattering.hpp): it closes nearly as the reference does.
            const dvec3 height = fluxes(a, Model::height, zenith).closure(std::cos(zenith));
            std::printf(
                "  sun %2.0f deg: closure reference %.4f %.4f %.4f, single %.4f %.4f %.4f, "
                "height %.4f %.4f %.4f\n",
                zenith_deg, all.x, all.y, all.z, single.x, single.y, single.z, height.x, height.y,
                height.z);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(height[c], 1.0, mie < 1e-5 ? kHeightClosureClear : kHeightClosureHaze)
                    << c;
            }
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(all[c], 1.0, 0.01)
                    << "mie " << mie << " sun " << zenith_deg << " c " << c;
                EXPECT_GT(std::abs(1.0 - single[c]), std::abs(1.0 - all[c]))
                    << "single scattering closes the balance better than the reference";
            }
        }
    }
}

TEST(MultipleScattering, UniformRadianceScattersBetaTimesIt) {
    // Bruneton 2017's closed form: in a uniform radiance field L every view direction gets a
    // scattering density beta_s L, whatever the phase function. The shares of the incoming
    // directions sum to 1 for every view, at every altitude, for forward and backward Mie.
    const aerial::MultipleScatteringSettings settings;
    for (double g : {0.0, 0.8, -0.5, 0.95}) {
        Atmosphere a;
        a.mie_g = g;
        for (double h : {0.0, 3000.0, 59000.0}) {
            const auto directions = aerial::detail::incoming_directions(a, settings, h);
            std::vector<double> rayleigh(directions.size()), mie(directions.size());
            for (const dvec3& view : {dvec3(0, 0, 1), glm::normalize(dvec3(1, 0.3, -0.2)),
                                      glm::normalize(dvec3(-0.2, 0.9, 0.05))}) {
                aerial::detail::scattering_shares(view, directions, g, rayleigh.data(), mie.data());
                double sum_r = 0.0, sum_m = 0.0;
                for (std::size_t k = 0; k < directions.size(); ++k) {
                    EXPECT_GE(rayleigh[k], 0.0);
                    EXPECT_GE(mie[k], 0.0);
                    sum_r += rayleigh[k];
                    sum_m += mie[k];
                }
                EXPECT_NEAR(sum_r, 1.0, 1e-12) << "g " << g << " h " << h;
                EXPECT_NEAR(sum_m, 1.0, 1e-12) << "g " << g << " h " << h;
            }
            // Before the scaling the quadrature alone is close: the solid angles sum to 4 pi.
            double solid_angle = 0.0;
            for (const auto& d : directions) solid_angle += d.weight;
            EXPECT_NEAR(solid_angle, 4.0 * kPi, 1e-9) << "h " << h;
        }
    }
}

TEST(MultipleScattering, UniformSkyRadianceGivesAGroundIrradianceOfPiTimesIt) {
    const Atmosphere a;
    const auto directions = aerial::detail::incoming_directions(a, {}, 0.0);
    const dvec3 radiance(0.25, 1.0, 3.0);
    const dvec3 e = aerial::detail::horizontal_irradiance(
        directions, std::vector<dvec3>(directions.size(), radiance));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(e[c], kPi * radiance[c], 1e-12 * radiance[c]);
}

/// (reference - single-scattering) / single-scattering of L_in (G) at a few views.
double higher_order_share(const Atmosphere& a) {
    View v;
    v.eye = dvec3(0, 0, 100);
    v.sun_dir = glm::normalize(dvec3(0, 0.6, 0.8));
    double worst = 0.0;
    for (const dvec3& p : {dvec3(0, 20000, 100), dvec3(15000, 0, 3000), dvec3(0, -5000, 40000)}) {
        const auto all = aerial::evaluate(a, v, Model::reference, p);
        const auto single = aerial::evaluate(a, v, Model::single_scattering, p);
        EXPECT_TRUE(all.ok() && single.ok());
        worst = std::max(worst, all->in_scattering.y / single->in_scattering.y - 1.0);
    }
    return worst;
}

TEST(MultipleScattering, HigherOrdersVanishWithTheOpticalDepth) {
    // Scaling every coefficient by k scales the second order's share of L_in by k: the orders
    // >= 2 vanish in the single-scattering limit, linearly.
    Atmosphere thin;
    thin.ground_albedo = dvec3(0.0);
    double previous = 0.0;
    for (double k : {1.0, 0.1, 0.01}) {
        Atmosphere a = thin;
        a.rayleigh_scattering *= k;
        a.mie_scattering *= k;
        a.ozone_absorption *= k;
        const double share = higher_order_share(a);
        std::printf("coefficients x %.2f: higher orders add %.4f %% of L_in (G)\n", k,
                    100.0 * share);
        EXPECT_GT(share, 0.0) << "k " << k;
        if (previous > 0.0) {
            EXPECT_NEAR(share / previous, 0.1, 0.03) << "k " << k;
        }
        previous = share;
    }
    EXPECT_LT(previous, 5e-3);
}

TEST(MultipleScattering, TheReportGivesOrdersAndABoundBelowItsTarget) {
    const auto report = aerial::reference_multiple_scattering(Atmosphere{});
    ASSERT_TRUE(report.ok());
    EXPECT_GE(report->orders, 3);
    EXPECT_EQ(report->order_sums.size(), std::size_t(report->orders - 1));
    for (int c = 0; c < 3; ++c) EXPECT_LT(report->remainder_bound[c], 1e-3) << c;
    // Each order holds less light than the one before it.
    for (std::size_t n = 1; n < report->order_sums.size(); ++n) {
        for (int c = 0; c < 3; ++c)
            EXPECT_LT(report->order_sums[n][c], report->order_sums[n - 1][c]) << n;
    }
    // Stopped by max_orders before two orders could be compared, the bound is unknown; with two,
    // it is finite but above the target.
    aerial::MultipleScatteringSettings stopped;
    stopped.max_orders = 2;
    const auto one_order = aerial::reference_multiple_scattering(Atmosphere{}, stopped);
    ASSERT_TRUE(one_order.ok());
    EXPECT_EQ(one_order->orders, 2);
    EXPECT_TRUE(std::isinf(one_order->remainder_bound.y));
    stopped.max_orders = 3;
    const auto two_orders = aerial::reference_multiple_scattering(Atmosphere{}, stopped);
    ASSERT_TRUE(two_orders.ok());
    EXPECT_EQ(two_orders->orders, 3);
    EXPECT_GT(two_orders->remainder_bound.y, 1e-3);
    EXPECT_LT(two_orders->remainder_bound.y, 1.0);
    // Bad input is an error naming the field.
    Atmosphere bad;
    bad.ground_albedo.y = -0.5;
    const auto refused = aerial::reference_multiple_scattering(bad);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().field, "ground_albedo[1]");
}

TEST(MultipleScattering, SettingsOutOfRangeAreErrorsNamingTheFieldAndClampedInTheIntegrator) {
    aerial::MultipleScatteringSettings s;
    EXPECT_FALSE(aerial::validate(s));
    s.altitudes = 100000;  // would ask for gigabytes
    auto e = aerial::validate(s);
    ASSERT_TRUE(e);
    EXPECT_EQ(e->message,
              "aerial::validate(): altitudes: expected a count in [4, 256], got 100000");
    s = {};
    s.steps_per_efold = std::nan("");
    EXPECT_EQ(aerial::validate(s)->field, "steps_per_efold");
    s = {};
    s.max_remainder = 0.0;
    EXPECT_EQ(aerial::validate(s)->field, "max_remainder");
    s = {};
    s.half_azimuths = 1;
    const auto refused = aerial::reference_multiple_scattering(Atmosphere{}, s);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().field, "half_azimuths");
    // The integrator has no error channel: it clamps (here to the smallest tables) and stays
    // finite.
    aerial::ReferenceOptions options;
    options.multiple_scattering = true;
    options.tables = {1, -3, 0, 0, 0, 0, 0, std::nan(""), -1.0, 0};
    View v;
    v.eye = dvec3(0, 0, 100);
    const auto r = aerial::reference_scattering(Atmosphere{}, v, dvec3(0, 5000, 100), options);
    for (int c = 0; c < 3; ++c)
        EXPECT_TRUE(std::isfinite(r.in_scattering[c]) && r.in_scattering[c] > 0);
}

TEST(MultipleScattering, GroundReflectionBrightensTheSkyAndTheReferenceIsBrighterThanSingle) {
    View v;
    v.eye = dvec3(0, 0, 100);
    v.sun_dir = glm::normalize(dvec3(0, 0.6, 0.8));
    Atmosphere black;
    black.ground_albedo = dvec3(0.0);
    Atmosphere bright;
    bright.ground_albedo = dvec3(0.8);
    const dvec3 p(0, -5000, 40000);
    const auto single = *aerial::evaluate(black, v, Model::single_scattering, p);
    const auto on_black = *aerial::evaluate(black, v, Model::reference, p);
    const auto on_bright = *aerial::evaluate(bright, v, Model::reference, p);
    for (int c = 0; c < 3; ++c) {
        EXPECT_GT(on_black.in_scattering[c], single.in_scattering[c]) << c;
        EXPECT_GT(on_bright.in_scattering[c], on_black.in_scattering[c]) << c;
        EXPECT_EQ(on_black.extinction[c], single.extinction[c]) << c;
    }
}

}  // namespace

namespace {

/// G channel of L_in from the eye at 100 m to `target`, for a sun at `elevation_deg`.
double lin_g(const Atmosphere& a, Model model, double elevation_deg, const dvec3& target) {
    View v;
    v.eye = dvec3(0, 0, 100);
    const double e = elevation_deg * kPi / 180.0;
    v.sun_dir = dvec3(0.0, std::cos(e), std::sin(e));
    const auto s = aerial::evaluate(a, v, model, target);
    EXPECT_TRUE(s.ok());
    return s.ok() ? s->in_scattering.y : 0.0;
}

TEST(MultipleScattering, ShareOfTheHigherOrdersPerPresetAndSunElevation) {
    // The table of docs/models.md: the part of L_in (G) that the orders >= 2 and the ground add,
    // for terrain 20 km away towards the sun's azimuth (at 100 m) and the zenith sky.
    std::printf("| preset | view | 90 deg | 30 deg | 10 deg | 2 deg | 0 deg | -4 deg |\n");
    for (const std::string& name : aerial::atmosphere_preset_names()) {
        const Atmosphere a = *aerial::atmosphere_preset(name);
        for (const auto& [view, target] :
             {std::pair<const char*, dvec3>{"terrain 20 km", {0, 20000, 100}},
              std::pair<const char*, dvec3>{"zenith sky", {0, 0, 2e5}}}) {
            std::printf("| `%s` | %s |", name.c_str(), view);
            for (double elevation : {90.0, 30.0, 10.0, 2.0, 0.0, -4.0}) {
                const double all = lin_g(a, Model::reference, elevation, target);
                const double single = lin_g(a, Model::single_scattering, elevation, target);
                EXPECT_GE(all, single) << name << " " << view << " " << elevation;
                if (all > 0.0) {
                    std::printf(" %.0f %% |", 100.0 * (all - single) / all);
                } else {
                    std::printf(" - |");
                }
                // Below the horizon only the higher orders light the air under the shadow.
                if (elevation > 1.0) {
                    EXPECT_LT(all - single, all) << name << " " << view;
                }
            }
            std::printf("\n");
        }
    }
}

TEST(MultipleScattering, OzoneTurnsTheZenithSkyBlueAtSunset) {
    // With the sun on the horizon the sunlight lighting the zenith crosses the ozone layer
    // edgewise; ozone absorbs green and red (Chappuis band) and leaves blue, so the zenith's blue
    // to red ratio rises (the blue hour) and its green falls.
    Atmosphere with;
    Atmosphere without;
    without.ozone_absorption = dvec3(0.0);
    View v;
    v.eye = dvec3(0, 0, 100);
    for (double elevation : {0.0, -2.0}) {
        const double e = elevation * kPi / 180.0;
        v.sun_dir = dvec3(0.0, std::cos(e), std::sin(e));
        const dvec3 z1 = aerial::evaluate(with, v, Model::reference, {0, 0, 2e5})->in_scattering;
        const dvec3 z0 = aerial::evaluate(without, v, Model::reference, {0, 0, 2e5})->in_scattering;
        std::printf(
            "sun %.0f deg: zenith L_in with ozone %.4g %.4g %.4g, without %.4g %.4g %.4g "
            "(B/R %.2f vs %.2f)\n",
            elevation, z1.x, z1.y, z1.z, z0.x, z0.y, z0.z, z1.z / z1.x, z0.z / z0.x);
        EXPECT_GT(z1.z / z1.x, 1.1 * z0.z / z0.x) << elevation;
        EXPECT_LT(z1.y, 0.8 * z0.y) << elevation;
    }
}

}  // namespace

namespace {

/// Sets an environment variable for one scope, and puts the old value back.
class ScopedEnvironment {
  public:
    ScopedEnvironment(const char* name, const char* value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old;
        if (value) {
            ::setenv(name, value, 1);
        } else {
            ::unsetenv(name);
        }
    }
    ~ScopedEnvironment() {
        if (old_) {
            ::setenv(name_, old_->c_str(), 1);
        } else {
            ::unsetenv(name_);
        }
    }

  private:
    const char* name_;
    std::optional<std::string> old_;
};

}  // namespace

TEST(TableCache, StoresReadsBackAndIgnoresWhatDoesNotMatch) {
    namespace fs = std::filesystem;
    const fs::path dir =
        fs::temp_directory_path() / ("aerial-table-cache-" + std::to_string(long(::getpid())));
    fs::remove_all(dir);
    const ScopedEnvironment cache_dir("AERIAL_CACHE_DIR", dir.c_str());
    const ScopedEnvironment enabled("AERIAL_CACHE_DISABLE", nullptr);
    aerial::MultipleScatteringSettings settings;
    const std::string key = aerial::detail::table_cache_key(Atmosphere{}, settings);
    std::vector<dvec3> table{dvec3(1.0, 2.0, 3.0), dvec3(0.5, 0.25, 0.125)};
    aerial::MultipleScatteringReport report;
    report.orders = 7;
    report.remainder_bound = dvec3(1e-4);
    report.order_sums = {dvec3(3.0), dvec3(1.0)};
    report.seconds = 2.5;
    aerial::detail::store_cached_table(key, table, report);

    std::vector<dvec3> read;
    aerial::MultipleScatteringReport read_report;
    ASSERT_TRUE(aerial::detail::load_cached_table(key, table.size(), read, read_report));
    EXPECT_EQ(read, table);
    EXPECT_EQ(read_report.orders, 7);
    EXPECT_EQ(read_report.order_sums.size(), 2u);
    EXPECT_EQ(read_report.seconds, 2.5);
    EXPECT_TRUE(read_report.from_cache);
    // Another key (one field changed by one ulp), another size: misses.
    Atmosphere other;
    other.mie_g = std::nextafter(other.mie_g, 1.0);
    EXPECT_FALSE(aerial::detail::load_cached_table(aerial::detail::table_cache_key(other, settings),
                                                   table.size(), read, read_report));
    EXPECT_FALSE(aerial::detail::load_cached_table(key, table.size() + 1, read, read_report));
    // The tables are per unit E_sun0: the key leaves sun_irradiance out.
    other = Atmosphere{};
    other.sun_irradiance = dvec3(7.0);
    EXPECT_EQ(aerial::detail::table_cache_key(other, settings), key);
    // A truncated file is a miss, not an error.
    for (const auto& entry : fs::directory_iterator(dir)) {
        fs::resize_file(entry.path(), fs::file_size(entry.path()) - 8);
    }
    EXPECT_FALSE(aerial::detail::load_cached_table(key, table.size(), read, read_report));
    // Turned off: nothing is read or written.
    aerial::detail::store_cached_table(key, table, report);
    ASSERT_TRUE(aerial::detail::load_cached_table(key, table.size(), read, read_report));
    {
        const ScopedEnvironment off("AERIAL_CACHE_DISABLE", "1");
        EXPECT_FALSE(aerial::detail::load_cached_table(key, table.size(), read, read_report));
        fs::remove_all(dir);
        aerial::detail::store_cached_table(key, table, report);
        EXPECT_FALSE(fs::exists(dir));
    }
    fs::remove_all(dir);
}

TEST(TableCache, KeepsTheRecentlyReadWithinItsLimit) {
    namespace fs = std::filesystem;
    const fs::path dir =
        fs::temp_directory_path() / ("aerial-table-lru-" + std::to_string(long(::getpid())));
    fs::remove_all(dir);
    const ScopedEnvironment cache_dir("AERIAL_CACHE_DIR", dir.c_str());
    const ScopedEnvironment enabled("AERIAL_CACHE_DISABLE", nullptr);
    const ScopedEnvironment limit("AERIAL_CACHE_MAX_MB", "1");
    const std::vector<dvec3> table(17000, dvec3(1.0));  // 408 kB: two fit in 1 MB, three do not
    const aerial::MultipleScatteringReport report;
    std::vector<std::string> keys;
    for (int i = 0; i < 3; ++i) {
        Atmosphere a;
        a.mie_g = 0.1 * i;
        keys.push_back(aerial::detail::table_cache_key(a, aerial::MultipleScatteringSettings{}));
    }
    std::vector<dvec3> read;
    aerial::MultipleScatteringReport read_report;
    const auto pause = [] { std::this_thread::sleep_for(std::chrono::milliseconds(20)); };
    aerial::detail::store_cached_table(keys[0], table, report);
    pause();
    aerial::detail::store_cached_table(keys[1], table, report);
    pause();
    // Reading the first renews it: the second is now the least recently used.
    ASSERT_TRUE(aerial::detail::load_cached_table(keys[0], table.size(), read, read_report));
    pause();
    aerial::detail::store_cached_table(keys[2], table, report);
    EXPECT_TRUE(aerial::detail::load_cached_table(keys[0], table.size(), read, read_report));
    EXPECT_FALSE(aerial::detail::load_cached_table(keys[1], table.size(), read, read_report));
    EXPECT_TRUE(aerial::detail::load_cached_table(keys[2], table.size(), read, read_report));
    fs::remove_all(dir);
}

TEST(HeightMultipleScattering, TheSliceIsThereForHeightUnlessTurnedOffAndAddsLight) {
    View view;
    view.eye = dvec3(0.0, 0.0, 300.0);
    view.sun_dir = glm::normalize(dvec3(0.0, 1.0, 0.5));
    const auto with = aerial::prepare_frame<double>(Atmosphere{}, view, Model::height);
    aerial::FrameOptions off;
    off.multiple_scattering = false;
    const auto without = aerial::prepare_frame<double>(Atmosphere{}, view, Model::height, off);
    const auto hp = aerial::prepare_frame<double>(Atmosphere{}, view, Model::hoffman_preetham);
    ASSERT_TRUE(with.ok() && without.ok() && hp.ok());
    EXPECT_NE(with->multiple_scattering, nullptr);
    EXPECT_EQ(without->multiple_scattering, nullptr);
    EXPECT_EQ(hp->multiple_scattering, nullptr) << "the 2002 model stays the 2002 model";
    // The higher orders only add light; F_ex is the same.
    for (const dvec3& p : {dvec3(0, 20000, 0), dvec3(5000, -3000, 200), dvec3(0, 1e5, 3e4)}) {
        const auto a = aerial::scatter(*with, p), b = aerial::scatter(*without, p);
        for (int c = 0; c < 3; ++c) {
            EXPECT_GT(a.in_scattering[c], b.in_scattering[c]) << c;
            EXPECT_EQ(a.extinction[c], b.extinction[c]) << c;
        }
    }
    // The planet's shadow: the sun 4 deg below the horizon, the single scattering of the low
    // air is gone, the higher orders still light it.
    view.sun_dir = glm::normalize(dvec3(0.0, 1.0, -0.07));
    const auto dusk = aerial::prepare_frame<double>(Atmosphere{}, view, Model::height);
    ASSERT_TRUE(dusk.ok());
    EXPECT_GT(aerial::scatter(*dusk, dvec3(0, 3000, 0)).in_scattering.y, 0.0);
}
