// SkyCubemapCache: the sky cubemap kept current by a bound on how far its texels could be off.
#include <algorithm>
#include <cmath>
#include <optional>
#include <thread>
#include <utility>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "aerial/phase.hpp"
#include "aerial/sky.hpp"
#include "sky_view_table.hpp"
#include "worker_pool.hpp"

namespace aerial {
namespace {

using detail::any_horizontal;
using detail::SkyViewTable;
using glm::dvec3;

constexpr const char* kUpdate = "SkyCubemapCache::update";
/// The probes' steps: the sun raised by 0.2 degrees, the eye by 25 m.
constexpr double kSunStepRad = 0.2 * kPi / 180.0;
constexpr double kAltitudeStepM = 25.0;
/// Probe directions: every 8th row and 5th column of the table's nodes.
constexpr int kProbeRowStride = 8;
constexpr int kProbeColumnStride = 5;
/// The up axis counts as unchanged within this (1 - cos of the angle).
constexpr double kUpTolerance = 1e-12;

/// d(display value)/d(x) of the tone curve at x = exposure * radiance.
double tone_slope(double x, ToneCurve curve) {
    if (curve == ToneCurve::exponential) return std::exp(-std::max(x, 0.0));
    return x < 1.0 ? 1.0 : 0.0;
}

/// 8-bit steps a change dL of a radiance L moves its code by: e |dL| times the tone curve's
/// slope at the darker end, L - |dL| (the curve's slope falls as x grows, so a texel that is
/// white at this exposure is not taken as unmoved when the change could bring it below white).
double steps(const dvec3& radiance, const dvec3& change, const Display& d) {
    double most = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double e = double(d.exposure);
        const double darker = std::max(radiance[c] - std::abs(change[c]), 0.0);
        most = std::max(most, 255.0 * tone_slope(e * darker, d.tone) * e * std::abs(change[c]));
    }
    return most;
}

/// What the sun and the eye were when a sky was made (or texels encoded).
struct ViewState {
    double sun_elevation_rad = 0.0;
    double sun_azimuth_rad = 0.0;  ///< about up, from a fixed horizontal axis
    double altitude_m = 0.0;
};

/// The radiance at one probe direction and its change per radian of sun elevation and per metre
/// of eye altitude.
struct Probe {
    dvec3 radiance{0.0}, per_rad{0.0}, per_m{0.0};
};

/// A sky made or being made: its table, the state it is for, and (when complete) its
/// sensitivities: probes for the sun's elevation and the eye's altitude, and per node the
/// radiance and its change per radian of azimuth (the sun turning about up turns the sky).
struct Sky {
    SkyViewTable table;
    Atmosphere atmosphere;  ///< what it is made for (the table's context may adjust E_sun0)
    ViewState state;
    std::vector<Probe> probes;
    std::vector<dvec3> node_radiance, node_per_azimuth;
};

/// The sky of a view whose sun is raised by `rise` radians and eye by `climb_m` metres.
Result<SkyContext> perturbed(const SkyContext& base, double rise, double climb_m) {
    View view = base.view;
    const dvec3& up = view.up;
    const double elevation = std::asin(std::clamp(glm::dot(view.sun_dir, up), -1.0, 1.0));
    dvec3 toward = view.sun_dir - up * glm::dot(view.sun_dir, up);
    toward = glm::length(toward) > 1e-9 ? glm::normalize(toward) : any_horizontal(up);
    const double e = std::min(elevation + rise, kPi / 2);
    view.sun_dir = std::cos(e) * toward + std::sin(e) * up;
    view.eye = base.eye_m + up * climb_m;
    view.meters_per_unit = 1.0;
    return prepare_sky(base.atmosphere, view, base.method);
}

/// A sky is scaled to a new E_sun0 when no channel changed by more than this factor; beyond,
/// it is made again (the bound is first order: where the tone curve saturates, it would not see
/// a large change).
constexpr double kMaxLightScale = 2.0;

/// Whether two atmospheres differ at most in E_sun0, each channel within kMaxLightScale of
/// `shown`'s: the sky of one is the other's times their ratio per channel (radiance is linear
/// in E_sun0).
bool same_but_light(const Atmosphere& a, const Atmosphere& shown) {
    Atmosphere b = shown;
    b.sun_irradiance = a.sun_irradiance;
    if (!(a == b)) return false;
    for (int c = 0; c < 3; ++c) {
        const double ratio = a.sun_irradiance[c] / shown.sun_irradiance[c];
        if (!(ratio >= 1.0 / kMaxLightScale && ratio <= kMaxLightScale)) return false;
    }
    return true;
}

}  // namespace

struct SkyCubemapCache::State {
    Options options;
    Stats stats;
    std::optional<Sky> shown, building;
    Atmosphere atmosphere;     ///< the shown sky's
    dvec3 light{1.0};          ///< E_sun0 now over the shown sky's, per channel
    dvec3 up{0.0}, axis{0.0};  ///< axis: the fixed horizontal axis azimuths are taken from
    ViewState encoded_state;
    Display encoded_display;
    dvec3 encoded_light{1.0};  ///< `light` when the texels were encoded
    SkyCubemap cubemap;
    std::array<std::vector<std::uint8_t>, 6> rgba8;

    /// How far texels made at `from` could be from the sky at `to` (steps at display d); with
    /// `with_turn` false without the sun's turn about up (which turns the sky, not its table).
    double bound(const Sky& sky, const ViewState& from, const ViewState& to, const Display& d,
                 bool with_turn = true) const;
    /// The steps a texel moves from the light and exposure it was encoded at to these.
    double light_steps(const Display& d) const;
    void finish(Sky& sky);
    void encode(const dvec3& sun, const ViewState& now, const Display& d, bool switched);
};

double SkyCubemapCache::State::bound(const Sky& sky, const ViewState& from, const ViewState& to,
                                     const Display& d, bool with_turn) const {
    const double rise = std::abs(to.sun_elevation_rad - from.sun_elevation_rad);
    const double climb = std::abs(to.altitude_m - from.altitude_m);
    double turn = std::abs(to.sun_azimuth_rad - from.sun_azimuth_rad);
    turn = with_turn ? std::min(turn, 2.0 * kPi - turn) : 0.0;
    // The sky at this light: every radiance and sensitivity times `light` per channel.
    double most = 0.0;
    for (const Probe& p : sky.probes)
        most = std::max(most,
                        steps(light * p.radiance, light * (rise * p.per_rad + climb * p.per_m), d));
    for (std::size_t k = 0; k < sky.node_radiance.size(); ++k)
        most = std::max(
            most, steps(light * sky.node_radiance[k], light * (turn * sky.node_per_azimuth[k]), d));
    return most;
}

double SkyCubemapCache::State::light_steps(const Display& d) const {
    dvec3 ratio(0.0);
    for (int c = 0; c < 3; ++c) {
        ratio[c] = std::abs(std::log(double(d.exposure) * light[c] /
                                     (double(encoded_display.exposure) * encoded_light[c])));
    }
    double most = 0.0;
    for (const dvec3& l : shown->node_radiance)
        most = std::max(most, steps(light * l, ratio * light * l, d));
    return most;
}

void SkyCubemapCache::State::finish(Sky& sky) {
    const SkyContext& base = sky.table.sky();
    auto raised = perturbed(base, kSunStepRad, 0.0);
    auto climbed = perturbed(base, 0.0, kAltitudeStepM);
    std::vector<dvec3> directions;
    for (int row = 0; row < SkyViewTable::kRows; row += kProbeRowStride) {
        for (int column = 0; column < SkyViewTable::kColumns; column += kProbeColumnStride)
            directions.push_back(sky.table.node_direction(row, column));
    }
    sky.probes.assign(directions.size(), Probe{});
    const auto task = [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) {
            const dvec3& d = directions[i];
            Probe& p = sky.probes[i];
            p.radiance = sky_radiance(base, d);
            if (raised) p.per_rad = (sky_radiance(*raised, d) - p.radiance) / kSunStepRad;
            if (climbed) p.per_m = (sky_radiance(*climbed, d) - p.radiance) / kAltitudeStepM;
        }
    };
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    detail::WorkerPool::instance().run(threads, directions.size(), 4, task);
    stats.directions_last_update += 3 * int(directions.size());
    constexpr int kRows = SkyViewTable::kRows, kColumns = SkyViewTable::kColumns;
    constexpr double kColumnRad = kPi / (kColumns - 1);
    sky.node_radiance.assign(std::size_t(kRows * kColumns), dvec3(0.0));
    sky.node_per_azimuth.assign(sky.node_radiance.size(), dvec3(0.0));
    for (int row = 0; row < kRows; ++row) {
        for (int column = 0; column < kColumns; ++column) {
            sky.node_radiance[std::size_t(row * kColumns + column)] =
                sky.table.radiance(sky.table.node_direction(row, column));
        }
        for (int column = 0; column < kColumns; ++column) {
            const int a = std::max(column - 1, 0), b = std::min(column + 1, kColumns - 1);
            const auto& n = sky.node_radiance;
            sky.node_per_azimuth[std::size_t(row * kColumns + column)] =
                (n[std::size_t(row * kColumns + b)] - n[std::size_t(row * kColumns + a)]) /
                (double(b - a) * kColumnRad);
        }
    }
}

void SkyCubemapCache::State::encode(const dvec3& sun, const ViewState& now, const Display& d,
                                    bool switched) {
    shown->table.set_sun_direction(sun);
    cubemap = detail::cubemap_from_table(shown->table, options.size);
    if (light != dvec3(1.0)) {
        for (auto& face : cubemap.faces) {
            for (glm::vec3& texel : face) texel *= glm::vec3(light);
        }
    }
    auto codes = cubemap_to_rgba8(cubemap, d.exposure, d.tone);
    if (switched) {
        int largest = 0;
        for (std::size_t f = 0; f < 6; ++f) {
            for (std::size_t k = 0; k < codes[f].size() && k < rgba8[f].size(); ++k)
                largest = std::max(largest, std::abs(int(codes[f][k]) - int(rgba8[f][k])));
        }
        stats.last_switch_steps = largest;
    }
    rgba8 = std::move(codes);
    encoded_state = now;
    encoded_display = d;
    encoded_light = light;
    ++stats.encodes;
}

SkyCubemapCache::SkyCubemapCache() : SkyCubemapCache(Options{}) {}
SkyCubemapCache::SkyCubemapCache(const Options& options) : state_(std::make_unique<State>()) {
    state_->options = options;
}
SkyCubemapCache::~SkyCubemapCache() = default;
SkyCubemapCache::SkyCubemapCache(SkyCubemapCache&&) noexcept = default;
SkyCubemapCache& SkyCubemapCache::operator=(SkyCubemapCache&&) noexcept = default;

const SkyCubemap& SkyCubemapCache::cubemap() const { return state_->cubemap; }
const std::array<std::vector<std::uint8_t>, 6>& SkyCubemapCache::rgba8() const {
    return state_->rgba8;
}
const SkyCubemapCache::Stats& SkyCubemapCache::stats() const { return state_->stats; }

namespace {

std::optional<Error> check_options(const SkyCubemapCache::Options& o) {
    using detail::invalid;
    using detail::number;
    if (o.size < 1 || o.size > 4096) return invalid(kUpdate, "size", "1 .. 4096", number(o.size));
    if (!(o.max_change_steps >= 0.0) || !std::isfinite(o.max_change_steps))
        return invalid(kUpdate, "max_change_steps", "a finite value >= 0",
                       number(o.max_change_steps));
    if (o.spread_updates < 1)
        return invalid(kUpdate, "spread_updates", ">= 1", number(o.spread_updates));
    if (!(o.max_lag_steps >= o.max_change_steps) || !std::isfinite(o.max_lag_steps))
        return invalid(kUpdate, "max_lag_steps", "a finite value >= max_change_steps",
                       number(o.max_lag_steps));
    return std::nullopt;
}

}  // namespace

Result<bool> SkyCubemapCache::update(const Atmosphere& atmosphere, const View& view,
                                     const Display& display) {
    State& s = *state_;
    if (auto e = check_options(s.options)) return *e;
    if (auto e = validate(atmosphere)) return detail::from(kUpdate, *e);
    if (auto e = validate(view)) return detail::from(kUpdate, *e);
    if (!(display.exposure > 0.0f) || !std::isfinite(display.exposure))
        return detail::invalid(kUpdate, "display.exposure", "a finite value > 0",
                               detail::number(display.exposure));
    const dvec3 up = glm::normalize(view.up);
    const dvec3 sun = glm::normalize(view.sun_dir);
    // A new E_sun0 alone (a moon's changing light, a tint) scales the sky: no new sky.
    const bool reset = !s.shown || !same_but_light(atmosphere, s.atmosphere) ||
                       glm::dot(up, s.up) < 1.0 - kUpTolerance;
    if (s.building && !same_but_light(atmosphere, s.building->atmosphere)) {
        s.building.reset();  // begun for another atmosphere: start again below if needed
    }
    // Azimuths are taken from a horizontal axis fixed while the up axis holds.
    const dvec3 axis = reset ? any_horizontal(up) : s.axis;
    ViewState now;
    now.sun_elevation_rad = std::asin(std::clamp(glm::dot(sun, up), -1.0, 1.0));
    now.sun_azimuth_rad = std::atan2(glm::dot(sun, glm::cross(up, axis)), glm::dot(sun, axis));
    now.altitude_m = altitude_above_sphere(dvec3(view.eye * view.meters_per_unit), up,
                                           atmosphere.planet_radius_m);
    s.stats.directions_last_update = 0;
    const auto compute = [&](int rows) {
        SkyViewTable& table = s.building->table;
        const int done = table.rows_done();
        table.compute_rows(done, rows);
        // The zenith row is one direction.
        const bool zenith = table.complete() && done < SkyViewTable::kRows;
        s.stats.directions_last_update += (table.rows_done() - done) * SkyViewTable::kColumns -
                                          (zenith ? SkyViewTable::kColumns - 1 : 0);
    };
    const auto light_of = [&](const Atmosphere& made) {
        return atmosphere.sun_irradiance / made.sun_irradiance;
    };
    const auto start = [&]() -> std::optional<Error> {
        auto sky = prepare_sky(atmosphere, view, s.options.method);
        if (!sky) return detail::from(kUpdate, sky.error());
        s.building.emplace(Sky{SkyViewTable(*sky), atmosphere, now, {}, {}, {}});
        return std::nullopt;
    };
    // How far the shown texels could be from this view, and whether to catch up at once.
    if (!reset) s.light = light_of(s.atmosphere);
    const double behind = reset ? 0.0 : s.bound(*s.shown, s.shown->state, now, display, false);
    bool at_once = reset || behind >= s.options.max_lag_steps;
    if (reset) {
        if (auto e = start()) return *e;
        s.axis = axis;
    } else if (s.building) {
        // The sky under way is for an earlier view: when the shown one is too far behind,
        // finish it if it is close enough to this view, else start over.
        if (at_once && s.bound(*s.shown, s.building->state, now, display, false) >=
                           s.options.max_change_steps) {
            if (auto e = start()) return *e;
        }
    } else if (behind >= s.options.max_change_steps) {
        if (auto e = start()) return *e;
    }
    s.stats.bound_steps = behind;
    bool switched = false;
    if (s.building) {
        const int spread = s.options.spread_updates;
        compute(at_once ? SkyViewTable::kRows : (SkyViewTable::kRows + spread - 1) / spread);
        if (s.building->table.complete()) {
            s.finish(*s.building);
            s.atmosphere = s.building->atmosphere;
            s.light = light_of(s.atmosphere);
            s.shown = std::move(s.building);
            s.building.reset();
            s.up = up;
            ++s.stats.recomputes;
            switched = true;
        }
    }
    s.stats.building = s.building.has_value();
    // The texels: re-encoded from the shown sky when it changed or when the sun (its phase angle
    // and azimuth), the altitude or the exposure could have moved them by the bound.
    const double texel_steps =
        s.bound(*s.shown, s.encoded_state, now, display) + s.light_steps(display);
    if (switched || reset || display.tone != s.encoded_display.tone ||
        texel_steps >= s.options.max_change_steps) {
        s.encode(sun, now, display, switched && !reset);
        return true;
    }
    return false;
}

}  // namespace aerial
