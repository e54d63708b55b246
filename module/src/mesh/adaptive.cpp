// Colour-error-driven longest-edge bisection (Rivara's LEPP) with undo records for coarsening.
//
// Every bisection splits both faces of an edge (TriMesh::split(EdgeHandle, VertexHandle)), so the
// mesh stays conforming; the new vertex is the edge midpoint projected onto the surface. A split
// is undone by collapsing its vertex into one end of the split edge, which restores the two
// parent faces exactly, and only when the vertex's one-ring is still the one it was born with.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <queue>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "aerial/mesh.hpp"
#include "mesh_internal.hpp"

namespace aerial::mesh {
namespace {

using Clock = std::chrono::steady_clock;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

double elapsed_ms(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

struct HeapEntry {
    float error;
    int face;
    bool operator<(const HeapEntry& o) const {
        return error < o.error || (error == o.error && face > o.face);
    }
};

}  // namespace

std::optional<Error> validate(const AdaptiveSettings& settings) {
    if (auto e = validate(settings.colour)) return e;
    if (!(settings.split_lsb > 0.0f) || !std::isfinite(settings.split_lsb))
        return Error{"split_lsb", "split_lsb: expected a finite value > 0, got " +
                                      std::to_string(settings.split_lsb)};
    if (settings.colour.quantized_vertices && !(settings.split_lsb > 0.5f))
        return Error{"split_lsb",
                     "split_lsb: expected > 0.5 with colour.quantized_vertices (8-bit "
                     "vertex colours are off by up to half a step), got " +
                         std::to_string(settings.split_lsb)};
    if (!(settings.merge_ratio >= 1.0f) || !std::isfinite(settings.merge_ratio))
        return Error{"merge_ratio", "merge_ratio: expected a finite value >= 1, got " +
                                        std::to_string(settings.merge_ratio)};
    if (settings.max_vertices < 3)
        return Error{"max_vertices",
                     "max_vertices: expected >= 3, got " + std::to_string(settings.max_vertices)};
    if (!(settings.time_slice_ms >= 0.0) || !std::isfinite(settings.time_slice_ms))
        return Error{"time_slice_ms", "time_slice_ms: expected a finite value >= 0, got " +
                                          std::to_string(settings.time_slice_ms)};
    if (!(settings.eye_move_fraction >= 0.0) || !(settings.sun_turn_rad >= 0.0))
        return Error{"eye_move_fraction", "eye_move_fraction, sun_turn_rad: expected >= 0"};
    if (settings.morph_updates < 0 || settings.morph_updates > 1000)
        return Error{"morph_updates", "morph_updates: expected 0 .. 1000, got " +
                                          std::to_string(settings.morph_updates)};
    if (!(settings.compact_garbage_ratio >= 0.0f) || !std::isfinite(settings.compact_garbage_ratio))
        return Error{"compact_garbage_ratio",
                     "compact_garbage_ratio: expected a finite value >= 0, got " +
                         std::to_string(settings.compact_garbage_ratio)};
    if (!(settings.colour_edge_min_angle_deg >= 0.0f &&
          settings.colour_edge_min_angle_deg <= 60.0f))
        return Error{"colour_edge_min_angle_deg",
                     "colour_edge_min_angle_deg: expected 0 .. 60, got " +
                         std::to_string(settings.colour_edge_min_angle_deg)};
    if (!(settings.relocate_min_angle_deg >= 0.0f && settings.relocate_min_angle_deg <= 60.0f))
        return Error{"relocate_min_angle_deg", "relocate_min_angle_deg: expected 0 .. 60, got " +
                                                   std::to_string(settings.relocate_min_angle_deg)};
    return std::nullopt;
}

Result<AdaptiveMesh> AdaptiveMesh::create(Mesh base, Surface surface, AdaptiveSettings settings) {
    if (auto e = validate(settings)) return *e;
    if (auto e = validate_mesh(base, "base")) return *e;
    if (surface.kind == Surface::Kind::sphere &&
        (!(surface.radius_m > 0.0) || !std::isfinite(surface.radius_m) || !finite(surface.centre)))
        return Error{"surface",
                     "surface: sphere needs a finite centre and a radius > 0, got "
                     "radius " +
                         std::to_string(surface.radius_m)};
    if (surface.kind == Surface::Kind::heightfield && !surface.height_m)
        return Error{"surface", "surface: heightfield without a height function"};
    AdaptiveMesh m;
    m.mesh_ = std::move(base);
    m.mesh_.garbage_collection();
    m.surface_ = std::move(surface);
    m.settings_ = settings;
    m.base_vertices_ = m.mesh_.n_vertices();
    m.mesh_.add_property(m.colour_);
    m.mesh_.add_property(m.colour_eye_);
    m.mesh_.add_property(m.colour_sun_);
    m.mesh_.add_property(m.error_);
    m.mesh_.add_property(m.error_eye_);
    m.mesh_.add_property(m.error_sun_);
    m.mesh_.add_property(m.error_radius_sq_);
    m.mesh_.add_property(m.record_);
    for (auto v : m.mesh_.vertices()) m.mesh_.property(m.record_, v) = -1;
    m.live_vertices_ = m.mesh_.n_vertices();
    m.live_faces_ = m.mesh_.n_faces();
    m.invalidate();
    return m;
}

void AdaptiveMesh::invalidate() {
    index_valid_ = false;
    for (auto v : mesh_.vertices()) mesh_.property(colour_eye_, v).v = glm::vec3(kNaN);
    for (auto f : mesh_.faces()) {
        mesh_.property(error_eye_, f).v = glm::vec3(kNaN);
        mesh_.property(error_, f) = 0.0f;
    }
}

float AdaptiveMesh::face_error(OpenMesh::FaceHandle face) const {
    return mesh_.property(error_, face);
}

namespace {

// True when a value computed with (stamp_eye, stamp_sun) for something at `position` is out of
// date for the frame: the eye moved by more than `fraction` of the distance, or the sun turned.
bool stale(const glm::vec3& stamp_eye, const glm::vec3& stamp_sun, const glm::dvec3& position,
           const Frame<float>& frame, const AdaptiveSettings& settings) {
    if (std::isnan(stamp_eye.x)) return true;
    const glm::dvec3 eye = frame.view.eye;
    const double moved = glm::length(eye - glm::dvec3(stamp_eye));
    if (moved > settings.eye_move_fraction * glm::length(position - eye)) return true;
    const double c = std::clamp(glm::dot(frame.view.sun_dir, glm::dvec3(stamp_sun)), -1.0, 1.0);
    return std::acos(c) > settings.sun_turn_rad;
}

}  // namespace

glm::vec3 AdaptiveMesh::vertex_colour(OpenMesh::VertexHandle v) {
    const glm::dvec3 p = to_glm(mesh_.point(v));
    if (stale(mesh_.property(colour_eye_, v).v, mesh_.property(colour_sun_, v).v, p, *frame_,
              settings_)) {
        mesh_.property(colour_, v).v = display_colour(*frame_, settings_.colour, p);
        mesh_.property(colour_eye_, v).v = glm::vec3(frame_->view.eye);
        mesh_.property(colour_sun_, v).v = glm::vec3(frame_->view.sun_dir);
    }
    return mesh_.property(colour_, v).v;
}

int AdaptiveMesh::sample_multiple() const {
    // Relocation moves vertices to where its score (colour_error's samples: the edge midpoints
    // and the centroid on small faces) is small, which can be where the rest of the face is not:
    // estimated with those samples, a refined dome's dense error rose from 1.59 to 2.26 steps.
    // Estimating with twice the samples per edge (a grid containing colour_error's) sends those
    // faces back to refinement: 1.31 steps.
    return settings_.relocate ? 2 : 1;
}

bool AdaptiveMesh::edge_locked(OpenMesh::EdgeHandle e) const {
    return settings_.lock_boundary && mesh_.is_boundary(e);
}

float AdaptiveMesh::estimate(OpenMesh::FaceHandle f) {
    glm::dvec3 p[3];
    glm::vec3 c[3];
    bool skip[3];
    int k = 0;
    for (auto h : mesh_.fh_range(f)) {  // halfedge k runs from vertex k to vertex k + 1
        const auto v = mesh_.from_vertex_handle(h);
        p[k] = to_glm(mesh_.point(v));
        c[k] = vertex_colour(v);
        skip[k] = edge_locked(mesh_.edge_handle(h));
        ++k;
    }
    const float e = colour_error_skipping(*frame_, settings_.colour, p, c, skip, sample_multiple());
    stamp(f, e);
    return e;
}

void AdaptiveMesh::stamp(OpenMesh::FaceHandle f, float error) {
    const glm::dvec3 eye = frame_->view.eye;
    const glm::dvec3 centroid = to_glm(mesh_.calc_face_centroid(f));
    const double radius = settings_.eye_move_fraction * glm::length(centroid - eye);
    mesh_.property(error_, f) = error;
    mesh_.property(error_eye_, f).v = glm::vec3(eye);
    mesh_.property(error_sun_, f).v = glm::vec3(frame_->view.sun_dir);
    mesh_.property(error_radius_sq_, f) = float(radius * radius);
    for (auto v : mesh_.fv_range(f)) touched_.push_back(v);
    if (error <= settings_.split_lsb) estimated_max_ = std::max(estimated_max_, error);
    if (recording_) {
        const std::size_t i = std::size_t(f.idx());
        if (face_group_.size() <= i) {
            face_group_.resize(i + 1, 0);
            in_above_.resize(i + 1, 0);
        }
        face_group_[i] = groups_.back().id;
        groups_.back().faces.push_back({mesh_.property(error_radius_sq_, f), f.idx()});
        if (error > settings_.split_lsb) {
            if (!in_above_[i]) {
                in_above_[i] = 1;
                above_.push_back(f.idx());
            }
        } else {
            below_.push_back({error, f.idx()});
            std::push_heap(below_.begin(), below_.end());
        }
    }
}

void AdaptiveMesh::rebuild_index() {
    // Groups faces by the exact eye and sun of their last estimate.
    groups_.clear();
    above_.clear();
    below_.clear();
    face_group_.assign(mesh_.n_faces(), 0);
    in_above_.assign(mesh_.n_faces(), 0);
    std::map<std::array<std::uint32_t, 6>, std::size_t> by_stamp;
    for (auto f : mesh_.faces()) {
        const glm::vec3 eye = mesh_.property(error_eye_, f).v;
        const glm::vec3 sun = mesh_.property(error_sun_, f).v;
        if (std::isnan(eye.x)) {  // not estimated yet: the full sweep handles it
            index_valid_ = false;
            groups_.clear();
            return;
        }
        std::array<std::uint32_t, 6> key;
        std::memcpy(key.data(), &eye, sizeof eye);
        std::memcpy(key.data() + 3, &sun, sizeof sun);
        auto [it, added] = by_stamp.emplace(key, groups_.size());
        if (added) {
            StampGroup g;
            g.id = next_group_++;
            g.eye = eye;
            g.sun = sun;
            groups_.push_back(std::move(g));
        }
        StampGroup& g = groups_[it->second];
        g.faces.push_back({mesh_.property(error_radius_sq_, f), f.idx()});
        face_group_[std::size_t(f.idx())] = g.id;
        const float e = mesh_.property(error_, f);
        if (e > settings_.split_lsb) {
            in_above_[std::size_t(f.idx())] = 1;
            above_.push_back(f.idx());
        } else {
            below_.push_back({e, f.idx()});
        }
    }
    std::make_heap(below_.begin(), below_.end());
    for (StampGroup& g : groups_) std::sort(g.faces.begin(), g.faces.end());
    index_valid_ = true;
}

bool AdaptiveMesh::sweep_indexed(UpdateStats& stats, const std::function<bool()>& out_of_time) {
    // Exactly the faces face_stale() accepts: in a group every face has the same stamp eye and
    // sun, so `moved` and the sun's cosine are the same floats face_stale() computes.
    const glm::vec3 eye(frame_->view.eye), sun(frame_->view.sun_dir);
    const float cos_turn = float(std::cos(settings_.sun_turn_rad));
    const std::size_t n_groups = groups_.size() - 1;  // the last one is this update's
    bool finished = true;
    std::size_t visited = 0;
    for (std::size_t g = 0; g < n_groups && finished; ++g) {
        StampGroup& group = groups_[g];
        const glm::vec3 moved = eye - group.eye;
        const float d2 = glm::dot(moved, moved);
        const bool turned = glm::dot(sun, group.sun) < cos_turn;
        std::size_t i = group.head;
        for (; i < group.faces.size() && (turned || d2 > group.faces[i].first); ++i) {
            // Under a time slice: stop between entries; the group's head keeps the place.
            if ((++visited & 255) == 0 && out_of_time()) {
                finished = false;
                break;
            }
            const OpenMesh::FaceHandle f(group.faces[i].second);
            // Entries of faces stamped again since (later, or later in the same update with
            // another radius after a split changed them) are dead.
            if (face_group_[std::size_t(f.idx())] != group.id || mesh_.status(f).deleted() ||
                mesh_.property(error_radius_sq_, f) != group.faces[i].first)
                continue;
            estimate(f);
            ++stats.faces_estimated;
        }
        group.head = i;
    }
    std::size_t kept = 0;
    for (std::size_t g = 0; g < groups_.size(); ++g)
        if (g == groups_.size() - 1 || groups_[g].head < groups_[g].faces.size()) {
            if (kept != g) groups_[kept] = std::move(groups_[g]);
            ++kept;
        }
    groups_.resize(kept);
    return finished;
}

bool AdaptiveMesh::face_stale(OpenMesh::FaceHandle f) const {
    // The eye moved by more than eye_move_fraction of the face's distance at its last estimate,
    // or the sun turned by more than sun_turn_rad.
    const glm::vec3& eye = mesh_.property(error_eye_, f).v;
    if (std::isnan(eye.x)) return true;
    const glm::vec3 moved = glm::vec3(frame_->view.eye) - eye;
    if (glm::dot(moved, moved) > mesh_.property(error_radius_sq_, f)) return true;
    const float c = glm::dot(glm::vec3(frame_->view.sun_dir), mesh_.property(error_sun_, f).v);
    return c < float(std::cos(settings_.sun_turn_rad));
}

OpenMesh::EdgeHandle AdaptiveMesh::longest_edge(OpenMesh::FaceHandle f) const {
    // A total order (length, then handle) so that LEPP paths strictly ascend and end.
    OpenMesh::EdgeHandle best;
    double best_length = -1.0;
    for (auto h : mesh_.fh_range(f)) {
        const auto e = mesh_.edge_handle(h);
        const double length = mesh_.calc_edge_sqr_length(e);
        if (length > best_length || (length == best_length && e.idx() < best.idx())) {
            best = e;
            best_length = length;
        }
    }
    return best;
}

namespace {

// The smallest angle (rad) of the triangle p, q, r.
double min_angle(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r) {
    auto angle = [](const glm::dvec3& apex, const glm::dvec3& u, const glm::dvec3& v) {
        const glm::dvec3 a = u - apex, b = v - apex;
        return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
    };
    return std::min({angle(p, q, r), angle(q, r, p), angle(r, p, q)});
}

}  // namespace

OpenMesh::EdgeHandle AdaptiveMesh::colour_edge(OpenMesh::FaceHandle f) {
    // The edge with the largest midpoint error whose bisection keeps both faces' halves at
    // least colour_edge_min_angle_deg in every angle; ties and no candidate: the longest edge.
    const double bound =
        double(settings_.colour_edge_min_angle_deg) * 3.14159265358979323846 / 180.0;
    const OpenMesh::EdgeHandle longest = longest_edge(f);
    OpenMesh::EdgeHandle best;
    float best_error = -1.0f;
    for (auto h : mesh_.fh_range(f)) {
        const auto e = mesh_.edge_handle(h);
        if (edge_locked(e) || !(mesh_.calc_edge_sqr_length(e) > 0.0)) continue;
        const auto va = mesh_.from_vertex_handle(h), vb = mesh_.to_vertex_handle(h);
        const glm::dvec3 a = to_glm(mesh_.point(va)), b = to_glm(mesh_.point(vb));
        const glm::dvec3 m = surface_.project(0.5 * (a + b));
        bool shaped = true;
        for (auto side : {h, mesh_.opposite_halfedge_handle(h)}) {
            if (mesh_.is_boundary(side)) continue;
            const glm::dvec3 apex =
                to_glm(mesh_.point(mesh_.to_vertex_handle(mesh_.next_halfedge_handle(side))));
            if (min_angle(a, m, apex) < bound || min_angle(m, b, apex) < bound) shaped = false;
        }
        if (!shaped) continue;
        const float error = edge_midpoint_error(*frame_, settings_.colour, a, b, vertex_colour(va),
                                                vertex_colour(vb));
        if (error > best_error || (error == best_error && e == longest)) {
            best = e;
            best_error = error;
        }
    }
    return best.is_valid() ? best : longest;
}

bool AdaptiveMesh::splittable(OpenMesh::FaceHandle f) const {
    // A face whose longest edge is locked stays: bisecting its other edges would only make
    // slivers along the locked edge without reducing the error there.
    const auto e = longest_edge(f);
    return e.is_valid() && !edge_locked(e) && mesh_.calc_edge_sqr_length(e) > 0.0;
}

void AdaptiveMesh::bisect(OpenMesh::EdgeHandle e, UpdateStats& stats) {
    const auto h0 = mesh_.halfedge_handle(e, 0);
    const auto h1 = mesh_.halfedge_handle(e, 1);
    Split record;
    record.a = mesh_.from_vertex_handle(h0);
    record.b = mesh_.to_vertex_handle(h0);
    if (!mesh_.is_boundary(h0)) record.c = mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h0));
    if (!mesh_.is_boundary(h1)) record.d = mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h1));
    const glm::dvec3 mid = 0.5 * (to_glm(mesh_.point(record.a)) + to_glm(mesh_.point(record.b)));
    record.vertex = mesh_.add_vertex(to_point(surface_.project(mid)));
    mesh_.property(colour_eye_, record.vertex).v = glm::vec3(kNaN);
    mesh_.property(record_, record.vertex) = int(splits_.size());
    record.born = updates_;
    splits_.push_back(record);
    mesh_.split(e, record.vertex);
    ++stats.splits;
    ++live_vertices_;
    live_faces_ += record.c.is_valid() && record.d.is_valid() ? 2 : 1;
    if (settings_.relocate) relocate(record.vertex, stats);
    for (auto f : mesh_.vf_range(record.vertex)) {
        estimate(f);
        ++stats.faces_estimated;
    }
}

void AdaptiveMesh::relocate(OpenMesh::VertexHandle v, UpdateStats& stats) {
    // A pattern search on the surface: from the edge midpoint, try kDirections points at a step
    // around the vertex, move to the best that is better (at most kMoves times a step), halve
    // the step kLevels times. Better means fewer of the vertex's faces above split_lsb (faces that
    // refinement would split next), then a smaller sum of their errors: minimising the largest
    // error alone hardly helps (a face's error far from the vertex does not move with it).
    constexpr int kDirections = 8, kLevels = 3, kMoves = 2;
    constexpr double kFirstStep = 0.25;  // of the distance to the nearest ring vertex
    constexpr double kPi = 3.14159265358979323846;
    if (mesh_.is_boundary(v)) return;
    // The vertex's faces, each as its three corners (halfedge k runs from corner k to k + 1),
    // which corner is v, which edges are locked, and the face's normal with v at the midpoint.
    struct RingFace {
        glm::dvec3 p[3];
        glm::vec3 c[3];
        bool skip[3];
        int at = -1;
        glm::dvec3 normal;
    };
    std::vector<RingFace> ring;
    const glm::dvec3 x0 = to_glm(mesh_.point(v));
    for (auto f : mesh_.vf_range(v)) {
        RingFace r;
        int k = 0;
        for (auto h : mesh_.fh_range(f)) {
            const auto w = mesh_.from_vertex_handle(h);
            r.p[k] = to_glm(mesh_.point(w));
            if (w == v)
                r.at = k;
            else
                r.c[k] = vertex_colour(w);
            r.skip[k] = edge_locked(mesh_.edge_handle(h));
            ++k;
        }
        r.normal = glm::cross(r.p[1] - r.p[0], r.p[2] - r.p[0]);
        ring.push_back(r);
    }
    double nearest = std::numeric_limits<double>::infinity();
    for (auto w : mesh_.vv_range(v))
        nearest = std::min(nearest, glm::length(to_glm(mesh_.point(w)) - x0));
    if (ring.empty() || !(nearest > 0.0)) return;
    auto smallest_angle = [&](const glm::dvec3& x) {
        double least = kPi;
        for (RingFace& r : ring) {
            r.p[r.at] = x;
            least = std::min(least, min_angle(r.p[0], r.p[1], r.p[2]));
        }
        return least;
    };
    const double bound =
        std::min(double(settings_.relocate_min_angle_deg) * kPi / 180.0, smallest_angle(x0));
    struct Score {
        int above = std::numeric_limits<int>::max();  // refused positions score worst
        float sum = 0.0f;
        bool operator<(const Score& o) const {
            return above < o.above || (above == o.above && sum < o.sum);
        }
    };
    auto score = [&](const glm::dvec3& x) {
        for (RingFace& r : ring) {
            r.p[r.at] = x;
            if (!(glm::dot(glm::cross(r.p[1] - r.p[0], r.p[2] - r.p[0]), r.normal) > 0.0))
                return Score{};  // turned over
        }
        if (!(smallest_angle(x) >= bound)) return Score{};
        const glm::vec3 colour = display_colour(*frame_, settings_.colour, x);
        Score out;
        out.above = 0;
        for (RingFace& r : ring) {
            r.p[r.at] = x;
            r.c[r.at] = colour;
            const float e = colour_error_skipping(*frame_, settings_.colour, r.p, r.c, r.skip);
            out.above += e > settings_.split_lsb ? 1 : 0;
            out.sum += e;
        }
        return out;
    };
    Score best = score(x0);
    if (best.above == 0) return;  // refinement would split none of the faces
    // The tangent plane: the surface's normal (sphere, heightfield) or the faces' mean normal.
    glm::dvec3 n(0.0);
    if (surface_.kind == Surface::Kind::sphere)
        n = x0 - surface_.centre;
    else if (surface_.kind == Surface::Kind::heightfield)
        n = glm::dvec3(0.0, 0.0, 1.0);
    else
        for (const RingFace& r : ring) n += glm::normalize(r.normal);
    if (!(glm::length(n) > 0.0)) return;
    n = glm::normalize(n);
    const glm::dvec3 along =
        to_glm(mesh_.point(mesh_.to_vertex_handle(mesh_.halfedge_handle(v)))) - x0;
    glm::dvec3 u = along - glm::dot(along, n) * n;
    if (!(glm::length(u) > 0.0)) return;
    u = glm::normalize(u);
    const glm::dvec3 w = glm::cross(n, u);
    glm::dvec3 x = x0;
    double step = kFirstStep * nearest;
    for (int level = 0; level < kLevels; ++level, step *= 0.5) {
        for (int move = 0; move < kMoves; ++move) {
            glm::dvec3 next = x;
            Score next_score = best;
            for (int k = 0; k < kDirections; ++k) {
                const double a = 2.0 * kPi * k / kDirections;
                const glm::dvec3 y =
                    surface_.project(x + step * (std::cos(a) * u + std::sin(a) * w));
                const Score s = score(y);
                if (s < next_score) {
                    next = y;
                    next_score = s;
                }
            }
            if (next == x) break;
            x = next;
            best = next_score;
        }
    }
    if (x == x0) return;
    mesh_.set_point(v, to_point(x));
    mesh_.property(colour_eye_, v).v = glm::vec3(kNaN);
    ++stats.relocated;
}

bool AdaptiveMesh::undo_allowed(std::size_t index, UpdateStats& stats, float& error_c,
                                float& error_d) {
    const Split s = splits_[index];
    if (!s.vertex.is_valid() || mesh_.status(s.vertex).deleted() || s.ring_lost) return false;
    const float merge_lsb = settings_.split_lsb / settings_.merge_ratio;
    // The ring must be the one the vertex was born with.
    std::size_t expected = 2 + (s.c.is_valid() ? 1 : 0) + (s.d.is_valid() ? 1 : 0);
    std::size_t count = 0;
    for (auto w : mesh_.vv_range(s.vertex)) {
        if (w != s.a && w != s.b && w != s.c && w != s.d) return false;
        ++count;
    }
    if (count != expected) return false;
    // Cheap test first: the children's last estimates.
    for (auto f : mesh_.vf_range(s.vertex))
        if (mesh_.property(error_, f) > merge_lsb || std::isnan(mesh_.property(error_eye_, f).v.x))
            return false;
    // The parents' errors now.
    auto parent_error = [&](OpenMesh::VertexHandle apex) {
        const OpenMesh::VertexHandle vs[3] = {s.a, s.b, apex};
        glm::dvec3 p[3];
        glm::vec3 c[3];
        bool skip[3];
        for (int k = 0; k < 3; ++k) {
            p[k] = to_glm(mesh_.point(vs[k]));
            c[k] = vertex_colour(vs[k]);
        }
        skip[0] = false;  // a-b was split, so it is not locked
        for (int k = 1; k < 3; ++k) {
            const auto h = mesh_.find_halfedge(vs[k], vs[(k + 1) % 3]);
            skip[k] = h.is_valid() && edge_locked(mesh_.edge_handle(h));
        }
        ++stats.faces_estimated;
        return colour_error_skipping(*frame_, settings_.colour, p, c, skip, sample_multiple());
    };
    error_c = s.c.is_valid() ? parent_error(s.c) : 0.0f;
    error_d = s.d.is_valid() ? parent_error(s.d) : 0.0f;
    if (error_c > merge_lsb || error_d > merge_lsb) return false;
    const auto h = mesh_.find_halfedge(s.vertex, s.a);
    return h.is_valid() && mesh_.is_collapse_ok(h);
}

float AdaptiveMesh::record_weight(const Split& s) const {
    const double n = settings_.morph_updates;
    if (n <= 0.0) return 1.0f;
    const double w = s.fade_start >= 0.0 ? s.fade_weight - (updates_ - s.fade_start) / n
                                         : (updates_ - s.born) / n;
    return float(std::clamp(w, 0.0, 1.0));
}

bool AdaptiveMesh::try_undo(std::size_t index, UpdateStats& stats) {
    Split& record = splits_[index];
    if (!record.vertex.is_valid() || mesh_.status(record.vertex).deleted()) return false;
    float error_c = 0.0f, error_d = 0.0f;
    const bool allowed = undo_allowed(index, stats, error_c, error_d);
    if (settings_.morph_updates > 0) {
        const float w = record_weight(record);
        if (!allowed) {
            // Needed again: blend back in from where the fade-out got to.
            if (record.fade_start >= 0.0) {
                record.fade_start = -1.0;
                record.born = updates_ - double(w) * settings_.morph_updates;
            }
            return false;
        }
        if (record.fade_start < 0.0) {
            record.fade_start = updates_;
            record.fade_weight = w;
            fading_.push_back(int(index));
        }
        if (record_weight(record) > 0.0f) return false;
    } else if (!allowed) {
        return false;
    }
    const Split s = record;
    mesh_.collapse(mesh_.find_halfedge(s.vertex, s.a));
    const auto ab = mesh_.find_halfedge(s.a, s.b);
    for (auto hh : {ab, mesh_.opposite_halfedge_handle(ab)}) {
        const auto f = mesh_.face_handle(hh);
        if (!f.is_valid()) continue;
        const auto apex = mesh_.to_vertex_handle(mesh_.next_halfedge_handle(hh));
        stamp(f, apex == s.c ? error_c : error_d);
    }
    splits_[index].vertex = OpenMesh::VertexHandle();
    ++stats.merges;
    --live_vertices_;
    live_faces_ -= s.c.is_valid() && s.d.is_valid() ? 2 : 1;
    return true;
}

UpdateStats AdaptiveMesh::update(const Frame<float>& frame) {
    const auto start = Clock::now();
    const double slice = settings_.time_slice_ms;
    auto out_of_time = [&](double fraction) {
        return slice > 0.0 && elapsed_ms(start) > fraction * slice;
    };
    frame_ = &frame;
    updates_ += 1.0;
    touched_.clear();
    estimated_max_ = 0.0f;
    UpdateStats stats;

    // 1. Re-estimate what the view change made stale (round robin under a time slice) and queue
    // every face above the target.
    std::priority_queue<HeapEntry> heap;
    const bool indexed = settings_.indexed_sweep && index_valid_;
    recording_ = indexed;
    if (indexed) {
        StampGroup g;
        g.id = next_group_++;
        g.eye = glm::vec3(frame.view.eye);
        g.sun = glm::vec3(frame.view.sun_dir);
        groups_.push_back(std::move(g));
        const bool swept = sweep_indexed(stats, [&] { return out_of_time(0.5); });
        if (!swept) stats.complete = false;
        // The same heap and maximum the full sweep builds. When the time slice cut the sweep,
        // faces above the target may still be stale: those are re-estimated first, so that
        // nothing is refined on an old estimate (above_ may grow while we walk it).
        std::size_t kept = 0;
        for (std::size_t n = 0; n < above_.size(); ++n) {
            const int i = above_[n];
            const OpenMesh::FaceHandle f(i);
            if (!swept && !mesh_.status(f).deleted() && face_stale(f)) {
                estimate(f);
                ++stats.faces_estimated;
            }
            const float e = mesh_.property(error_, f);
            if (!mesh_.status(f).deleted() && e > settings_.split_lsb) {
                heap.push({e, i});
                above_[kept++] = i;
            } else {
                in_above_[std::size_t(i)] = 0;
            }
        }
        above_.resize(kept);
        while (!below_.empty()) {
            const auto [e, i] = below_.front();
            const OpenMesh::FaceHandle f(i);
            if (!mesh_.status(f).deleted() && mesh_.property(error_, f) == e) {
                estimated_max_ = std::max(estimated_max_, e);
                break;
            }
            std::pop_heap(below_.begin(), below_.end());
            below_.pop_back();
        }
    }
    const std::size_t n_faces = indexed ? 0 : mesh_.n_faces();
    std::size_t visited = 0;
    for (; visited < n_faces; ++visited) {
        if ((visited & 255) == 0 && out_of_time(0.5)) {
            stats.complete = false;
            break;
        }
        const OpenMesh::FaceHandle f(int((cursor_ + visited) % n_faces));
        if (mesh_.status(f).deleted()) continue;
        if (face_stale(f)) {
            estimate(f);
            ++stats.faces_estimated;
        }
        const float e = mesh_.property(error_, f);
        if (e > settings_.split_lsb)
            heap.push({e, f.idx()});
        else
            estimated_max_ = std::max(estimated_max_, e);
    }
    if (!indexed) cursor_ = n_faces ? (cursor_ + visited) % n_faces : 0;

    // 2. Refine: worst face first, LEPP bisection until the target, the budget or the slice.
    float unrefined_max = 0.0f;  // faces above the target left as they are
    std::size_t iterations = 0;
    while (!heap.empty()) {
        const HeapEntry top = heap.top();
        const OpenMesh::FaceHandle f0(top.face);
        if (mesh_.status(f0).deleted() || mesh_.property(error_, f0) != top.error) {
            heap.pop();
            continue;
        }
        if (live_vertices_ >= settings_.max_vertices ||
            ((++iterations & 15) == 0 && out_of_time(0.9))) {
            stats.complete = false;
            break;
        }
        heap.pop();
        if (!splittable(f0)) {
            unrefined_max = std::max(unrefined_max, top.error);
            continue;
        }
        const auto e0 = settings_.colour_edge ? colour_edge(f0) : longest_edge(f0);
        for (bool done = false; !done && live_vertices_ < settings_.max_vertices;) {
            // A path from a shorter edge can come back to f0 and split it: then f0 is estimated
            // again (and queued if still above the target) and this path ends.
            if (mesh_.face_handle(mesh_.halfedge_handle(e0, 0)) != f0 &&
                mesh_.face_handle(mesh_.halfedge_handle(e0, 1)) != f0)
                break;
            // Walk the longest-edge propagation path to its terminal edge and split that.
            OpenMesh::FaceHandle f = f0;
            OpenMesh::EdgeHandle e = e0;
            for (int step = 0; step < 4096; ++step) {
                const auto h = mesh_.halfedge_handle(e, 0);
                const auto across = mesh_.face_handle(h) == f
                                        ? mesh_.face_handle(mesh_.halfedge_handle(e, 1))
                                        : mesh_.face_handle(h);
                if (!across.is_valid()) break;
                const auto next = longest_edge(across);
                if (!next.is_valid() || next == e || edge_locked(next)) break;
                f = across;
                e = next;
            }
            done = e == e0;
            bisect(e, stats);
            for (auto nf : mesh_.vf_range(OpenMesh::VertexHandle(int(mesh_.n_vertices()) - 1)))
                if (mesh_.property(error_, nf) > settings_.split_lsb)
                    heap.push({mesh_.property(error_, nf), nf.idx()});
        }
    }
    for (; !heap.empty(); heap.pop()) {
        const OpenMesh::FaceHandle f(heap.top().face);
        if (!mesh_.status(f).deleted() && mesh_.property(error_, f) == heap.top().error)
            unrefined_max = std::max(unrefined_max, heap.top().error);
    }

    // 3. Coarsen: undo bisections whose parents are back below split / merge_ratio. Only
    // vertices next to a face estimated in this update can have changed their answer; newest
    // first, and an undo makes the parents' vertices candidates again (cascades).
    if (settings_.coarsen) {
        std::priority_queue<int> candidates;
        std::size_t consumed = 0;
        auto collect = [&] {
            for (; consumed < touched_.size(); ++consumed) {
                const auto v = touched_[consumed];
                if (!mesh_.status(v).deleted() && mesh_.property(record_, v) >= 0)
                    candidates.push(mesh_.property(record_, v));
            }
        };
        // Fading vertices go on fading (or come back) whether or not their faces were
        // re-estimated; the last step of a fade removes the vertex (and, like any undo, makes
        // the parents' vertices candidates below).
        std::vector<int> fading;
        fading.swap(fading_);
        std::sort(fading.begin(), fading.end(), std::greater<int>());
        fading.erase(std::unique(fading.begin(), fading.end()), fading.end());
        for (const int r : fading) {
            const Split& s = splits_[std::size_t(r)];
            if (!s.vertex.is_valid() || mesh_.status(s.vertex).deleted() || s.fade_start < 0.0)
                continue;
            if (!try_undo(std::size_t(r), stats) && splits_[std::size_t(r)].fade_start >= 0.0)
                fading_.push_back(r);
        }
        collect();
        int last = -1;
        while (!candidates.empty()) {
            if ((++iterations & 63) == 0 && out_of_time(1.0)) {
                stats.complete = false;
                break;
            }
            const int r = candidates.top();
            candidates.pop();
            if (r == last) continue;  // duplicates come out together
            last = r;
            if (try_undo(std::size_t(r), stats)) {
                collect();
                last = -1;
            }
        }
    }

    if (indexed) {
        std::sort(groups_.back().faces.begin(), groups_.back().faces.end());
        if (below_.size() > 4 * live_faces_ + 1024) rebuild_index();
    } else if (settings_.indexed_sweep) {
        rebuild_index();  // once every face has an estimate (after a complete first sweep)
    }
    recording_ = false;
    frame_ = nullptr;

    const double ratio = settings_.compact_garbage_ratio;
    auto too_much = [ratio](std::size_t stored, std::size_t live) {
        return double(stored - live) > ratio * double(live);
    };
    if (ratio > 0.0 &&
        (too_much(mesh_.n_vertices(), live_vertices_) || too_much(mesh_.n_faces(), live_faces_))) {
        compact();
        stats.compacted = true;
    }
    stats.vertices = live_vertices_;
    stats.faces = live_faces_;
    stats.max_error_lsb = std::max(estimated_max_, unrefined_max);
    return stats;
}

float AdaptiveMesh::morph_weight(OpenMesh::VertexHandle v) const {
    const int r = mesh_.property(record_, v);
    return r < 0 ? 1.0f : record_weight(splits_[std::size_t(r)]);
}

std::pair<OpenMesh::VertexHandle, OpenMesh::VertexHandle> AdaptiveMesh::parents(
    OpenMesh::VertexHandle v) const {
    const int r = mesh_.property(record_, v);
    if (r < 0) return {OpenMesh::VertexHandle(), OpenMesh::VertexHandle()};
    return {splits_[std::size_t(r)].a, splits_[std::size_t(r)].b};
}

template <typename T>
void AdaptiveMesh::morph_values(T* values, std::size_t components, std::size_t stride) const {
    if (settings_.morph_updates <= 0) return;
    // Geomorphing of the detail: a vertex shows its parents' shown mean plus w times its own
    // detail (its value minus its parents' mean). Vertices born together then move on straight
    // lines from the coarse interpolation to their values, 1/morph_updates of the way per update,
    // however deep the chain of bisections. Records are in the order of the splits, so parents
    // come before their children.
    std::vector<float> exact;
    for (const Split& s : splits_) {
        if (!s.vertex.is_valid() || mesh_.status(s.vertex).deleted()) continue;
        const float w = record_weight(s);
        if (w >= 1.0f) continue;
        if (exact.empty()) {
            exact.resize(mesh_.n_vertices() * components);
            for (std::size_t v = 0; v < mesh_.n_vertices(); ++v)
                for (std::size_t k = 0; k < components; ++k)
                    exact[v * components + k] = float(values[v * stride + k]);
        }
        const std::size_t i = std::size_t(s.vertex.idx()), a = std::size_t(s.a.idx()),
                          b = std::size_t(s.b.idx());
        T* out = values + i * stride;
        for (std::size_t k = 0; k < components; ++k) {
            const float shown_parents =
                0.5f * (float(values[a * stride + k]) + float(values[b * stride + k]));
            const float detail = exact[i * components + k] -
                                 0.5f * (exact[a * components + k] + exact[b * components + k]);
            const float v = shown_parents + w * detail;
            if constexpr (std::is_same_v<T, std::uint8_t>)
                out[k] = T(std::clamp(std::lround(v), 0L, 255L));
            else
                out[k] = T(v);
        }
    }
}

void AdaptiveMesh::morph_into(float* values, std::size_t components, std::size_t stride) const {
    morph_values(values, components, stride);
}

void AdaptiveMesh::morph_into(std::uint8_t* values, std::size_t components,
                              std::size_t stride) const {
    morph_values(values, components, stride);
}

void AdaptiveMesh::compact() {
    const CompactMaps maps = compact_keeping_order(mesh_);
    auto vertex = [&](OpenMesh::VertexHandle& v) {
        if (!v.is_valid()) return true;
        v = OpenMesh::VertexHandle(maps.vertex[std::size_t(v.idx())]);
        return v.is_valid();
    };
    auto face = [&](int f) { return maps.face[std::size_t(f)]; };

    // Undo records of live vertices, in their order (parents before children, newest last).
    std::vector<int> record(splits_.size(), -1);
    std::vector<Split> live;
    for (std::size_t i = 0; i < splits_.size(); ++i) {
        Split s = splits_[i];
        if (!s.vertex.is_valid() || maps.vertex[std::size_t(s.vertex.idx())] < 0) continue;
        for (OpenMesh::VertexHandle* h : {&s.vertex, &s.a, &s.b, &s.c, &s.d})
            if (!vertex(*h)) s.ring_lost = true;
        record[i] = int(live.size());
        live.push_back(s);
    }
    splits_ = std::move(live);
    for (std::size_t i = 0; i < splits_.size(); ++i)
        mesh_.property(record_, splits_[i].vertex) = int(i);
    std::size_t kept = 0;
    for (const int r : fading_)
        if (record[std::size_t(r)] >= 0) fading_[kept++] = record[std::size_t(r)];
    fading_.resize(kept);
    touched_.clear();

    // The round-robin sweep goes on at the first live face from where it was.
    std::size_t cursor = 0;
    for (std::size_t f = 0; f < cursor_ && f < maps.face.size(); ++f) cursor += face(int(f)) >= 0;
    cursor_ = mesh_.n_faces() ? cursor % mesh_.n_faces() : 0;

    // The index of estimates: entries of deleted faces could never be visited again.
    if (!index_valid_) return;
    for (StampGroup& g : groups_) {
        std::size_t n = 0;
        for (std::size_t i = g.head; i < g.faces.size(); ++i) {
            const int f = face(g.faces[i].second);
            if (f >= 0) g.faces[n++] = {g.faces[i].first, f};
        }
        g.faces.resize(n);
        g.head = 0;
    }
    std::vector<std::uint64_t> face_group(mesh_.n_faces(), 0);
    std::vector<char> in_above(mesh_.n_faces(), 0);
    for (std::size_t i = 0; i < maps.face.size(); ++i) {
        const int f = face(int(i));
        if (f < 0) continue;
        if (i < face_group_.size()) face_group[std::size_t(f)] = face_group_[i];
        if (i < in_above_.size()) in_above[std::size_t(f)] = in_above_[i];
    }
    face_group_ = std::move(face_group);
    in_above_ = std::move(in_above);
    kept = 0;
    for (const int f : above_)
        if (face(f) >= 0) above_[kept++] = face(f);
    above_.resize(kept);
    kept = 0;
    for (const auto& [e, f] : below_)
        if (face(f) >= 0) below_[kept++] = {e, face(f)};
    below_.resize(kept);
    std::make_heap(below_.begin(), below_.end());
}

}  // namespace aerial::mesh
