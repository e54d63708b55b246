#include "world.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>

#include <glm/geometric.hpp>

namespace sample {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;
constexpr int kTextureSize = 256;
/// Ground reflectance over pi (the lit colour is albedo x irradiance, radiance needs the 1/pi);
/// the texture (mean about 0.45) carries the colour.
constexpr float kGroundAlbedo = float(0.3 / kPi);

double smoothstep(double a, double b, double x) {
    const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

/// Grass, earth and rock in tiling value noise: 256² texels, repeating every 250 m.
std::shared_ptr<aerial::scene::Texture> ground_texture(std::uint32_t seed) {
    auto texture = std::make_shared<aerial::scene::Texture>();
    texture->width = texture->height = kTextureSize;
    texture->rgb.resize(std::size_t(kTextureSize) * kTextureSize * 3);
    // Tiling noise: a lattice of period `cells` on the texture.
    const auto lattice = [seed](int ix, int iy, int cells) {
        ix = ((ix % cells) + cells) % cells;
        iy = ((iy % cells) + cells) % cells;
        std::uint32_t h = std::uint32_t(ix) * 0x8da6b343u ^ std::uint32_t(iy) * 0xd8163841u ^
                          (seed + std::uint32_t(cells)) * 0xcb1ab31fu;
        h ^= h >> 16;
        h *= 0x85ebca6bu;
        h ^= h >> 13;
        return double(h & 0xffffff) / double(0x1000000);
    };
    const auto noise = [&](double u, double v, int cells) {
        const double x = u * cells, y = v * cells;
        const int ix = int(std::floor(x)), iy = int(std::floor(y));
        const double fx = x - ix, fy = y - iy;
        const double sx = fx * fx * (3 - 2 * fx), sy = fy * fy * (3 - 2 * fy);
        const double a = lattice(ix, iy, cells), b = lattice(ix + 1, iy, cells);
        const double c = lattice(ix, iy + 1, cells), d = lattice(ix + 1, iy + 1, cells);
        return (a + (b - a) * sx) * (1 - sy) + (c + (d - c) * sx) * sy;
    };
    for (int y = 0; y < kTextureSize; ++y) {
        for (int x = 0; x < kTextureSize; ++x) {
            const double u = (x + 0.5) / kTextureSize, v = (y + 0.5) / kTextureSize;
            const double patches =
                0.5 * noise(u, v, 4) + 0.3 * noise(u, v, 8) + 0.2 * noise(u, v, 16);
            const double grain = 0.6 * noise(u, v, 64) + 0.4 * noise(u, v, 128);
            const glm::dvec3 grass{0.30, 0.42, 0.16}, dry{0.50, 0.46, 0.28}, rock{0.52, 0.50, 0.47};
            glm::dvec3 c = glm::mix(grass, dry, smoothstep(0.45, 0.65, patches));
            c = glm::mix(c, rock, smoothstep(0.68, 0.8, patches));
            c *= 0.8 + 0.4 * grain;
            for (int ch = 0; ch < 3; ++ch) {
                texture
                    ->rgb[(std::size_t(y) * kTextureSize + std::size_t(x)) * 3 + std::size_t(ch)] =
                    std::uint8_t(std::clamp(c[ch], 0.0, 1.0) * 255.0 + 0.5);
            }
        }
    }
    return texture;
}

/// Days since 1970-01-01 of a proleptic Gregorian date, and back (H. Hinnant's algorithms).
long days_from_civil(int y, int m, int d) {
    y -= m <= 2;
    const long era = (y >= 0 ? y : y - 399) / 400;
    const long yoe = y - era * 400;
    const long doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
    const long doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    return era * 146097 + doe - 719468;
}

void civil_from_days(long z, int& y, int& m, int& d) {
    z += 719468;
    const long era = (z >= 0 ? z : z - 146096) / 146097;
    const long doe = z - era * 146097;
    const long yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    const long doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    const long mp = (5 * doy + 2) / 153;
    d = int(doy - (153 * mp + 2) / 5 + 1);
    m = int(mp < 10 ? mp + 3 : mp - 9);
    y = int(yoe + era * 400 + (m <= 2));
}

}  // namespace

aerial::UtcDateTime utc_at(const SunSchedule& schedule, double minutes) {
    const double whole_days = std::floor(minutes / 1440.0);
    double rest = minutes - whole_days * 1440.0;
    aerial::UtcDateTime time;
    civil_from_days(days_from_civil(schedule.year, schedule.month, schedule.day) + long(whole_days),
                    time.year, time.month, time.day);
    time.hour = std::min(23, int(rest / 60.0));
    rest -= time.hour * 60.0;
    time.minute = std::min(59, int(rest));
    time.second = std::clamp((rest - time.minute) * 60.0, 0.0, 59.999);
    return time;
}

namespace {

/// The sun's elevation at `minutes` (UTC) for the schedule's place (valid: make_sun_schedule
/// checked it), radians.
double sun_elevation_at(const SunSchedule& schedule, double minutes) {
    const auto sun = aerial::sun_position(utc_at(schedule, minutes), schedule.latitude_rad,
                                          schedule.longitude_rad);
    return sun ? sun->elevation_rad : 0.0;
}

/// When the evening sun's centre sinks `depression_rad` below the horizon, by bisection between
/// noon and solar midnight (the sun sinks all the way between them); none where it stays higher.
std::optional<double> evening_utc_min(const SunSchedule& schedule, double depression_rad) {
    double high = schedule.noon_utc_min, low = schedule.noon_utc_min + 720.0;
    if (sun_elevation_at(schedule, low) > -depression_rad) return std::nullopt;
    for (int i = 0; i < 40; ++i) {  // 720 min / 2^40: well below a second
        const double mid = 0.5 * (high + low);
        (sun_elevation_at(schedule, mid) > -depression_rad ? high : low) = mid;
    }
    return 0.5 * (high + low);
}

}  // namespace

aerial::Result<SunSchedule> make_sun_schedule(int year, int month, int day, double latitude_rad,
                                              double longitude_rad) {
    SunSchedule schedule;
    schedule.year = year;
    schedule.month = month;
    schedule.day = day;
    schedule.latitude_rad = latitude_rad;
    schedule.longitude_rad = longitude_rad;
    auto events = aerial::solar_events(year, month, day, latitude_rad, longitude_rad);
    if (!events) {
        aerial::Error e = events.error();
        if (e.field == "year" || e.field == "month" || e.field == "day") e.field = "date";
        return e;
    }
    if (events->polar_night) {
        return aerial::Error{"latitude",
                             "the sun does not rise on that date at this latitude (polar night)"};
    }
    schedule.noon_utc_min = events->solar_noon_utc_min;
    if (!events->sunset_utc_min) {  // polar day
        schedule.end_utc_min = schedule.noon_utc_min + kPolarDayScriptMinutes;
        schedule.sunset_utc_min = schedule.night_utc_min = schedule.end_utc_min;
        return schedule;
    }
    schedule.sunset_utc_min = *events->sunset_utc_min;
    // White nights: the sun's lowest point, solar midnight.
    schedule.end_utc_min =
        evening_utc_min(schedule, kScriptEndDepressionRad).value_or(schedule.noon_utc_min + 720.0);
    schedule.night_utc_min =
        evening_utc_min(schedule, kNightDepressionRad).value_or(schedule.end_utc_min);
    return schedule;
}

SunSchedule default_sun_schedule() {
    return make_sun_schedule(kDefaultYear, kDefaultMonth, kDefaultDay,
                             kDefaultLatitudeDeg * kDegree, kDefaultLongitudeDeg * kDegree)
        .value();  // a valid date and place
}

double script_utc_min(const SunSchedule& schedule, double day) {
    day = std::clamp(day, 0.0, 1.0);
    // (script position, UTC) where each part of the script ends: noon held, the afternoon,
    // twilight, the night.
    struct Knot {
        double day, utc_min;
    };
    const Knot knots[] = {{0.15, schedule.noon_utc_min},
                          {0.6, schedule.sunset_utc_min},
                          {0.82, schedule.night_utc_min},
                          {1.0, schedule.end_utc_min}};
    if (day <= knots[0].day) return knots[0].utc_min;
    Knot from = knots[0];
    for (std::size_t i = 1; i < std::size(knots); ++i) {
        // A part of no length (the last knots at the end) gives its share to the one before.
        const bool last = i + 1 == std::size(knots) || knots[i].utc_min >= schedule.end_utc_min;
        const Knot to = last ? knots[std::size(knots) - 1] : knots[i];
        if (day <= to.day || last) {
            double u = (day - from.day) / (to.day - from.day);
            if (i == 1) u = smoothstep(0.0, 1.0, u);  // the afternoon: slow near noon and sunset
            return from.utc_min + (to.utc_min - from.utc_min) * u;
        }
        from = to;
    }
    return schedule.end_utc_min;
}

void place_sky(FlightState& state, const SunSchedule& schedule, double utc_min) {
    state.utc_min = utc_min;
    const aerial::UtcDateTime time = utc_at(schedule, utc_min);
    // The schedule's place is valid (make_sun_schedule checked it).
    const auto sun = aerial::sun_position(time, schedule.latitude_rad, schedule.longitude_rad);
    if (!sun) return;
    state.sun_elevation_rad = sun->elevation_rad;
    state.sun_azimuth_rad = sun->azimuth_rad;
    auto moon = aerial::moon_position(time, schedule.latitude_rad, schedule.longitude_rad);
    state.moon = moon ? std::optional<aerial::MoonPosition>(*moon) : std::nullopt;
    // Local apparent solar time: UTC + longitude (4 minutes a degree) + equation of time.
    const double local_min =
        utc_min + schedule.longitude_rad / kDegree * 4.0 + sun->equation_of_time_min;
    state.clock_hours = std::fmod(std::fmod(local_min, 1440.0) + 1440.0, 1440.0) / 60.0;
}

World build_world(const WorldOptions& options) {
    World world;
    world.options = options;
    world.terrain.seed = options.seed;
    world.terrain.amplitude = 900.0;
    world.terrain.feature_size = 6000.0;
    world.terrain.base = 20.0;
    world.root = aerial::scene::make_group("world");
    world.root->add(aerial::scene::make_sky_dome());
    world.root->add(aerial::scene::make_sun());
    auto terrain_group = aerial::scene::make_group("terrain");
    std::shared_ptr<const aerial::scene::Texture> texture = ground_texture(options.seed);
    const int tiles = std::max(1, int(std::lround(options.size_m / options.tile_m)));
    const double origin = -0.5 * tiles * options.tile_m;
    for (int j = 0; j < tiles; ++j) {
        for (int i = 0; i < tiles; ++i) {
            aerial::scene::HeightfieldSpec spec;
            spec.origin_x = origin + i * options.tile_m;
            spec.origin_y = origin + j * options.tile_m;
            spec.size = options.tile_m;
            spec.resolution = options.tile_resolution;
            spec.texture_repeat = 250.0;
            auto mesh = aerial::scene::heightfield_mesh(
                spec, [&](double x, double y) { return ground_height(world, x, y); });
            world.vertices += mesh->vertex_count();
            // Albedo: the texture carries the colour; this scales it to a ground reflectance.
            terrain_group->add(aerial::scene::make_terrain_tile(
                "tile " + std::to_string(i) + " " + std::to_string(j),
                std::make_shared<const aerial::scene::MeshData>(std::move(mesh.value())), texture,
                glm::vec3(kGroundAlbedo)));
            ++world.tiles;
        }
    }
    world.root->add(std::move(terrain_group));
    return world;
}

double ground_height(const World& world, double x, double y) {
    return aerial::scene::procedural_height(world.terrain, x, y);
}

namespace {

/// In the night part of the script the view turns from the path towards the moon (when it is
/// up), keeping it 10 degrees above the centre of the frame, over the terrain.
constexpr double kNightLookStart = 0.8, kNightLookEnd = 0.92;

void look_at_the_moon(FlightState& s, double weight) {
    if (!s.moon || s.moon->elevation_rad < 0.0 || !(weight > 0.0)) return;
    // The shortest turn from the path's heading to the moon's azimuth.
    const double turn = std::remainder(s.moon->azimuth_rad - s.heading_rad, 2.0 * kPi);
    s.heading_rad += weight * turn;
    const double pitch = std::clamp(s.moon->elevation_rad - 0.17, -0.09, 0.3);
    s.pitch_rad += weight * (pitch - s.pitch_rad);
}

}  // namespace

FlightState flight_at(const World& world, double t, const SunSchedule& schedule) {
    t = std::clamp(t, 0.0, 1.0);
    FlightState s;
    // North from the south edge, weaving, turning west in the second half; the path scales with
    // the world (12 km over the default 16 km).
    const double scale = world.options.size_m / WorldOptions{}.size_m;
    const double heading = -0.7 * smoothstep(0.35, 1.0, t);
    s.heading_rad = heading + 0.15 * std::sin(6.0 * t);
    double x = 0.0, y = -6500.0 * scale;
    const int steps = 200;
    for (int i = 0; i < steps; ++i) {  // integrate the heading along the path
        const double u = t * (i + 0.5) / steps;
        const double h = -0.7 * smoothstep(0.35, 1.0, u) + 0.15 * std::sin(6.0 * u);
        x += std::sin(h) * 12000.0 * scale * t / steps;
        y += std::cos(h) * 12000.0 * scale * t / steps;
    }
    s.x = x;
    s.y = y;
    s.altitude_agl = 250.0;
    // The highest ground 600 m ahead and below, so the flight clears the hills.
    double ground = ground_height(world, x, y);
    for (double d = 100.0; d <= 600.0; d += 100.0) {
        ground = std::max(ground, ground_height(world, x + std::sin(s.heading_rad) * d,
                                                y + std::cos(s.heading_rad) * d) -
                                      0.3 * d);
    }
    s.altitude_agl = 250.0 + (ground - ground_height(world, x, y));
    s.pitch_rad = -0.09;
    s.fog = t > 0.4 && t < 0.6;
    place_sky(s, schedule, script_utc_min(schedule, t));
    look_at_the_moon(s, smoothstep(kNightLookStart, kNightLookEnd, t));
    return s;
}

aerial::scene::Camera camera_for(const World& world, const FlightState& s, double aspect) {
    aerial::scene::Camera c;
    c.eye = {s.x, s.y, ground_height(world, s.x, s.y) + s.altitude_agl};
    const glm::dvec3 forward{std::sin(s.heading_rad) * std::cos(s.pitch_rad),
                             std::cos(s.heading_rad) * std::cos(s.pitch_rad),
                             std::sin(s.pitch_rad)};
    c.target = c.eye + forward * 1000.0;
    c.up = {0.0, 0.0, 1.0};
    c.fov_y_rad = 50.0 * kPi / 180.0;
    c.aspect = aspect;
    c.near_units = 5.0;
    c.far_units = 40000.0;
    return c;
}

namespace {

/// One light (the sun, or the moon as a dimmer sun) on the level grey card at
/// kLightingAltitudeM.
struct CardLight {
    glm::dvec3 direct{0.0};  ///< through the atmosphere, on a surface facing the light
    double elevation_rad = 0.0;
    glm::dvec3 sky{0.0};  ///< its skylight on level ground
    glm::dvec3 direct_on_card() const { return direct * std::max(std::sin(elevation_rad), 0.0); }
    glm::dvec3 on_card() const { return direct_on_card() + sky; }
};

aerial::SkyAmbientOptions ambient_options() {
    aerial::SkyAmbientOptions options;
    options.elevation_steps = 8;
    options.azimuth_steps = 16;
    return options;
}

aerial::Result<CardLight> card_light(const aerial::Atmosphere& atmosphere, double elevation_rad) {
    CardLight light;
    light.elevation_rad = elevation_rad;
    light.direct =
        aerial::sun_irradiance_at_altitude(atmosphere, kLightingAltitudeM, elevation_rad);
    auto sky =
        aerial::sky_ambient(atmosphere, kLightingAltitudeM, elevation_rad, ambient_options());
    if (!sky) return sky.error();
    light.sky = *sky;
    return light;
}

/// The atmosphere of the preset, with the ground-fog layer when the state has it.
aerial::Result<aerial::Atmosphere> flight_atmosphere(const FlightState& s,
                                                     const std::string& preset) {
    auto atmosphere = aerial::atmosphere_preset(preset);
    if (!atmosphere || !s.fog) return atmosphere;
    aerial::GroundHaze haze;
    haze.visibility_in_layer_m = 1200.0;
    haze.layer_thickness_m = 500.0;
    haze.visibility_aloft_m = 15000.0;
    // Real fog looks bright from every side because light scatters many times in it: the
    // height model's higher orders carry that (docs/models.md), with the droplets' own g.
    return aerial::atmosphere_with_ground_haze(haze, *atmosphere);
}

/// frame_light's exposure: the day's rule (the cones, dazzled by a low sun) and night_exposure
/// (the rods), blended in log exposure by the rod share of the card's luminance.
aerial::Result<double> exposure_for(const FrameLight& light, const CardLight& sun) {
    aerial::ExposureOptions options;
    options.key = kExposureKey;
    options.max_gain = kExposureMaxGain;
    // The sun's direct light, and the rest of the card's (the skylight, the moon).
    double day =
        aerial::auto_exposure(sun.direct, sun.elevation_rad, light.card - sun.direct_on_card(),
                              light.atmosphere.sun_irradiance, options);
    const aerial::NightOptions night_options;
    const double sky_radiance = aerial::luminance(light.skylight) / kPi;
    if (sun.elevation_rad < 0.0 && sky_radiance > 0.0) {
        // After sunset the eye adapts to the sky: the day's exposure grows as the skylight fades,
        // holding the sky's mean radiance at night_exposure's max_sky_value (about where it is
        // at sunset), so that civil twilight reads (the afterglow over the sun, the Earth's
        // shadow opposite) instead of going black.
        day = std::max(day, night_options.max_sky_value / sky_radiance);
    }
    const double night = aerial::night_exposure(light.atmosphere, light.card, light.skylight,
                                                options, night_options);
    const double rods = aerial::rod_share(light.card_cd_m2);
    if (!(night > 0.0) || !(rods > 0.0)) return day;
    return std::exp((1.0 - rods) * std::log(day) + rods * std::log(night));
}

/// The Purkinje tint at the card's luminance: purkinje_shift of white (the rods' blue at
/// luminance 1) mixed with white by the rod share, in steps of kTintStep.
glm::dvec3 purkinje_tint(double card_cd_m2) {
    const double share = std::round(aerial::rod_share(card_cd_m2) / kTintStep) * kTintStep;
    const glm::dvec3 white(1.0);
    const double rods_only = 0.0;  // cd/m2: below the scotopic level
    return glm::mix(white, aerial::purkinje_shift(white, rods_only), share);
}

/// aerial::moonlight_fraction in steps of kMoonFractionStep e-folds.
double stepped_moon_fraction(const aerial::MoonPosition& moon) {
    const double fraction = aerial::moonlight_fraction(moon);
    if (!(fraction > 0.0)) return 0.0;
    return std::exp(std::round(std::log(fraction) / kMoonFractionStep) * kMoonFractionStep);
}

}  // namespace

aerial::Result<FrameLight> frame_light(const FlightState& s, const std::string& preset) {
    auto atmosphere = flight_atmosphere(s, preset);
    if (!atmosphere) return atmosphere.error();
    FrameLight light;
    light.atmosphere = *atmosphere;
    light.sun_dir = {std::cos(s.sun_elevation_rad) * std::sin(s.sun_azimuth_rad),
                     std::cos(s.sun_elevation_rad) * std::cos(s.sun_azimuth_rad),
                     std::sin(s.sun_elevation_rad)};
    // Light of level ground at a typical terrain altitude: each light through the atmosphere
    // (zero in the planet's shadow) and its skylight, which is also the terrain's ambient term.
    auto sun = card_light(light.atmosphere, s.sun_elevation_rad);
    if (!sun) return sun.error();
    CardLight moon;
    if (s.moon) {
        light.moon = aerial::scene::Moonlight{aerial::moon_direction_enu(*s.moon),
                                              stepped_moon_fraction(*s.moon)};
        auto lit = card_light(aerial::moonlit(light.atmosphere, light.moon->fraction),
                              s.moon->elevation_rad);
        if (!lit) return lit.error();
        moon = *lit;
    }
    light.moon_direct = moon.direct;
    light.skylight = sun->sky + moon.sky;
    light.card = sun->on_card() + moon.on_card();
    light.card_cd_m2 = aerial::card_luminance_cd_m2(light.atmosphere, light.card);
    auto exposure = exposure_for(light, *sun);
    if (!exposure) return exposure.error();
    light.exposure = *exposure;
    light.tint = purkinje_tint(light.card_cd_m2);
    return light;
}

aerial::scene::FrameSettings settings_for(const FrameLight& light, aerial::Model model,
                                          aerial::ToneCurve tone) {
    aerial::scene::FrameSettings settings;
    settings.atmosphere = light.atmosphere;
    settings.atmosphere.sun_irradiance *= light.tint;
    settings.sun_dir = light.sun_dir;
    settings.moon = light.moon;
    settings.model = model;
    settings.ambient = glm::vec3(light.skylight * light.tint);  // skylight is linear in E_sun0
    settings.display.exposure = float(light.exposure);
    settings.display.tone = tone;
    return settings;
}

aerial::Result<aerial::scene::FrameSettings> settings_for(const FlightState& state,
                                                          const std::string& preset,
                                                          aerial::Model model,
                                                          aerial::ToneCurve tone) {
    auto light = frame_light(state, preset);
    if (!light) return light.error();
    return settings_for(*light, model, tone);
}

}  // namespace sample
