// What the sources of AdaptiveMesh share (not installed): one update's state, passed between the
// steps of AdaptiveMesh::update, and the geometry both refinement and relocation use.
#pragma once

#include <chrono>
#include <cstddef>
#include <limits>
#include <queue>

#include <glm/vec3.hpp>

#include "aerial/mesh.hpp"

namespace aerial::mesh {

/// Marks a colour or an estimate that was never computed (its stamp eye is NaN).
inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
inline constexpr double kPi = 3.14159265358979323846;

/// The smallest angle (rad) of the triangle p, q, r.
double min_angle(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r);

/// One update: its clock, the queue of faces to refine and what it has counted so far.
struct AdaptiveMesh::Pass {
    using Clock = std::chrono::steady_clock;
    /// A face queued for refinement with the estimate it had then; entries whose face was deleted
    /// or estimated again since are stale and skipped.
    struct Entry {
        float error;
        int face;
        bool operator<(const Entry& o) const {
            return error < o.error || (error == o.error && face > o.face);
        }
    };

    Clock::time_point start = Clock::now();
    double slice_ms = 0.0;             ///< settings.time_slice_ms; 0: no limit
    std::priority_queue<Entry> queue;  ///< faces above split_lsb, the worst first
    /// Refinement and coarsening steps so far: the clock is read every 16th / 64th step.
    std::size_t iterations = 0;
    float unrefined_max =
        0.0f;  ///< the largest estimate of faces above the target left as they are
    UpdateStats stats;

    /// True when `fraction` of the time slice has gone.
    bool out_of_time(double fraction) const {
        return slice_ms > 0.0 &&
               std::chrono::duration<double, std::milli>(Clock::now() - start).count() >
                   fraction * slice_ms;
    }
};

}  // namespace aerial::mesh
