// The sky-view table: the sky around the eye by elevation and azimuth from the sun, in parts.
#include "sky_view_table.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/geometric.hpp>

#include "aerial/phase.hpp"
#include "sky_internal.hpp"
#include "worker_pool.hpp"

namespace aerial::detail {
namespace {

using glm::dvec3;

/// The part of `v` perpendicular to unit `up`, normalised; `fallback` when v is (nearly) up.
dvec3 horizontal(const dvec3& v, const dvec3& up, const dvec3& fallback) {
    const dvec3 h = v - up * glm::dot(v, up);
    const double length = glm::length(h);
    return length > 1e-9 ? h / length : fallback;
}

/// Rows: elevation = (k u^2 + (1 - k) u) 90 deg for u in [0, 1], twice as dense at the horizon
/// (where the sky changes fastest by day) as at the zenith, but not sparse above it (where the
/// twilight sky has its structure).
constexpr double kRowCurvature = 1.0;

double row_elevation(double u) {
    return (kRowCurvature * u * u + (1.0 - kRowCurvature) * u) * (kPi / 2);
}
double row_of_elevation(double elevation_rad) {
    const double x = std::clamp(elevation_rad / (kPi / 2), 0.0, 1.0);
    const double b = 1.0 - kRowCurvature;
    return (-b + std::sqrt(b * b + 4.0 * kRowCurvature * x)) / (2.0 * kRowCurvature);
}

/// The parts as logarithms (what the table holds); radiance below kFloor counts as kFloor.
constexpr double kFloor = 1e-30;
HeightParts<double> logs(const HeightParts<double>& p) {
    HeightParts<double> out = p;
    out.rayleigh = glm::log(glm::max(p.rayleigh, dvec3(kFloor)));
    out.mie = glm::log(glm::max(p.mie, dvec3(kFloor)));
    out.multiple = glm::log(glm::max(p.multiple, dvec3(kFloor)));
    return out;
}

/// The `height-chained` sky: the `height` model over sky.segments pieces of the ray, each
/// attenuated by the ones before it, part by part (the phase is the same along the whole ray),
/// in the precision of `frame` (the sky's, or the table's float copy of it). Quadratic spacing:
/// short pieces near the eye, where density changes fastest along near-horizontal rays and
/// where the attenuation of the rest is set.
template <class T>
HeightParts<double> chained_parts(const SkyContext& sky, const Frame<T>& frame, const dvec3& dir) {
    using V = glm::vec<3, T>;
    HeightParts<double> out;
    const double length = sky_ray_length_m(sky, dir);
    dvec3 transmittance(1.0), start = sky.eye_m;
    Frame<T> piece = frame;  // moved along the ray, one piece after the other
    for (int i = 1; i <= sky.segments; ++i) {
        const double f = double(i) / sky.segments;
        const dvec3 end = sky.eye_m + dir * (length * f * f);
        if (i > 1) move_frame_eye(piece, start);
        const HeightParts<T> p = height_parts(piece, V(end));
        out.rayleigh += transmittance * dvec3(p.rayleigh);
        out.mie += transmittance * dvec3(p.mie);
        out.multiple += transmittance * dvec3(p.multiple);
        transmittance *= dvec3(p.extinction);
        start = end;
    }
    out.extinction = transmittance;
    return out;
}

}  // namespace

dvec3 any_horizontal(const dvec3& up) {
    const dvec3 helper = std::abs(up.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
    return glm::normalize(helper - up * glm::dot(helper, up));
}

HeightParts<double> sky_radiance_parts(const SkyContext& sky, const dvec3& dir) {
    HeightParts<double> out;
    switch (sky.method) {
        case SkyMethod::dome_height:
            return height_parts(sky.frame, sky.eye_m + dir * sky_ray_length_m(sky, dir));
        case SkyMethod::height_chained:
            return chained_parts(sky, sky.frame, dir);
        default:
            out.multiple = sky_radiance(sky, dir);
            return out;
    }
}

SkyViewTable::SkyViewTable(const SkyContext& sky) : sky_(sky), nodes_(std::size_t(kNodes)) {
    if (sky_.method == SkyMethod::height_chained) {
        // The chain in float: libm's float functions are about twice as fast, and a node's
        // radiance needs no more digits than a texel shows.
        auto frame = prepare_frame<float>(sky_.atmosphere, sky_.view, Model::height);
        if (frame) float_frame_ = std::move(frame).value();
    }
    const dvec3& up = sky_.view.up;
    toward_sun_ = horizontal(sky_.view.sun_dir, up, any_horizontal(up));
    across_ = glm::cross(up, toward_sun_);
}

void SkyViewTable::set_sun_direction(const dvec3& sun) {
    const dvec3& up = sky_.view.up;
    sky_.view.sun_dir = sun;
    toward_sun_ = horizontal(sun, up, toward_sun_);
    across_ = glm::cross(up, toward_sun_);
}

dvec3 SkyViewTable::node_direction(int row, int column) const {
    const double elevation = row_elevation(double(row) / (kRows - 1));
    const double azimuth = kPi * column / (kColumns - 1);
    return std::cos(elevation) * (std::cos(azimuth) * toward_sun_ + std::sin(azimuth) * across_) +
           std::sin(elevation) * sky_.view.up;
}

void SkyViewTable::compute_rows(int first, int count) {
    const int begin = std::max(0, first), end = std::min(kRows, first + count);
    if (end <= begin) return;
    // Nodes are independent: spread over the worker threads (the zenith row is one direction).
    const std::size_t items = std::size_t(end - begin) * kColumns;
    const auto task = [&](std::size_t a, std::size_t b) {
        for (std::size_t k = a; k < b; ++k) {
            const int row = begin + int(k / kColumns), column = int(k % kColumns);
            if (row == kRows - 1 && column > 0) continue;
            const dvec3 d = row == kRows - 1 ? sky_.view.up : node_direction(row, column);
            nodes_[std::size_t(row) * kColumns + std::size_t(column)] = logs(
                float_frame_ ? chained_parts(sky_, *float_frame_, d) : sky_radiance_parts(sky_, d));
        }
    };
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    WorkerPool::instance().run(threads, items, kColumns, task);
    if (end == kRows) {
        HeightParts<double>* zenith = &nodes_[std::size_t(kRows - 1) * kColumns];
        std::fill(zenith + 1, zenith + kColumns, zenith[0]);
    }
    rows_done_ = std::max(rows_done_, end);
}

SkyViewCoordinates SkyViewTable::coordinates(const dvec3& d) const {
    const dvec3& up = sky_.view.up;
    const double along_up = glm::dot(d, up);
    // Below the horizon: the horizon under the direction (as compute_sky_cubemap defines).
    const dvec3 view = along_up < 0 ? horizontal(d, up, toward_sun_) : d;
    const double elevation = std::asin(std::clamp(glm::dot(view, up), 0.0, 1.0));
    const double azimuth =
        std::atan2(std::abs(glm::dot(view, across_)), glm::dot(view, toward_sun_));
    SkyViewCoordinates c;
    c.row = row_of_elevation(elevation) * (kRows - 1);
    c.column = azimuth / kPi * (kColumns - 1);
    c.cos_theta = std::clamp(glm::dot(view, sky_.view.sun_dir), -1.0, 1.0);
    return c;
}

HeightParts<double> SkyViewTable::parts(const SkyViewCoordinates& c) const {
    const int r0 = std::clamp(int(c.row), 0, kRows - 2);
    const int c0 = std::clamp(int(c.column), 0, kColumns - 2);
    const double fr = std::clamp(c.row - r0, 0.0, 1.0), fc = std::clamp(c.column - c0, 0.0, 1.0);
    const auto at = [&](int r, int col) -> const HeightParts<double>& {
        return nodes_[std::size_t(r) * kColumns + std::size_t(col)];
    };
    const double w[4] = {(1 - fr) * (1 - fc), (1 - fr) * fc, fr * (1 - fc), fr * fc};
    const HeightParts<double>* p[4] = {&at(r0, c0), &at(r0, c0 + 1), &at(r0 + 1, c0),
                                       &at(r0 + 1, c0 + 1)};
    // The parts change by factors across the table (exponentially towards the horizon and the
    // planet's shadow): interpolated in log form.
    HeightParts<double> out;
    out.rayleigh = out.mie = out.multiple = dvec3(0.0);
    for (int k = 0; k < 4; ++k) {
        out.rayleigh += w[k] * p[k]->rayleigh;
        out.mie += w[k] * p[k]->mie;
        out.multiple += w[k] * p[k]->multiple;
    }
    out.rayleigh = glm::exp(out.rayleigh);
    out.mie = glm::exp(out.mie);
    out.multiple = glm::exp(out.multiple);
    return out;
}

dvec3 SkyViewTable::radiance(const HeightParts<double>& p, double cos_theta) const {
    return p.in_scattering(rayleigh_phase(cos_theta),
                           henyey_greenstein_phase(cos_theta, sky_.frame.mie_g));
}

SkyCubemap cubemap_from_table(const SkyViewTable& table, int size) {
    SkyCubemap out;
    out.size = size;
    for (int face = 0; face < 6; ++face) {
        auto& texels = out.faces[std::size_t(face)];
        texels.resize(std::size_t(size) * std::size_t(size));
        for (int j = 0; j < size; ++j) {
            for (int i = 0; i < size; ++i) {
                texels[std::size_t(j) * std::size_t(size) + std::size_t(i)] =
                    glm::vec3(table.radiance(cubemap_texel_direction(face, i, j, size)));
            }
        }
    }
    return out;
}

}  // namespace aerial::detail
