#include "world.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace sample {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kTextureSize = 256;
/// Altitude of the light that sets the exposure and the terrain's skylight, m (the terrain
/// spans about 20 to 920 m).
constexpr double kLightingAltitudeM = 300.0;
/// The grey card's exposed radiance (aerial::ExposureOptions::key): brighter than the default
/// 0.5, since the terrain's texture and albedo make it darker than an 18 % card.
constexpr double kExposureKey = 0.8;
/// At most this many times the exposure of the sun at the zenith: dusk may stay darker than
/// noon instead of turning the bright sky around the low sun white.
constexpr double kExposureMaxGain = 3.5;
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

/// The UTC moment `minutes` after 00:00 of the schedule's date (any sign, days roll over).
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
    schedule.end_utc_min = events->civil_dusk_utc_min ? *events->civil_dusk_utc_min
                           : events->sunset_utc_min
                               ? *events->sunset_utc_min + kWhiteNightMinutesAfterSunset
                               : events->solar_noon_utc_min + 600.0;
    return schedule;
}

SunSchedule default_sun_schedule() {
    constexpr double kDegree = kPi / 180.0;
    return make_sun_schedule(kDefaultYear, kDefaultMonth, kDefaultDay,
                             kDefaultLatitudeDeg * kDegree, kDefaultLongitudeDeg * kDegree)
        .value();  // a valid date and place
}

void place_sun(FlightState& state, const SunSchedule& schedule, double day) {
    day = std::clamp(day, 0.0, 1.0);
    // Slow at first, fast through the afternoon, slow again towards sunset.
    const double u = smoothstep(0.15, 1.0, day);
    state.utc_min = schedule.noon_utc_min + (schedule.end_utc_min - schedule.noon_utc_min) * u;
    // The schedule's place and date are valid (make_sun_schedule checked them).
    const auto sun = aerial::sun_position(utc_at(schedule, state.utc_min), schedule.latitude_rad,
                                          schedule.longitude_rad);
    if (!sun) return;
    state.sun_elevation_rad = sun->elevation_rad;
    state.sun_azimuth_rad = sun->azimuth_rad;
    // Local apparent solar time: UTC + longitude (4 minutes a degree) + equation of time.
    const double local_min =
        state.utc_min + schedule.longitude_rad * 180.0 / kPi * 4.0 + sun->equation_of_time_min;
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
    place_sun(s, schedule, t);
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

aerial::Result<aerial::scene::FrameSettings> settings_for(const FlightState& s,
                                                          const std::string& preset,
                                                          aerial::Model model,
                                                          aerial::ToneCurve tone) {
    auto atmosphere = aerial::atmosphere_preset(preset);
    if (!atmosphere) return atmosphere.error();
    aerial::scene::FrameSettings settings;
    settings.atmosphere = *atmosphere;
    if (s.fog) {
        aerial::GroundHaze haze;
        haze.visibility_in_layer_m = 1200.0;
        haze.layer_thickness_m = 500.0;
        haze.visibility_aloft_m = 15000.0;
        // Real fog looks bright from every side because light scatters many times in it: the
        // height model's higher orders carry that (docs/models.md), with the droplets' own g.
        auto foggy = aerial::atmosphere_with_ground_haze(haze, settings.atmosphere);
        if (!foggy) return foggy.error();
        settings.atmosphere = *foggy;
    }
    settings.sun_dir = {std::cos(s.sun_elevation_rad) * std::sin(s.sun_azimuth_rad),
                        std::cos(s.sun_elevation_rad) * std::cos(s.sun_azimuth_rad),
                        std::sin(s.sun_elevation_rad)};
    settings.model = model;
    // Light of level ground at a typical terrain altitude: the sun through the atmosphere
    // (zero in the planet's shadow) and the skylight, which is also the terrain's ambient term.
    // The exposure maps a grey card under that light to a fixed display level, so that noon
    // and dusk both read (aerial::auto_exposure).
    const glm::dvec3 sun = aerial::sun_irradiance_at_altitude(
        settings.atmosphere, kLightingAltitudeM, s.sun_elevation_rad);
    aerial::SkyAmbientOptions ambient_options;
    ambient_options.elevation_steps = 8;
    ambient_options.azimuth_steps = 16;
    auto sky = aerial::sky_ambient(settings.atmosphere, kLightingAltitudeM, s.sun_elevation_rad,
                                   ambient_options);
    if (!sky) return sky.error();
    settings.ambient = glm::vec3(*sky);
    aerial::ExposureOptions exposure;
    exposure.key = kExposureKey;
    exposure.max_gain = kExposureMaxGain;
    double value = aerial::auto_exposure(sun, s.sun_elevation_rad, *sky,
                                         settings.atmosphere.sun_irradiance, exposure);
    if (s.sun_elevation_rad < 0.0) {
        // After sunset the exposure follows the sky down: it grows as the skylight fades below
        // its value at sunset, so that civil twilight reads (the afterglow over the sun, the
        // Earth's shadow opposite) instead of going black.
        auto at_sunset =
            aerial::sky_ambient(settings.atmosphere, kLightingAltitudeM, 0.0, ambient_options);
        if (!at_sunset) return at_sunset.error();
        value *=
            std::max(1.0, aerial::luminance(*at_sunset) / std::max(aerial::luminance(*sky), 1e-30));
    }
    settings.display.exposure = float(value);
    settings.display.tone = tone;
    return settings;
}

}  // namespace sample
