// DecimatingMesh: the run-time adaptive mesh started from a decimated mesh, rebuilt (refine, then
// decimate) on a thread of its own when the view has moved on. See aerial/mesh.hpp.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <optional>
#include <utility>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "aerial/mesh.hpp"

namespace aerial::mesh {
namespace {

using aerial::detail::invalid;
using aerial::detail::number;

/// What a rebuild gives: the adaptive mesh started from the decimated one, already updated for
/// the rebuild's frame, and its time.
struct Rebuilt {
    Result<AdaptiveMesh> adaptive;
    double ms = 0.0;
};

Rebuilt rebuild(const Mesh& start, const Surface& surface, const DecimatingSettings& settings,
                const Frame<float>& frame) {
    constexpr const char* kFunction = "mesh::DecimatingMesh::update";
    const auto began = std::chrono::steady_clock::now();
    const auto elapsed = [&] {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - began)
            .count();
    };
    AdaptiveSettings fine_settings = settings.adaptive;
    fine_settings.split_lsb = settings.fine_split_lsb;
    fine_settings.time_slice_ms = 0.0;
    fine_settings.morph_updates = 0;
    auto made_fine = AdaptiveMesh::create(start, surface, fine_settings);
    if (!made_fine) return {aerial::detail::from(kFunction, made_fine.error()), elapsed()};
    AdaptiveMesh fine = std::move(made_fine).value();
    fine.update(frame);
    DecimateOptions d;
    d.colour = settings.adaptive.colour;
    d.max_lsb = settings.decimate_lsb;
    d.lock_boundary = true;  // the horizon ring, the tile's edge: the outline stays
    auto decimated = decimate(fine.mesh(), frame, d);
    if (!decimated) return {aerial::detail::from(kFunction, decimated.error()), elapsed()};
    auto made = AdaptiveMesh::create(std::move(decimated).value(), surface, settings.adaptive);
    if (!made) return {aerial::detail::from(kFunction, made.error()), elapsed()};
    AdaptiveMesh adaptive = std::move(made).value();
    adaptive.update(frame);
    return {std::move(adaptive), elapsed()};
}

}  // namespace

std::optional<Error> validate(const DecimatingSettings& settings) {
    constexpr const char* kFunction = "mesh::validate";
    if (auto e = validate(settings.adaptive)) return aerial::detail::from(kFunction, *e);
    const float split = settings.adaptive.split_lsb;
    if (!(settings.fine_split_lsb > 0.0f) || !(settings.fine_split_lsb <= split))
        return invalid(kFunction, "fine_split_lsb", "in (0, adaptive.split_lsb]",
                       number(settings.fine_split_lsb));
    if (settings.adaptive.colour.quantized_vertices && !(settings.fine_split_lsb > 0.5f))
        return invalid(kFunction, "fine_split_lsb", "> 0.5 with colour.quantized_vertices",
                       number(settings.fine_split_lsb));
    if (!(settings.decimate_lsb >= settings.fine_split_lsb) || !(settings.decimate_lsb <= split))
        return invalid(kFunction, "decimate_lsb", "in [fine_split_lsb, adaptive.split_lsb]",
                       number(settings.decimate_lsb));
    if (!(settings.rebuild_sun_rad > 0.0) || !std::isfinite(settings.rebuild_sun_rad))
        return invalid(kFunction, "rebuild_sun_rad", "a finite value > 0",
                       number(settings.rebuild_sun_rad));
    if (!(settings.rebuild_eye_m >= 0.0) || !std::isfinite(settings.rebuild_eye_m))
        return invalid(kFunction, "rebuild_eye_m", "a finite value >= 0",
                       number(settings.rebuild_eye_m));
    return std::nullopt;
}

struct DecimatingMesh::Impl {
    Mesh start;
    Surface surface;
    DecimatingSettings settings;
    std::optional<AdaptiveMesh> current;
    glm::dvec3 built_sun{0.0}, built_eye{0.0};  ///< the current mesh's rebuild frame
    std::future<Rebuilt> running;
    glm::dvec3 running_sun{0.0}, running_eye{0.0};
    DecimatingStats stats;
    Mesh empty;

    ~Impl() {
        if (running.valid()) running.wait();
    }

    bool moved_on(const Frame<float>& frame) const {
        const glm::dvec3 sun = frame.view.sun_dir;
        const double turned = std::acos(
            std::clamp(glm::dot(glm::normalize(sun), glm::normalize(built_sun)), -1.0, 1.0));
        if (turned > settings.rebuild_sun_rad) return true;
        const glm::dvec3 eye = frame.view.eye * frame.view.meters_per_unit;
        return settings.rebuild_eye_m > 0.0 &&
               glm::length(eye - built_eye) > settings.rebuild_eye_m;
    }

    std::optional<Error> take(Rebuilt&& rebuilt, const glm::dvec3& sun, const glm::dvec3& eye) {
        stats.last_rebuild_ms = rebuilt.ms;
        stats.rebuild_ms += rebuilt.ms;
        if (!rebuilt.adaptive) return rebuilt.adaptive.error();
        current.emplace(std::move(rebuilt.adaptive).value());
        built_sun = sun;
        built_eye = eye;
        ++stats.rebuilds;
        stats.switched = true;
        return std::nullopt;
    }
};

DecimatingMesh::DecimatingMesh(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
DecimatingMesh::DecimatingMesh(DecimatingMesh&&) noexcept = default;
DecimatingMesh& DecimatingMesh::operator=(DecimatingMesh&&) noexcept = default;
DecimatingMesh::~DecimatingMesh() = default;

Result<DecimatingMesh> DecimatingMesh::create(Mesh start, Surface surface,
                                              DecimatingSettings settings) {
    constexpr const char* kFunction = "mesh::DecimatingMesh::create";
    if (auto e = validate_mesh(start)) return aerial::detail::from(kFunction, *e);
    if (auto e = validate(settings)) return aerial::detail::from(kFunction, *e);
    // The surface and the start mesh are checked as AdaptiveMesh checks them.
    if (auto probe = AdaptiveMesh::create(start, surface, settings.adaptive); !probe)
        return aerial::detail::from(kFunction, probe.error());
    auto impl = std::make_unique<Impl>();
    impl->start = std::move(start);
    impl->surface = std::move(surface);
    impl->settings = settings;
    return DecimatingMesh(std::move(impl));
}

Result<UpdateStats> DecimatingMesh::update(const Frame<float>& frame) {
    Impl& m = *impl_;
    m.stats.switched = false;
    const glm::dvec3 sun = frame.view.sun_dir;
    const glm::dvec3 eye = frame.view.eye * frame.view.meters_per_unit;
    if (!m.current) {
        if (auto e = m.take(rebuild(m.start, m.surface, m.settings, frame), sun, eye)) return *e;
    } else if (m.running.valid() &&
               m.running.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
        if (auto e = m.take(m.running.get(), m.running_sun, m.running_eye)) return *e;
    }
    if (!m.running.valid() && m.moved_on(frame)) {
        if (m.settings.background) {
            m.running_sun = sun;
            m.running_eye = eye;
            m.running = std::async(std::launch::async,
                                   [start = m.start, surface = m.surface, settings = m.settings,
                                    frame] { return rebuild(start, surface, settings, frame); });
        } else if (auto e = m.take(rebuild(m.start, m.surface, m.settings, frame), sun, eye)) {
            return *e;
        }
    }
    m.stats.rebuilding = m.running.valid();
    return m.current->update(frame);
}

const Mesh& DecimatingMesh::mesh() const {
    return impl_->current ? impl_->current->mesh() : impl_->empty;
}

const DecimatingStats& DecimatingMesh::stats() const { return impl_->stats; }

}  // namespace aerial::mesh
