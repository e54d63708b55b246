// The `height` model's per-frame slice of the light scattered more than once (see the header).
#include "height_multiple_scattering.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <tuple>
#include <vector>

#include "multiple_scattering.hpp"

namespace aerial::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
/// The view directions level(h) averages over: midpoints, evenly in the zenith cosine and in
/// azimuth over [0, pi] (the field is symmetric about the sun's vertical plane): equal solid
/// angles.
constexpr int kMeanCosines = 16, kMeanAzimuths = 8;

/// What the slice is cut from and where: the cache's key.
struct SliceKey {
    const MultipleScatteringTable* table;
    double sun_irradiance[3];
    double eye_cos_sun_zenith;
    bool operator==(const SliceKey& o) const {
        return table == o.table &&
               std::equal(sun_irradiance, sun_irradiance + 3, o.sun_irradiance) &&
               eye_cos_sun_zenith == o.eye_cos_sun_zenith;
    }
};

/// J_ms / beta_s at an altitude (m) towards a view (zenith cosine, azimuth from the sun), times
/// E_sun0: radiance per unit scattering coefficient. Zero in a channel that does not scatter.
class Field {
  public:
    Field(const Atmosphere& a, const MultipleScatteringTable& table, double cos_sun_zenith)
        : a_(a), table_(table) {
        const double mu_s = std::clamp(cos_sun_zenith, -1.0, 1.0);
        sun_ = glm::dvec3(std::sqrt(1.0 - mu_s * mu_s), 0.0, mu_s);
    }
    glm::dvec3 operator()(double altitude_m, double mu_v, double azimuth_rad) const {
        const double h = std::max(altitude_m, 0.0);
        const double across = std::sqrt(std::max(0.0, 1.0 - mu_v * mu_v));
        const glm::dvec3 view(across * std::cos(azimuth_rad), across * std::sin(azimuth_rad), mu_v);
        const glm::dvec3 x(0.0, 0.0, a_.planet_radius_m + h);
        const glm::dvec3 j = table_.density(x, view, sun_);
        const glm::dvec3 beta = a_.rayleigh_scattering * std::exp(-h / a_.rayleigh_scale_height_m) +
                                a_.mie_scattering * std::exp(-h / a_.mie_scale_height_m);
        glm::dvec3 psi(0.0);
        for (int c = 0; c < 3; ++c) {
            if (beta[c] > 0.0) psi[c] = j[c] / beta[c] * a_.sun_irradiance[c];
        }
        return psi;
    }

  private:
    const Atmosphere& a_;
    const MultipleScatteringTable& table_;
    glm::dvec3 sun_;
};

/// The shape's altitude rows: up to ten of the shorter scale height (where the shape changes, in
/// haze; at most the atmosphere's top), evenly in log(1 + h / knee) with the knee at a quarter of
/// it.
double shape_top_m(const Atmosphere& a) {
    return std::min(a.atmosphere_radius_m - a.planet_radius_m,
                    10.0 * std::min(a.rayleigh_scale_height_m, a.mie_scale_height_m));
}
double shape_knee_m(const Atmosphere& a) {
    return 0.25 * std::min(a.rayleigh_scale_height_m, a.mie_scale_height_m);
}
double shape_altitude_scale(const Atmosphere& a) {
    return (MultipleScatteringSlice::kShapeAltitudeRows - 1) /
           std::log1p(shape_top_m(a) / shape_knee_m(a));
}

using LevelRows = std::array<glm::vec3, MultipleScatteringSlice::kLevelRows>;

/// The sun zenith cosine of level's sun row k.
double sun_row_cosine(int k) {
    using S = MultipleScatteringSlice;
    return std::cos(S::kMaxSunZenithRad * k / (S::kSunRows - 1));
}

LevelRows compute_level_rows(const Atmosphere& a, const MultipleScatteringTable& table) {
    using S = MultipleScatteringSlice;
    LevelRows rows{};
    for (int k = 0; k < S::kSunRows; ++k) {
        const Field field(a, table, sun_row_cosine(k));
        for (int i = 0; i < S::kAltitudeRows; ++i) {
            const double h = slice_row_altitude_m(a, i);
            glm::dvec3 sum(0.0);
            for (int m = 0; m < kMeanCosines; ++m) {
                const double mu = -1.0 + (2.0 * m + 1.0) / kMeanCosines;
                for (int q = 0; q < kMeanAzimuths; ++q) {
                    sum += field(h, mu, kPi * (q + 0.5) / kMeanAzimuths);
                }
            }
            rows[k * S::kAltitudeRows + i] = glm::vec3(sum / double(kMeanCosines * kMeanAzimuths));
        }
    }
    return rows;
}

/// level(h, mu_s) of an atmosphere per unit E_sun0 (the table's own unit: an atmosphere that
/// differs in E_sun0 alone, such as the moon's light, shares them): 65 536 lookups in its
/// table, about 20 ms, kept for the last few tables (a game switching between clear air and fog).
std::shared_ptr<const LevelRows> level_rows(
    const Atmosphere& lit, const std::shared_ptr<const MultipleScatteringTable>& table) {
    Atmosphere a = lit;
    a.sun_irradiance = glm::dvec3(1.0);
    struct Entry {
        std::shared_ptr<const MultipleScatteringTable> table;  // keeps the address unique
        std::shared_ptr<const LevelRows> rows;
    };
    constexpr std::size_t kKept = 4;
    static std::mutex mutex;
    static std::vector<Entry> kept;  // most recent last
    {
        std::lock_guard<std::mutex> lock(mutex);
        for (std::size_t i = 0; i < kept.size(); ++i) {
            if (kept[i].table == table) {
                Entry hit = kept[i];
                kept.erase(kept.begin() + std::ptrdiff_t(i));
                kept.push_back(hit);
                return hit.rows;
            }
        }
    }
    auto rows = std::make_shared<const LevelRows>(compute_level_rows(a, *table));
    std::lock_guard<std::mutex> lock(mutex);
    if (kept.size() == kKept) kept.erase(kept.begin());
    kept.push_back({table, rows});
    return rows;
}

std::shared_ptr<const MultipleScatteringSlice> cut_slice(
    const Atmosphere& a, const std::shared_ptr<const MultipleScatteringTable>& table,
    double eye_cos_sun_zenith) {
    using S = MultipleScatteringSlice;
    auto slice = std::make_shared<S>();
    const double radius = a.planet_radius_m, top = a.atmosphere_radius_m;
    const double horizon = std::sqrt((top - radius) * (top + radius));
    slice->altitude_scale = float((S::kAltitudeRows - 1) / horizon);
    slice->two_radius_m = float(2.0 * radius);
    slice->level = *level_rows(a, table);
    for (glm::vec3& row : slice->level) row *= glm::vec3(a.sun_irradiance);
    const Field field(a, *table, eye_cos_sun_zenith);
    const float mu_s = float(eye_cos_sun_zenith);
    const auto cut_shape = [&](double altitude_m, glm::vec3* out) {
        const glm::vec3 level = slice_level(*slice, float(std::max(altitude_m, 0.0)), mu_s);
        for (int a_row = 0; a_row < S::kViewRows; ++a_row) {
            const double mu = -1.0 + 2.0 * a_row / (S::kViewRows - 1);
            for (int b = 0; b < S::kAzimuthRows; ++b) {
                const double azimuth = 2.0 * std::asin(double(b) / (S::kAzimuthRows - 1));
                const glm::dvec3 psi = field(altitude_m, mu, azimuth);
                glm::vec3 shape(0.0f);
                for (int c = 0; c < 3; ++c) {
                    if (level[c] > 0.0f) shape[c] = float(psi[c] / level[c]);
                }
                out[a_row * S::kAzimuthRows + b] = shape;
            }
        }
    };
    slice->shape_altitude_scale = float(shape_altitude_scale(a));
    slice->shape_inv_knee_m = float(1.0 / shape_knee_m(a));
    for (int r = 0; r < S::kShapeAltitudeRows; ++r) {
        cut_shape(slice_shape_row_altitude_m(a, r), slice->shapes.data() + r * S::kShapeRows);
    }
    return slice;
}

}  // namespace

double slice_row_altitude_m(const Atmosphere& a, int i) {
    const double radius = a.planet_radius_m, top = a.atmosphere_radius_m;
    const double rho = std::sqrt((top - radius) * (top + radius)) * i /
                       (MultipleScatteringSlice::kAltitudeRows - 1);
    return std::sqrt(radius * radius + rho * rho) - radius;
}

MultipleScatteringSettings height_table_settings() {
    MultipleScatteringSettings s;
    s.altitudes = 16;
    s.sun_zenith_angles = 32;
    s.view_zenith_angles = 33;
    s.azimuths = 16;
    s.steps_per_efold = 1.0;
    return s;
}

std::shared_ptr<const MultipleScatteringSlice> multiple_scattering_slice(
    const Atmosphere& atmosphere, double eye_cos_sun_zenith) {
    const glm::dvec3 beta = atmosphere.rayleigh_scattering + atmosphere.mie_scattering;
    if (std::max({beta.x, beta.y, beta.z}) <= 0.0) return nullptr;
    const auto table = multiple_scattering_table(atmosphere, height_table_settings());
    // The last few slices: evaluate() and the tests prepare one frame per vertex for the same
    // eye, and a frame of the scene renderer prepares several (its models, the sky and its
    // probes, the sun sprite) for two or three suns.
    struct Entry {
        std::shared_ptr<const MultipleScatteringTable> table;  // keeps the key's address unique
        SliceKey key;
        std::shared_ptr<const MultipleScatteringSlice> slice;
    };
    constexpr std::size_t kKept = 8;  // two lights (sun and moon) of the last frames
    static std::mutex mutex;
    static std::vector<Entry> kept;  // most recent last
    const SliceKey key{
        table.get(),
        {atmosphere.sun_irradiance.x, atmosphere.sun_irradiance.y, atmosphere.sun_irradiance.z},
        eye_cos_sun_zenith};
    {
        std::lock_guard<std::mutex> lock(mutex);
        for (std::size_t i = 0; i < kept.size(); ++i) {
            if (kept[i].key == key) {
                Entry hit = kept[i];
                kept.erase(kept.begin() + std::ptrdiff_t(i));
                kept.push_back(hit);
                return hit.slice;
            }
        }
    }
    auto slice = cut_slice(atmosphere, table, eye_cos_sun_zenith);
    std::lock_guard<std::mutex> lock(mutex);
    if (kept.size() == kKept) kept.erase(kept.begin());
    kept.push_back({table, key, slice});
    return slice;
}

template <class T>
glm::vec<3, T> slice_level(const MultipleScatteringSlice& s, T altitude_m, T mu_s) {
    using S = MultipleScatteringSlice;
    const T h = std::max(altitude_m, T(0));
    int i, k;
    T f, g;
    slice_cell(std::sqrt(h * (T(s.two_radius_m) + h)) * T(s.altitude_scale), S::kAltitudeRows, i,
               f);
    slice_cell(
        std::acos(std::clamp(mu_s, T(-1), T(1))) * T((S::kSunRows - 1) / S::kMaxSunZenithRad),
        S::kSunRows, k, g);
    auto at = [&](int row, int column) {
        return glm::vec<3, T>(s.level[row * S::kAltitudeRows + column]);
    };
    return (at(k, i) * (T(1) - f) + at(k, i + 1) * f) * (T(1) - g) +
           (at(k + 1, i) * (T(1) - f) + at(k + 1, i + 1) * f) * g;
}

double slice_shape_row_altitude_m(const Atmosphere& a, int r) {
    return shape_knee_m(a) * std::expm1(r / shape_altitude_scale(a));
}

template <class T>
glm::vec<3, T> slice_shape(const MultipleScatteringSlice& s, T altitude_m, T mu_v, T cos_azimuth) {
    using S = MultipleScatteringSlice;
    int r, a, b;
    T fr, fa, fb;
    slice_cell(
        std::log1p(std::max(altitude_m, T(0)) * T(s.shape_inv_knee_m)) * T(s.shape_altitude_scale),
        S::kShapeAltitudeRows, r, fr);
    slice_cell((mu_v + T(1)) * T(0.5 * (S::kViewRows - 1)), S::kViewRows, a, fa);
    const T sin_half = std::sqrt(std::max(T(0), (T(1) - cos_azimuth) * T(0.5)));
    slice_cell(sin_half * T(S::kAzimuthRows - 1), S::kAzimuthRows, b, fb);
    auto at = [&](int layer, int row, int column) {
        return glm::vec<3, T>(s.shapes[layer * S::kShapeRows + row * S::kAzimuthRows + column]);
    };
    auto plane = [&](int layer) {
        return (at(layer, a, b) * (T(1) - fb) + at(layer, a, b + 1) * fb) * (T(1) - fa) +
               (at(layer, a + 1, b) * (T(1) - fb) + at(layer, a + 1, b + 1) * fb) * fa;
    };
    return plane(r) * (T(1) - fr) + plane(r + 1) * fr;
}

template glm::vec3 slice_shape<float>(const MultipleScatteringSlice&, float, float, float);
template glm::dvec3 slice_shape<double>(const MultipleScatteringSlice&, double, double, double);
template glm::vec3 slice_level<float>(const MultipleScatteringSlice&, float, float);
template glm::dvec3 slice_level<double>(const MultipleScatteringSlice&, double, double);

}  // namespace aerial::detail
