// Atmosphere: validation messages, presets, the 2002 formulas, the constructors, JSON.
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "aerial/atmosphere.hpp"
#include "aerial/phase.hpp"

namespace {

using aerial::Atmosphere;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Expects validate() to reject `a` naming `field`, with `fragment` in the message.
void expect_rejected(const Atmosphere& a, const std::string& field, const std::string& fragment) {
    const auto error = aerial::validate(a);
    ASSERT_TRUE(error.has_value()) << "expected an error on " << field;
    EXPECT_EQ(error->field, field);
    EXPECT_EQ(error->message.rfind("aerial::validate(): " + field + ": expected ", 0), 0u)
        << "message must start with the function and the field: " << error->message;
    EXPECT_NE(error->message.find(fragment), std::string::npos)
        << "message '" << error->message << "' lacks '" << fragment << "'";
}

TEST(AtmosphereValidate, AcceptsEveryPreset) {
    for (const auto& name : aerial::atmosphere_preset_names()) {
        const auto a = aerial::atmosphere_preset(name);
        ASSERT_TRUE(a.ok()) << name << ": " << a.error().message;
        EXPECT_FALSE(aerial::validate(*a).has_value()) << name;
    }
}

TEST(AtmosphereValidate, NamesEachBadFieldAndValue) {
    Atmosphere a;
    a.rayleigh_scattering.y = -1e-6;
    expect_rejected(a, "rayleigh_scattering[1]", "got -1e-06");
    a = {};
    a.mie_scattering.z = kNaN;
    expect_rejected(a, "mie_scattering[2]", "got nan");
    a = {};
    a.mie_absorption.x = kInf;
    expect_rejected(a, "mie_absorption[0]", "got inf");
    a = {};
    a.mie_absorption.x = 2.0;
    expect_rejected(a, "mie_absorption[0]", "in [0, 1] 1/m, got 2");
    a = {};
    a.mie_g = 1.0;
    expect_rejected(a, "mie_g", "|g| < 1");
    a.mie_g = -1.2;
    expect_rejected(a, "mie_g", "got -1.2");
    a.mie_g = kNaN;
    expect_rejected(a, "mie_g", "got nan");
    a = {};
    a.rayleigh_scale_height_m = 0.0;
    expect_rejected(a, "rayleigh_scale_height_m", "got 0");
    a = {};
    a.mie_scale_height_m = -5.0;
    expect_rejected(a, "mie_scale_height_m", "got -5");
    a = {};
    a.planet_radius_m = kNaN;
    expect_rejected(a, "planet_radius_m", "got nan");
    a = {};
    a.atmosphere_radius_m = a.planet_radius_m;
    expect_rejected(a, "atmosphere_radius_m", "above planet_radius_m");
    a = {};
    a.sun_irradiance.y = -1.0;
    expect_rejected(a, "sun_irradiance[1]", "got -1");
}

TEST(AtmosphereValidate, NamesEachBadOzoneAndGroundField) {
    Atmosphere a;
    a.ozone_absorption.x = kNaN;
    expect_rejected(a, "ozone_absorption[0]", "in [0, 1] 1/m, got nan");
    a = {};
    a.ozone_absorption.z = -1e-7;
    expect_rejected(a, "ozone_absorption[2]", "got -1e-07");
    a = {};
    a.ozone_absorption.y = 2.0;
    expect_rejected(a, "ozone_absorption[1]", "got 2");
    a = {};
    a.ozone_center_altitude_m = kNaN;
    expect_rejected(a, "ozone_center_altitude_m", "in [0, 1e+06] m, got nan");
    a.ozone_center_altitude_m = -1.0;
    expect_rejected(a, "ozone_center_altitude_m", "got -1");
    a.ozone_center_altitude_m = 2e6;
    expect_rejected(a, "ozone_center_altitude_m", "got 2e+06");
    a = {};
    a.ozone_width_m = 0.0;
    expect_rejected(a, "ozone_width_m", "in [1, 1e+06] m, got 0");
    a.ozone_width_m = -30000.0;
    expect_rejected(a, "ozone_width_m", "got -30000");
    a.ozone_width_m = kInf;
    expect_rejected(a, "ozone_width_m", "got inf");
    a = {};
    a.ground_albedo.y = 1.5;
    expect_rejected(a, "ground_albedo[1]", "in [0, 1] (Lambertian albedo), got 1.5");
    a.ground_albedo.y = -0.1;
    expect_rejected(a, "ground_albedo[1]", "got -0.1");
    a = {};
    a.ground_albedo.z = kNaN;
    expect_rejected(a, "ground_albedo[2]", "got nan");
    // The bounds themselves are valid: no ozone, a layer centred at sea level, black and white
    // ground, the narrowest and widest layers.
    a = {};
    a.ozone_absorption = glm::dvec3(0.0);
    a.ozone_center_altitude_m = 0.0;
    a.ozone_width_m = 1.0;
    a.ground_albedo = glm::dvec3(0.0, 1.0, 0.0);
    EXPECT_FALSE(aerial::validate(a).has_value());
    a.ozone_center_altitude_m = 1e6;
    a.ozone_width_m = 1e6;
    EXPECT_FALSE(aerial::validate(a).has_value());
}

TEST(AtmosphereValidate, GroundAlbedoMessageWhole) {
    Atmosphere a;
    a.ground_albedo = {0.1, 1.5, 0.1};
    const auto error = aerial::validate(a);
    ASSERT_TRUE(error.has_value());
    EXPECT_EQ(error->field, "ground_albedo[1]");
    EXPECT_EQ(error->message,
              "aerial::validate(): ground_albedo[1]: expected a value in [0, 1] (Lambertian "
              "albedo), got 1.5");
}

TEST(AtmosphereEquality, ComparesEveryNewField) {
    const Atmosphere a;
    EXPECT_TRUE(a == Atmosphere{});
    std::vector<std::pair<const char*, Atmosphere>> changed;
    auto with = [&](const char* what, auto edit) {
        Atmosphere b = a;
        edit(b);
        changed.emplace_back(what, b);
    };
    with("ozone_absorption", [](Atmosphere& x) { x.ozone_absorption.z = 0.086e-6; });
    with("ozone_center_altitude_m", [](Atmosphere& x) { x.ozone_center_altitude_m += 1.0; });
    with("ozone_width_m", [](Atmosphere& x) { x.ozone_width_m += 1.0; });
    with("ground_albedo", [](Atmosphere& x) { x.ground_albedo.x = 0.2; });
    for (const auto& [what, b] : changed) {
        EXPECT_FALSE(a == b) << what;
        EXPECT_TRUE(a != b) << what;
    }
}

// The one message style, pinned whole: "aerial::FUNCTION(): FIELD: expected ..., got ...".
TEST(AtmosphereValidate, MessageIsFunctionFieldExpectedGot) {
    Atmosphere a;
    a.mie_g = 1.5;
    const auto error = aerial::validate(a);
    ASSERT_TRUE(error.has_value());
    EXPECT_EQ(error->field, "mie_g");
    EXPECT_EQ(error->message,
              "aerial::validate(): mie_g: expected |g| < 1 (g > 0 scatters forwards), got 1.5");
    // A constructor reports the validation of what it built as its own error.
    const auto dirty = aerial::atmosphere_with_air_pollution(2.0);
    ASSERT_FALSE(dirty.ok());
    EXPECT_EQ(dirty.error().message,
              "aerial::atmosphere_with_air_pollution(): pollution: expected a value in [0, 1], "
              "got 2");
    const auto from_pollution = aerial::atmosphere_with_air_pollution(0.5, a);
    ASSERT_FALSE(from_pollution.ok());
    EXPECT_EQ(from_pollution.error().message,
              "aerial::atmosphere_with_air_pollution(): mie_g: expected |g| < 1 (g > 0 scatters "
              "forwards), got 1.5");
}

TEST(AtmospherePresets, EarthHasTheDesignValues) {
    const auto a = aerial::atmosphere_preset("earth");
    ASSERT_TRUE(a.ok());
    EXPECT_DOUBLE_EQ(a->rayleigh_scattering.x, 5.802e-6);
    EXPECT_DOUBLE_EQ(a->rayleigh_scattering.y, 13.558e-6);
    EXPECT_DOUBLE_EQ(a->rayleigh_scattering.z, 33.1e-6);
    EXPECT_DOUBLE_EQ(a->mie_scattering.y, 3.996e-6);
    EXPECT_DOUBLE_EQ(a->mie_absorption.y, 0.0);
    EXPECT_DOUBLE_EQ(a->mie_g, 0.8);
    EXPECT_DOUBLE_EQ(a->rayleigh_scale_height_m, 8000.0);
    EXPECT_DOUBLE_EQ(a->mie_scale_height_m, 1200.0);
    EXPECT_DOUBLE_EQ(a->planet_radius_m, 6360e3);
    EXPECT_DOUBLE_EQ(a->atmosphere_radius_m, 6420e3);
    EXPECT_DOUBLE_EQ(a->sun_irradiance.z, 1.0);
    // Bruneton 2017 (ozone also Hillaire 2020's): ground albedo 0.1, ozone from 10 to 40 km.
    EXPECT_EQ(a->ground_albedo, glm::dvec3(0.1));
    EXPECT_EQ(a->ozone_absorption, glm::dvec3(0.650e-6, 1.881e-6, 0.085e-6));
    EXPECT_EQ(a->ozone_center_altitude_m, 25000.0);
    EXPECT_EQ(a->ozone_width_m, 30000.0);
    EXPECT_TRUE(*a == Atmosphere{}) << "the struct's defaults are the earth preset";
}

TEST(AtmospherePresets, EarthBasedPresetsKeepItsOzoneAndGround) {
    const Atmosphere earth;
    for (const char* name : {"hp2002", "hazy", "foggy"}) {
        const auto a = aerial::atmosphere_preset(name);
        ASSERT_TRUE(a.ok()) << name;
        EXPECT_EQ(a->ozone_absorption, earth.ozone_absorption) << name;
        EXPECT_EQ(a->ozone_center_altitude_m, earth.ozone_center_altitude_m) << name;
        EXPECT_EQ(a->ozone_width_m, earth.ozone_width_m) << name;
        EXPECT_EQ(a->ground_albedo, earth.ground_albedo) << name;
    }
}

TEST(AtmospherePresets, MarsHasNoOzoneAndItsOwnGround) {
    const auto a = aerial::atmosphere_preset("mars");
    ASSERT_TRUE(a.ok());
    EXPECT_EQ(a->ozone_absorption, glm::dvec3(0.0));
    EXPECT_EQ(a->ground_albedo, glm::dvec3(0.25));
}

TEST(AtmosphereOzone, DensityIsATentAroundTheCentre) {
    const Atmosphere a;  // earth: centre 25 km, width 30 km
    EXPECT_EQ(a.ozone_density(25000.0), 1.0);
    EXPECT_EQ(a.ozone_density(17500.0), 0.5);
    EXPECT_EQ(a.ozone_density(32500.0), 0.5);
    EXPECT_NEAR(a.ozone_density(24000.0), 1.0 - 1000.0 / 15000.0, 1e-15);
    EXPECT_EQ(a.ozone_density(10000.0), 0.0) << "lower edge";
    EXPECT_EQ(a.ozone_density(40000.0), 0.0) << "upper edge";
    for (double h : {0.0, -500.0, 9999.0, 40001.0, 60000.0, 1e9, -kInf, kInf, kNaN}) {
        EXPECT_EQ(a.ozone_density(h), 0.0) << h;
    }
    EXPECT_GT(a.ozone_density(10001.0), 0.0);
    EXPECT_GT(a.ozone_density(39999.0), 0.0);
    // A layer centred at sea level reaches the ground.
    Atmosphere low;
    low.ozone_center_altitude_m = 0.0;
    low.ozone_width_m = 2000.0;
    EXPECT_EQ(low.ozone_density(0.0), 1.0);
    EXPECT_EQ(low.ozone_density(500.0), 0.5);
    EXPECT_EQ(low.ozone_density(-500.0), 0.5);
    EXPECT_EQ(low.ozone_density(1000.0), 0.0);
}

TEST(AtmospherePresets, UnknownNameListsTheKnownOnes) {
    const auto a = aerial::atmosphere_preset("venus");
    ASSERT_FALSE(a.ok());
    EXPECT_EQ(a.error().field, "preset");
    EXPECT_EQ(a.error().message,
              "aerial::atmosphere_preset(): preset: expected one of earth, hp2002, hazy, foggy, "
              "mars, got 'venus'");
}

TEST(Hp2002, RayleighFromTheTalkFormulaMatchesItsPublishedValues) {
    // 6.95e-6, 1.18e-5, 2.44e-5 /m at 650, 570, 475 nm (the issue's figures, 3 digits).
    EXPECT_NEAR(aerial::rayleigh_scattering_from_wavelength(650e-9), 6.95e-6, 0.01e-6);
    EXPECT_NEAR(aerial::rayleigh_scattering_from_wavelength(570e-9), 1.18e-5, 0.01e-5);
    EXPECT_NEAR(aerial::rayleigh_scattering_from_wavelength(475e-9), 2.44e-5, 0.01e-5);
    // lambda^-4.
    const double ratio = aerial::rayleigh_scattering_from_wavelength(475e-9) /
                         aerial::rayleigh_scattering_from_wavelength(650e-9);
    EXPECT_NEAR(ratio, std::pow(650.0 / 475.0, 4.0), 1e-12);
    const auto hp = aerial::atmosphere_preset("hp2002");
    ASSERT_TRUE(hp.ok());
    EXPECT_DOUBLE_EQ(hp->rayleigh_scattering.y,
                     aerial::rayleigh_scattering_from_wavelength(570e-9));
}

TEST(Hp2002, MieFromTurbidityHasTheOpticalDepthTurbidityMeans) {
    // T = (tau_R + tau_M) / tau_R: at T = 2 aerosol and air have about equal vertical optical
    // depth. This pins the CGS -> SI conversion (a literal SI reading is 100x too large).
    const auto mie = aerial::mie_scattering_from_turbidity(2.0);
    ASSERT_TRUE(mie.ok());
    const double tau_mie = mie->y * 1200.0;
    const double tau_rayleigh = aerial::rayleigh_scattering_from_wavelength(570e-9) * 8000.0;
    EXPECT_GT(tau_mie / tau_rayleigh, 0.7);
    EXPECT_LT(tau_mie / tau_rayleigh, 1.3);
    // Closed form at 570 nm: 0.434 c pi (2 pi / lambda)^2 K, lambda in cm, times 100.
    const double c = (0.6544 * 2.0 - 0.6510) * 1e-16;
    const double k = 2.0 * aerial::kPi / 570e-7;
    EXPECT_NEAR(mie->y, 0.434 * c * aerial::kPi * k * k * 0.679 * 100.0, 1e-18);
    // Grows with turbidity, bluer than grey but nearly so (K falls slower than lambda^-2 grows).
    EXPECT_GT(mie->z, mie->x);
    EXPECT_GT(aerial::mie_scattering_from_turbidity(6.0)->y, mie->y);
}

TEST(Hp2002, RejectsTurbidityWherePreethamsFitTurnsUnphysical) {
    for (double t : {1.29, 1.0, 0.5, -3.0, kNaN, 100.0}) {
        const auto mie = aerial::mie_scattering_from_turbidity(t);
        ASSERT_FALSE(mie.ok()) << t;
        EXPECT_EQ(mie.error().field, "turbidity");
        EXPECT_EQ(mie.error().message.rfind("aerial::mie_scattering_from_turbidity(): turbidity: "
                                            "expected a value in [1.3, 64] ",
                                            0),
                  0u)
            << mie.error().message;
    }
    EXPECT_TRUE(aerial::mie_scattering_from_turbidity(1.3).ok());
    EXPECT_FALSE(aerial::atmosphere_from_turbidity(1.0).ok());
}

TEST(AtmosphereConstructors, VisibilityFollowsKoschmieder) {
    for (double v : {500.0, 5000.0, 40000.0, 200000.0}) {
        const auto a = aerial::atmosphere_from_visibility(v);
        ASSERT_TRUE(a.ok()) << v << ": " << a.error().message;
        EXPECT_NEAR(a->extinction().y, 3.912 / v, 1e-15) << v;
        EXPECT_DOUBLE_EQ(a->mie_scattering.x, a->mie_scattering.z) << "Mie stays grey";
    }
    const auto absorbing = aerial::atmosphere_from_visibility(10000.0, Atmosphere{}, 0.8);
    ASSERT_TRUE(absorbing.ok());
    EXPECT_NEAR(absorbing->mie_absorption.y / absorbing->mie_extinction().y, 0.2, 1e-12);
}

TEST(AtmosphereConstructors, VisibilityBeyondCleanAirIsRejected) {
    const auto a = aerial::atmosphere_from_visibility(400000.0);
    ASSERT_FALSE(a.ok());
    EXPECT_EQ(a.error().field, "visibility_m");
    EXPECT_NE(a.error().message.find("clean air"), std::string::npos);
    EXPECT_FALSE(aerial::atmosphere_from_visibility(-1.0).ok());
    EXPECT_FALSE(aerial::atmosphere_from_visibility(kNaN).ok());
    EXPECT_EQ(aerial::atmosphere_from_visibility(1000.0, Atmosphere{}, 0.0).error().field,
              "mie_albedo");
}

TEST(AtmosphereConstructors, GroundHazeMeetsBothVisibilities) {
    aerial::GroundHaze haze;
    haze.visibility_in_layer_m = 800.0;
    haze.layer_thickness_m = 300.0;
    haze.visibility_aloft_m = 30000.0;
    const auto a = aerial::atmosphere_with_ground_haze(haze);
    ASSERT_TRUE(a.ok()) << a.error().message;
    auto extinction_g_at = [&](double h) {
        return a->rayleigh_scattering.y * std::exp(-h / a->rayleigh_scale_height_m) +
               a->mie_extinction().y * std::exp(-h / a->mie_scale_height_m);
    };
    EXPECT_NEAR(3.912 / extinction_g_at(0.0), 800.0, 1e-6);
    EXPECT_NEAR(3.912 / extinction_g_at(300.0), 30000.0, 1e-3);
    EXPECT_GT(3.912 / extinction_g_at(1000.0), 30000.0) << "the haze keeps thinning above";
}

TEST(AtmosphereConstructors, GroundHazeRejectsAloftNotClearerThanTheLayer) {
    aerial::GroundHaze haze;
    haze.visibility_in_layer_m = 5000.0;
    haze.visibility_aloft_m = 4000.0;
    const auto a = aerial::atmosphere_with_ground_haze(haze);
    ASSERT_FALSE(a.ok());
    EXPECT_EQ(a.error().field, "visibility_aloft_m");
    haze.visibility_aloft_m = 1e9;
    EXPECT_EQ(aerial::atmosphere_with_ground_haze(haze).error().field, "visibility_aloft_m");
    haze = {};
    haze.layer_thickness_m = 0.0;
    EXPECT_EQ(aerial::atmosphere_with_ground_haze(haze).error().field, "layer_thickness_m");
}

TEST(AtmosphereConstructors, AirPollutionAddsAbsorbingYellowingAerosol) {
    const Atmosphere base;
    const auto clean = aerial::atmosphere_with_air_pollution(0.0, base);
    ASSERT_TRUE(clean.ok());
    EXPECT_EQ(clean->mie_extinction(), base.mie_extinction());
    const auto dirty = aerial::atmosphere_with_air_pollution(1.0, base);
    ASSERT_TRUE(dirty.ok());
    EXPECT_GT(dirty->mie_extinction().y, base.mie_extinction().y);
    EXPECT_GT(dirty->mie_absorption.z, dirty->mie_absorption.x) << "absorbs more in blue";
    EXPECT_EQ(aerial::atmosphere_with_air_pollution(1.5, base).error().field, "pollution");
}

TEST(AtmosphereJson, RoundTripsEveryPreset) {
    for (const auto& name : aerial::atmosphere_preset_names()) {
        const auto a = aerial::atmosphere_preset(name);
        const auto back = aerial::atmosphere_from_json(aerial::to_json(*a));
        ASSERT_TRUE(back.ok()) << name << ": " << back.error().message;
        EXPECT_EQ(back->rayleigh_scattering, a->rayleigh_scattering) << name;
        EXPECT_EQ(back->mie_scattering, a->mie_scattering) << name;
        EXPECT_EQ(back->mie_absorption, a->mie_absorption) << name;
        EXPECT_EQ(back->mie_g, a->mie_g) << name;
        EXPECT_EQ(back->mie_scale_height_m, a->mie_scale_height_m) << name;
        EXPECT_EQ(back->ozone_absorption, a->ozone_absorption) << name;
        EXPECT_EQ(back->ozone_center_altitude_m, a->ozone_center_altitude_m) << name;
        EXPECT_EQ(back->ozone_width_m, a->ozone_width_m) << name;
        EXPECT_EQ(back->atmosphere_radius_m, a->atmosphere_radius_m) << name;
        EXPECT_EQ(back->ground_albedo, a->ground_albedo) << name;
        EXPECT_EQ(back->sun_irradiance, a->sun_irradiance) << name;
        EXPECT_TRUE(*back == *a) << name;
        EXPECT_EQ(aerial::to_json(*back), aerial::to_json(*a)) << name;
    }
}

TEST(AtmosphereJson, RoundTripsOddValuesOfTheNewFields) {
    Atmosphere a;
    a.ground_albedo = {0.3, 1.0 / 3.0, 0.0};
    a.ozone_absorption = {1.0 / 7.0 * 1e-6, 0.0, 2.5e-6};
    a.ozone_center_altitude_m = 0.0;
    a.ozone_width_m = 12345.678901234567;
    const auto back = aerial::atmosphere_from_json(aerial::to_json(a));
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_TRUE(*back == a) << aerial::to_json(*back);
}

TEST(AtmosphereJson, MissingFieldsKeepEarthAndAbsorbersAndGroundDefaultToZero) {
    const auto a = aerial::atmosphere_from_json(R"({"mie_g": 0.5})");
    ASSERT_TRUE(a.ok());
    EXPECT_EQ(a->mie_g, 0.5);
    EXPECT_EQ(a->rayleigh_scattering, Atmosphere{}.rayleigh_scattering);
    EXPECT_EQ(a->mie_absorption, glm::dvec3(0.0));
    EXPECT_EQ(a->ozone_absorption, glm::dvec3(0.0)) << "no ozone unless the file gives it";
    EXPECT_EQ(a->ground_albedo, glm::dvec3(0.0)) << "a black ground unless the file gives it";
    // The layer's shape keeps earth's (it matters only once ozone_absorption is given).
    EXPECT_EQ(a->ozone_center_altitude_m, 25000.0);
    EXPECT_EQ(a->ozone_width_m, 30000.0);
    const auto empty = aerial::atmosphere_from_json("{}");
    ASSERT_TRUE(empty.ok());
    EXPECT_EQ(empty->ozone_absorption, glm::dvec3(0.0));
    EXPECT_EQ(empty->ground_albedo, glm::dvec3(0.0));
}

TEST(AtmosphereJson, ReadsTheNewFields) {
    const auto grey = aerial::atmosphere_from_json(
        R"({"ground_albedo": 0.3, "ozone_absorption": [0.65e-6, 1.881e-6, 0.085e-6],
            "ozone_center_altitude_m": 22000, "ozone_width_m": 20000})");
    ASSERT_TRUE(grey.ok()) << grey.error().message;
    EXPECT_EQ(grey->ground_albedo, glm::dvec3(0.3)) << "a number is every channel";
    EXPECT_EQ(grey->ozone_absorption, Atmosphere{}.ozone_absorption);
    EXPECT_EQ(grey->ozone_center_altitude_m, 22000.0);
    EXPECT_EQ(grey->ozone_width_m, 20000.0);
    const auto coloured = aerial::atmosphere_from_json(R"({"ground_albedo": [0.2, 0.15, 0.1]})");
    ASSERT_TRUE(coloured.ok()) << coloured.error().message;
    EXPECT_EQ(coloured->ground_albedo, glm::dvec3(0.2, 0.15, 0.1));
    const auto integer = aerial::atmosphere_from_json(R"({"ground_albedo": 1})");
    ASSERT_TRUE(integer.ok()) << integer.error().message;
    EXPECT_EQ(integer->ground_albedo, glm::dvec3(1.0));
    // The preset written out reads back as the preset, ozone and ground included.
    const auto earth = aerial::atmosphere_from_json(aerial::to_json(Atmosphere{}));
    ASSERT_TRUE(earth.ok());
    EXPECT_TRUE(*earth == Atmosphere{});
}

TEST(AtmosphereJson, ErrorsNameTheField) {
    struct Case {
        const char* json;
        const char* field;
        const char* fragment;
    } cases[] = {
        {R"({"mie_g": 0.5, "colour": 1})", "colour", "not an atmosphere field"},
        {R"({"mie_g": "high"})", "mie_g", "expected a number, got string \"high\""},
        {R"({"rayleigh_scattering": [1e-6, 2e-6]})", "rayleigh_scattering", "array of 3"},
        {R"({"mie_scattering": [1e-6, "x", 2e-6]})", "mie_scattering[1]", "expected a number"},
        {R"({"rayleigh_scattering": [1e-6, -2e-6, 3e-6]})", "rayleigh_scattering[1]",
         "in [0, 1] 1/m, got -2e-06"},
        {R"({"mie_g": 1.0})", "mie_g", "|g| < 1"},
        {R"({"planet_radius_m": 7000000})", "atmosphere_radius_m", "above planet_radius_m"},
        {R"({"ground_albedo": "grey"})", "ground_albedo",
         "expected a number (every channel) or an array of 3 numbers (R, G, B), got \"grey\""},
        {R"({"ground_albedo": [0.1, 0.2]})", "ground_albedo", "got [0.1,0.2]"},
        {R"({"ground_albedo": {"r": 0.1}})", "ground_albedo", "an array of 3 numbers"},
        {R"({"ground_albedo": true})", "ground_albedo", "got true"},
        {R"({"ground_albedo": [0.1, null, 0.1]})", "ground_albedo[1]", "expected a number"},
        {R"({"ground_albedo": 1.5})", "ground_albedo[0]", "in [0, 1] (Lambertian albedo), got 1.5"},
        {R"({"ground_albedo": [0.1, 0.1, -0.2]})", "ground_albedo[2]", "got -0.2"},
        {R"({"ozone_absorption": 1e-6})", "ozone_absorption", "array of 3"},
        {R"({"ozone_absorption": [1e-6, -1e-6, 0]})", "ozone_absorption[1]",
         "in [0, 1] 1/m, got -1e-06"},
        {R"({"ozone_center_altitude_m": -10})", "ozone_center_altitude_m", "got -10"},
        {R"({"ozone_center_altitude_m": "high"})", "ozone_center_altitude_m", "expected a number"},
        {R"({"ozone_width_m": 0})", "ozone_width_m", "in [1, 1e+06] m, got 0"},
        {R"({"ozone": 1})", "ozone", "not an atmosphere field"},
        {R"({"mie_g": 1e999})", "json", "number overflow"},
        {R"([1, 2, 3])", "json", "expected an object, got array"},
        {R"({"mie_g": 0.5,})", "json", "parse error"},
        {"", "json", "parse error"},
    };
    for (const auto& c : cases) {
        const auto a = aerial::atmosphere_from_json(c.json);
        ASSERT_FALSE(a.ok()) << c.json;
        EXPECT_EQ(a.error().field, c.field) << c.json << " -> " << a.error().message;
        EXPECT_EQ(a.error().message.rfind(
                      std::string("aerial::atmosphere_from_json(): ") + c.field + ": ", 0),
                  0u)
            << a.error().message;
        EXPECT_NE(a.error().message.find(c.fragment), std::string::npos)
            << c.json << " -> " << a.error().message;
        EXPECT_EQ(a.error().message.find('\n'), std::string::npos) << "one line: " << c.json;
    }
}

TEST(AtmosphereJson, MissingFileIsNamed) {
    const auto a = aerial::load_atmosphere_json("/nonexistent/dir/air.json");
    ASSERT_FALSE(a.ok());
    EXPECT_EQ(a.error().field, "/nonexistent/dir/air.json");
    EXPECT_EQ(a.error().message,
              "aerial::load_atmosphere_json(): /nonexistent/dir/air.json: cannot open the "
              "atmosphere file");
}

}  // namespace
