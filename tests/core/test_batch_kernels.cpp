// The block kernels (batch_kernels.hpp): the SIMD kernel in both precisions against the scalar
// kernel and the double-precision model over realistic scenes, in 8-bit steps (LSB); the same
// extreme-range stability sweep as test_stability.cpp; tails, null outputs and invalid
// vertices; and the kernel's own building blocks (erfcx, fast exp2/log2) against the standard
// library in double. Each accuracy test prints its worst error, the figures quoted in the docs:
//   build/bin/test_core_batch_kernels
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/validation/test_hooks.hpp"
#include "batch_kernels.hpp"
#include "extreme_sampler.hpp"
#include "forced_target.hpp"

namespace {

using aerial::Atmosphere;
using aerial::Frame;
using aerial::Model;
using aerial::View;
using aerial::detail::kBlockSize;
using aerial::detail::KernelBlock;
using aerial::detail::KernelPrecision;
using aerial::testing::ExtremeSampler;
using aerial::testing::ForcedTarget;
using aerial::testing::Random;
using glm::dvec3;

constexpr double kLsb = 255.0;
/// The accurate SIMD kernel must stay within this of the double model (8-bit steps).
constexpr double kAccurateToleranceLsb = 0.5;
/// The fast SIMD kernel must stay below this.
constexpr double kFastToleranceLsb = 1.0;

enum class KernelKind { scalar, simd_accurate, simd_fast };
constexpr KernelKind kAllKernels[] = {KernelKind::scalar, KernelKind::simd_accurate,
                                      KernelKind::simd_fast};
constexpr KernelKind kSimdKernels[] = {KernelKind::simd_accurate, KernelKind::simd_fast};

const char* kernel_name(KernelKind k) {
    switch (k) {
        case KernelKind::scalar:
            return "scalar";
        case KernelKind::simd_accurate:
            return "simd accurate";
        case KernelKind::simd_fast:
            return "simd fast";
    }
    return "?";
}

std::string model_string(Model m) { return std::string(aerial::model_name(m)); }

/// Structure-of-arrays positions and outputs of any length.
struct Vertices {
    std::vector<float> x, y, z;
    void push(const glm::vec3& p) {
        x.push_back(p.x);
        y.push_back(p.y);
        z.push_back(p.z);
    }
    std::size_t size() const { return x.size(); }
    glm::vec3 at(std::size_t i) const { return {x[i], y[i], z[i]}; }
};

struct Shaded {
    std::array<std::vector<float>, 3> extinction, in_scattering, sun_irradiance;
    std::size_t invalid = 0;
};

std::size_t shade_block(KernelKind kernel, const Frame<float>& frame, const KernelBlock& block) {
    switch (kernel) {
        case KernelKind::scalar:
            return aerial::detail::shade_block_scalar(frame, block);
        case KernelKind::simd_accurate:
            return aerial::detail::shade_block_simd(frame, block, KernelPrecision::accurate);
        case KernelKind::simd_fast:
            return aerial::detail::shade_block_simd(frame, block, KernelPrecision::fast);
    }
    return 0;
}

/// Runs a kernel over all vertices, block by block, with every output requested.
Shaded shade(KernelKind kernel, const Frame<float>& frame, const Vertices& v) {
    Shaded out;
    for (int c = 0; c < 3; ++c) {
        out.extinction[c].assign(v.size(), -1.0f);
        out.in_scattering[c].assign(v.size(), -1.0f);
        out.sun_irradiance[c].assign(v.size(), -1.0f);
    }
    for (std::size_t first = 0; first < v.size(); first += kBlockSize) {
        KernelBlock b;
        b.x = v.x.data() + first;
        b.y = v.y.data() + first;
        b.z = v.z.data() + first;
        b.count = std::min(kBlockSize, v.size() - first);
        for (int c = 0; c < 3; ++c) {
            b.extinction[c] = out.extinction[c].data() + first;
            b.in_scattering[c] = out.in_scattering[c].data() + first;
            b.sun_irradiance[c] = out.sun_irradiance[c].data() + first;
        }
        out.invalid += shade_block(kernel, frame, b);
    }
    return out;
}

// ---- (1) Accuracy over realistic scenes --------------------------------------------------------

/// A point at distance `distance_m` from the eye (on the up axis, at `eye_altitude_m`) and at
/// `altitude_m` above the sphere, in the direction `azimuth_rad` (up = +Z).
dvec3 point_at(const Atmosphere& a, double eye_altitude_m, double distance_m, double altitude_m,
               double azimuth_rad) {
    const double re = a.planet_radius_m + eye_altitude_m, rt = a.planet_radius_m + altitude_m;
    const double cos_gamma =
        std::clamp((re * re + rt * rt - distance_m * distance_m) / (2 * re * rt), -1.0, 1.0);
    const double sin_gamma = std::sqrt(1 - cos_gamma * cos_gamma);
    return dvec3(rt * sin_gamma * std::cos(azimuth_rad), rt * sin_gamma * std::sin(azimuth_rad),
                 rt * cos_gamma - a.planet_radius_m);
}

/// Worst error of one kernel against the double model, in LSB.
struct Worst {
    double extinction_lsb = 0.0;
    double in_scattering_lsb = 0.0;
    std::string where_extinction, where_in_scattering;
};

struct SceneSet {
    Model model;
    int frames_per_preset;
    int points_per_frame;
    unsigned seed;
};

/// Runs every kernel over random frames of the five presets (eye 2 m..10 km, sun -10..90 deg,
/// points 1 m..200 km from the eye at ground or sky altitudes) and returns each kernel's worst
/// error against prepare_frame<double> + scatter. L_in is scaled per frame by the exposure that
/// maps the frame's brightest L_in (double model) to 1.
std::array<Worst, 3> scene_errors(const SceneSet& set, long long* vertices) {
    std::array<Worst, 3> worst;
    Random random(set.seed);
    *vertices = 0;
    for (const char* preset : {"earth", "hazy", "foggy", "mars", "hp2002"}) {
        const Atmosphere a = *aerial::atmosphere_preset(preset);
        for (int f = 0; f < set.frames_per_preset; ++f) {
            const double eye_altitude = random.log_uniform(2.0, 1e4);
            const double elevation = random.uniform(-10.0, 90.0) * aerial::kPi / 180;
            const double azimuth = random.uniform(0.0, 2 * aerial::kPi);
            View view;
            view.eye = {0.0, 0.0, eye_altitude};
            view.sun_dir = {std::cos(elevation) * std::cos(azimuth),
                            std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
            const auto frame_f = aerial::prepare_frame<float>(a, view, set.model);
            const auto frame_d = aerial::prepare_frame<double>(a, view, set.model);
            EXPECT_TRUE(frame_f.ok() && frame_d.ok());
            if (!frame_f.ok() || !frame_d.ok()) return worst;

            Vertices v;
            for (int p = 0; p < set.points_per_frame; ++p) {
                const double altitude =
                    random.chance(0.5) ? random.uniform(0.0, 3000.0) : random.log_uniform(1.0, 3e4);
                double distance = random.log_uniform(1.0, 2e5);
                const double climb = altitude - eye_altitude;
                const double target =
                    std::abs(climb) <= distance
                        ? altitude
                        : std::max(0.0, eye_altitude + std::copysign(distance, climb) *
                                                           random.uniform(0.0, 1.0));
                distance = std::max(distance, std::abs(target - eye_altitude));
                v.push(glm::vec3(point_at(a, eye_altitude, distance, target,
                                          random.uniform(0.0, 2 * aerial::kPi))));
            }
            std::vector<aerial::Scattering<double>> truth(v.size());
            double brightest = 0.0;
            for (std::size_t i = 0; i < v.size(); ++i) {
                truth[i] = aerial::scatter(*frame_d, glm::dvec3(v.at(i)));
                for (int c = 0; c < 3; ++c) {
                    brightest = std::max(brightest, truth[i].in_scattering[c]);
                }
            }
            const double exposure = brightest > 0.0 ? 1.0 / brightest : 0.0;
            for (KernelKind k : kAllKernels) {
                const Shaded s = shade(k, *frame_f, v);
                Worst& w = worst[int(k)];
                for (std::size_t i = 0; i < v.size(); ++i) {
                    for (int c = 0; c < 3; ++c) {
                        const double ef =
                            kLsb * std::abs(s.extinction[c][i] - truth[i].extinction[c]);
                        const double el =
                            kLsb * exposure *
                            std::abs(s.in_scattering[c][i] - truth[i].in_scattering[c]);
                        if (!(ef <= w.extinction_lsb) || !(el <= w.in_scattering_lsb)) {
                            char where[320];
                            std::snprintf(where, sizeof where,
                                          "%s eye %.1f m, sun elevation %.2f deg, point "
                                          "(%.1f %.1f %.1f), channel %d: got F %.6g L %.6g, "
                                          "double F %.6g L %.6g, exposure %.4g",
                                          preset, eye_altitude, elevation * 180 / aerial::kPi,
                                          double(v.x[i]), double(v.y[i]), double(v.z[i]), c,
                                          double(s.extinction[c][i]), double(s.in_scattering[c][i]),
                                          truth[i].extinction[c], truth[i].in_scattering[c],
                                          exposure);
                            if (!(ef <= w.extinction_lsb)) {
                                w.extinction_lsb = std::isnan(ef) ? 1e30 : ef;
                                w.where_extinction = where;
                            }
                            if (!(el <= w.in_scattering_lsb)) {
                                w.in_scattering_lsb = std::isnan(el) ? 1e30 : el;
                                w.where_in_scattering = where;
                            }
                        }
                    }
                }
            }
            *vertices += static_cast<long long>(v.size());
        }
    }
    return worst;
}

void check_scenes(const SceneSet& set, long long min_vertices) {
    long long vertices = 0;
    const auto worst = scene_errors(set, &vertices);
    for (KernelKind k : kAllKernels) {
        const Worst& w = worst[int(k)];
        std::printf(
            "%-16s %-13s vs double: max F_ex %.4f LSB, max L_in %.4f LSB (%lld vertices, "
            "target %s)\n",
            model_string(set.model).c_str(), kernel_name(k), w.extinction_lsb, w.in_scattering_lsb,
            vertices, aerial::detail::simd_target_name());
    }
    EXPECT_GE(vertices, min_vertices);
    for (KernelKind k : kAllKernels) {
        const Worst& w = worst[int(k)];
        const double tolerance =
            k == KernelKind::simd_fast ? kFastToleranceLsb : kAccurateToleranceLsb;
        EXPECT_LE(w.extinction_lsb, tolerance)
            << kernel_name(k) << " F_ex is off the double model at " << w.where_extinction;
        EXPECT_LE(w.in_scattering_lsb, tolerance)
            << kernel_name(k) << " L_in is off the double model at " << w.where_in_scattering;
    }
}

// 5 presets x 40 frames x 5120 points = 1.02e6 vertices per model.
TEST(BatchKernelAccuracy, HoffmanPreethamAccurateIsWithinHalfAnLsbAndFastWithinOneLsb) {
    check_scenes({Model::hoffman_preetham, 40, 5120, 11}, 1000000);
}
TEST(BatchKernelAccuracy, HeightAccurateIsWithinHalfAnLsbAndFastWithinOneLsb) {
    check_scenes({Model::height, 40, 5120, 12}, 1000000);
}

// ---- (2) Stability over extreme ranges ----------------------------------------------------------

bool physical(const Shaded& s, std::size_t i) {
    for (int c = 0; c < 3; ++c) {
        const float f = s.extinction[c][i], l = s.in_scattering[c][i], e = s.sun_irradiance[c][i];
        if (!std::isfinite(f) || !std::isfinite(l) || !std::isfinite(e)) return false;
        if (f < 0.0f || f > 1.0f || l < 0.0f || e < 0.0f) return false;
    }
    return true;
}

void sweep(Model model, unsigned seed, int frames, int points) {
    ExtremeSampler sampler(seed);
    long long evaluated[2] = {0, 0}, bad[2] = {0, 0};
    for (int f = 0; f < frames; ++f) {
        const Atmosphere a = sampler.atmosphere();
        const View v = sampler.view(a);
        const auto frame = aerial::testing::extreme_frame<float>(a, v, model);
        ASSERT_TRUE(frame.ok()) << "frame " << f << ": " << frame.error().message;
        Vertices vertices;
        for (int p = 0; p < points; ++p) vertices.push(glm::vec3(sampler.point(v)));
        for (KernelKind k : kSimdKernels) {
            const int slot = k == KernelKind::simd_fast ? 1 : 0;
            const Shaded s = shade(k, *frame, vertices);
            for (std::size_t i = 0; i < vertices.size(); ++i) {
                ++evaluated[slot];
                if (!physical(s, i) && ++bad[slot] <= 5) {
                    const glm::vec3 p = vertices.at(i);
                    ADD_FAILURE() << model_string(model) << " " << kernel_name(k) << " frame " << f
                                  << " point " << i << ": F=(" << s.extinction[0][i] << " "
                                  << s.extinction[1][i] << " " << s.extinction[2][i] << ") L=("
                                  << s.in_scattering[0][i] << " " << s.in_scattering[1][i] << " "
                                  << s.in_scattering[2][i] << ") E=(" << s.sun_irradiance[0][i]
                                  << " " << s.sun_irradiance[1][i] << " " << s.sun_irradiance[2][i]
                                  << ")\n  atmosphere " << aerial::to_json(a) << "  eye " << v.eye.x
                                  << "," << v.eye.y << "," << v.eye.z << " sun " << v.sun_dir.x
                                  << "," << v.sun_dir.y << "," << v.sun_dir.z << " up " << v.up.x
                                  << "," << v.up.y << "," << v.up.z << " m/unit "
                                  << v.meters_per_unit << " point " << p.x << "," << p.y << ","
                                  << p.z;
                }
            }
        }
    }
    for (int slot = 0; slot < 2; ++slot) {
        std::printf("%s %s: %lld combinations, %lld unphysical\n", model_string(model).c_str(),
                    slot ? "simd fast" : "simd accurate", evaluated[slot], bad[slot]);
        EXPECT_EQ(bad[slot], 0);
    }
}

// 4000 frames x 256 points = 1.02e6 combinations per model and precision.
TEST(BatchKernelStability, HoffmanPreethamSimdIsAlwaysPhysical) {
    sweep(Model::hoffman_preetham, 21, 4000, 256);
}
TEST(BatchKernelStability, HeightSimdIsAlwaysPhysical) { sweep(Model::height, 22, 4000, 256); }

// ---- (3) Tails, null outputs, invalid vertices ------------------------------------------------

/// An array whose last element ends exactly at a PROT_NONE page: reading or writing past it
/// crashes the test instead of passing silently.
class GuardedArray {
  public:
    explicit GuardedArray(std::size_t n) : n_(n) {
        page_ = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
        const std::size_t bytes = n * sizeof(float);
        data_pages_ = (bytes + page_ - 1) / page_ + 1;
        void* p = mmap(nullptr, (data_pages_ + 1) * page_, PROT_READ | PROT_WRITE,
                       MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        base_ = p == MAP_FAILED ? nullptr : static_cast<unsigned char*>(p);
        if (base_) mprotect(base_ + data_pages_ * page_, page_, PROT_NONE);
    }
    ~GuardedArray() {
        if (base_) munmap(base_, (data_pages_ + 1) * page_);
    }
    GuardedArray(const GuardedArray&) = delete;
    GuardedArray& operator=(const GuardedArray&) = delete;
    bool ok() const { return base_ != nullptr; }
    float* data() { return reinterpret_cast<float*>(base_ + data_pages_ * page_) - n_; }

  private:
    std::size_t n_, page_ = 0, data_pages_ = 0;
    unsigned char* base_ = nullptr;
};

aerial::Result<Frame<float>> test_frame(Model model, const char* preset = "earth") {
    View v;
    v.eye = {100.0, -50.0, 300.0};
    v.sun_dir = glm::normalize(dvec3(0.3, 0.5, 0.2));
    return aerial::prepare_frame<float>(*aerial::atmosphere_preset(preset), v, model);
}

Vertices landscape(std::size_t n, unsigned seed) {
    Random random(seed);
    Vertices v;
    for (std::size_t i = 0; i < n; ++i) {
        v.push(glm::vec3(random.uniform(-3e4, 3e4), random.uniform(-3e4, 3e4),
                         random.uniform(0.0, 2000.0)));
    }
    return v;
}

/// The relative difference allowed between the accurate SIMD kernel and the scalar kernel on
/// ordinary input (float rounding in a different order).
constexpr float kKernelRelativeTolerance = 2e-5f;

void expect_close(float simd, float scalar, const char* what, std::size_t i) {
    EXPECT_NEAR(simd, scalar, kKernelRelativeTolerance * std::max(std::abs(scalar), 1e-3f))
        << what << " of vertex " << i;
}

TEST(BatchKernelTails, AnyCountIsShadedWithoutTouchingMemoryPastIt) {
    for (Model model : {Model::hoffman_preetham, Model::height}) {
        const auto frame = test_frame(model);
        ASSERT_TRUE(frame.ok());
        for (std::size_t count : {std::size_t(1), std::size_t(7), std::size_t(255), kBlockSize}) {
            const Vertices v = landscape(count, unsigned(count));
            GuardedArray x(count), y(count), z(count);
            std::array<GuardedArray*, 9> outputs;
            std::vector<std::unique_ptr<GuardedArray>> storage;
            for (auto& o : outputs) {
                storage.push_back(std::make_unique<GuardedArray>(count));
                o = storage.back().get();
            }
            ASSERT_TRUE(x.ok() && y.ok() && z.ok());
            std::copy(v.x.begin(), v.x.end(), x.data());
            std::copy(v.y.begin(), v.y.end(), y.data());
            std::copy(v.z.begin(), v.z.end(), z.data());
            KernelBlock b;
            b.x = x.data();
            b.y = y.data();
            b.z = z.data();
            b.count = count;
            for (int c = 0; c < 3; ++c) {
                b.extinction[c] = outputs[c]->data();
                b.in_scattering[c] = outputs[3 + c]->data();
                b.sun_irradiance[c] = outputs[6 + c]->data();
            }
            const Shaded scalar = shade(KernelKind::scalar, *frame, v);
            for (KernelKind k : kSimdKernels) {
                EXPECT_EQ(shade_block(k, *frame, b), 0u) << kernel_name(k) << " count " << count;
                if (k != KernelKind::simd_accurate) continue;
                for (std::size_t i = 0; i < count; ++i) {
                    for (int c = 0; c < 3; ++c) {
                        expect_close(b.extinction[c][i], scalar.extinction[c][i], "F_ex", i);
                        expect_close(b.in_scattering[c][i], scalar.in_scattering[c][i], "L_in", i);
                        expect_close(b.sun_irradiance[c][i], scalar.sun_irradiance[c][i], "E_sun",
                                     i);
                    }
                }
            }
        }
    }
}

TEST(BatchKernelOutputs, NullOutputsAreSkippedAndTheOthersAreUnchanged) {
    const Vertices v = landscape(200, 5);
    for (Model model : {Model::hoffman_preetham, Model::height}) {
        const auto frame = test_frame(model);
        ASSERT_TRUE(frame.ok());
        for (KernelKind k : kSimdKernels) {
            const Shaded all = shade(k, *frame, v);
            // Each quantity alone, then one channel of each, then nothing at all.
            for (int wanted = 0; wanted < 5; ++wanted) {
                std::array<std::vector<float>, 9> out;
                for (auto& o : out) o.assign(v.size(), -7.0f);
                KernelBlock b;
                b.x = v.x.data();
                b.y = v.y.data();
                b.z = v.z.data();
                b.count = v.size();
                for (int c = 0; c < 3; ++c) {
                    if (wanted == 0 || (wanted == 3 && c == 0)) b.extinction[c] = out[c].data();
                    if (wanted == 1 || (wanted == 3 && c == 1)) {
                        b.in_scattering[c] = out[3 + c].data();
                    }
                    if (wanted == 2 || (wanted == 3 && c == 2)) {
                        b.sun_irradiance[c] = out[6 + c].data();
                    }
                }
                EXPECT_EQ(shade_block(k, *frame, b), 0u);
                for (int q = 0; q < 9; ++q) {
                    const float* requested = q < 3   ? b.extinction[q]
                                             : q < 6 ? b.in_scattering[q - 3]
                                                     : b.sun_irradiance[q - 6];
                    const std::vector<float>& reference = q < 3   ? all.extinction[q]
                                                          : q < 6 ? all.in_scattering[q - 3]
                                                                  : all.sun_irradiance[q - 6];
                    for (std::size_t i = 0; i < v.size(); ++i) {
                        if (requested) {
                            ASSERT_EQ(out[q][i], reference[i])
                                << model_string(model) << " " << kernel_name(k) << " output " << q
                                << " vertex " << i << " differs when others are null";
                        } else {
                            ASSERT_EQ(out[q][i], -7.0f) << "output " << q << " was written";
                        }
                    }
                }
            }
        }
    }
}

TEST(BatchKernelOutputs, InvalidVerticesAreCountedAndGetNoScattering) {
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    constexpr float kInf = std::numeric_limits<float>::infinity();
    Vertices v = landscape(37, 9);
    const std::size_t bad[] = {0, 3, 8, 9, 20, 36};
    v.x[0] = kNaN;
    v.y[3] = kInf;
    v.z[8] = -kInf;
    v.x[9] = 2e12f;  // farther than kMaxDistanceM
    v.z[20] = kNaN;
    v.x[36] = 3e38f;
    for (Model model : {Model::hoffman_preetham, Model::height}) {
        const auto frame = test_frame(model, "foggy");
        ASSERT_TRUE(frame.ok());
        for (KernelKind k : kAllKernels) {
            const Shaded s = shade(k, *frame, v);
            EXPECT_EQ(s.invalid, std::size(bad)) << model_string(model) << " " << kernel_name(k);
            for (std::size_t i = 0; i < v.size(); ++i) {
                const bool invalid = std::find(std::begin(bad), std::end(bad), i) != std::end(bad);
                for (int c = 0; c < 3; ++c) {
                    if (invalid) {
                        EXPECT_EQ(s.extinction[c][i], 1.0f) << kernel_name(k) << " vertex " << i;
                        EXPECT_EQ(s.in_scattering[c][i], 0.0f) << kernel_name(k) << " vertex " << i;
                        EXPECT_EQ(s.sun_irradiance[c][i], 0.0f)
                            << kernel_name(k) << " vertex " << i;
                    } else {
                        EXPECT_TRUE(physical(s, i)) << kernel_name(k) << " vertex " << i;
                        EXPECT_LT(s.extinction[c][i], 1.0f) << kernel_name(k) << " vertex " << i;
                        EXPECT_GT(s.in_scattering[c][i], 0.0f) << kernel_name(k) << " vertex " << i;
                    }
                }
            }
        }
    }
}

TEST(BatchKernelOutputs, VertexAtTheEyeHasNoExtinctionAndNoInScattering) {
    for (Model model : {Model::hoffman_preetham, Model::height}) {
        const auto frame = test_frame(model);
        ASSERT_TRUE(frame.ok());
        Vertices v;
        v.push(glm::vec3(frame->view.eye));
        for (KernelKind k : kSimdKernels) {
            const Shaded s = shade(k, *frame, v);
            for (int c = 0; c < 3; ++c) {
                EXPECT_EQ(s.extinction[c][0], 1.0f) << kernel_name(k);
                EXPECT_EQ(s.in_scattering[c][0], 0.0f) << kernel_name(k);
            }
        }
    }
}

// ---- (4) Building blocks against the standard library ------------------------------------------

/// exp(y^2) erfc(y) in double (long double where double would overflow), asymptotic beyond 100.
double erfcx_reference(double y) {
    if (y < 100.0) {
        const long double ly = y;
        return double(std::exp(ly * ly) * std::erfc(ly));
    }
    const double inv2 = 1.0 / (y * y);
    return 0.56418958354775628695 / y *
           (1 - inv2 * (0.5 - inv2 * (0.75 - inv2 * (1.875 - inv2 * 6.5625))));
}

void check_erfcx() {
    constexpr double kTolerance = 1e-5;  // relative
    std::vector<float> y;
    for (int i = 0; i <= 200000; ++i) y.push_back(float(i) * 5e-5f);  // [0, 10], dense
    for (double v = 10.0; v < 1e4; v *= 1.001) y.push_back(float(v));
    std::vector<float> got(y.size());
    aerial::detail::simd_erfcx(y.data(), got.data(), y.size());
    double worst = 0.0, worst_at = 0.0;
    for (std::size_t i = 0; i < y.size(); ++i) {
        const double e = std::abs(got[i] / erfcx_reference(double(y[i])) - 1.0);
        if (!(e <= worst)) worst = e, worst_at = double(y[i]);
    }
    std::printf("erfcx (%s): max relative error %.3g at y = %g over %zu values in [0, 1e4]\n",
                aerial::detail::simd_target_name(), worst, worst_at, y.size());
    EXPECT_LE(worst, kTolerance) << "at y = " << worst_at;
}

/// Where the exponentials must be exact for F_ex = exp(-tau) and L_in: 0 and -0 (the eye), a tiny
/// depth, far below the float range, -inf and NaN.
const float kExpSpecialInputs[] = {0.0f,
                                   -0.0f,
                                   -1e-7f,
                                   -200.0f,
                                   -std::numeric_limits<float>::infinity(),
                                   std::numeric_limits<float>::quiet_NaN()};

void check_fast_exp2() {
    constexpr double kTolerance = 1e-5;  // relative
    std::vector<float> x;
    for (double v = -126.0; v <= 127.0; v += 1.0 / 1024) x.push_back(float(v));
    for (float v = -1e-3f; v <= 1e-3f; v += 1e-6f) x.push_back(v);
    std::vector<float> got(x.size());
    aerial::detail::simd_fast_exp2(x.data(), got.data(), x.size());
    double worst = 0.0, worst_at = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        const double e = std::abs(got[i] / std::exp2(double(x[i])) - 1.0);
        if (!(e <= worst)) worst = e, worst_at = double(x[i]);
    }
    std::printf(
        "fast exp2 (%s): max relative error %.3g at x = %g over %zu values in "
        "[-126, 127]\n",
        aerial::detail::simd_target_name(), worst, worst_at, x.size());
    EXPECT_LE(worst, kTolerance) << "at x = " << worst_at;

    // Exact where it matters for F_ex = exp(-tau): 1 at 0, never above 1 below 0, 0 far below.
    float out[std::size(kExpSpecialInputs)];
    aerial::detail::simd_fast_exp2(kExpSpecialInputs, out, std::size(kExpSpecialInputs));
    EXPECT_EQ(out[0], 1.0f);
    EXPECT_EQ(out[1], 1.0f);
    EXPECT_LE(out[2], 1.0f);
    EXPECT_EQ(out[3], 0.0f);
    EXPECT_EQ(out[4], 0.0f);
    EXPECT_TRUE(std::isfinite(out[5])) << "NaN in a masked-off lane must not stay NaN";
}

void check_fast_log2() {
    constexpr double kTolerance = 1e-5;  // absolute, in log2 units
    std::vector<float> x;
    for (double v = 1e-37; v < 3e38; v *= 1.0001) x.push_back(float(v));
    for (float v = 0.5f; v <= 2.0f; v += 1e-6f) x.push_back(v);
    std::vector<float> got(x.size());
    aerial::detail::simd_fast_log2(x.data(), got.data(), x.size());
    double worst = 0.0, worst_at = 0.0, worst_relative_near_one = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        const double exact = std::log2(double(x[i]));
        const double e = std::abs(got[i] - exact);
        if (!(e <= worst)) worst = e, worst_at = double(x[i]);
        if (std::abs(x[i] - 1.0f) < 0.25f && exact != 0.0) {
            worst_relative_near_one = std::max(worst_relative_near_one, e / std::abs(exact));
        }
    }
    std::printf(
        "fast log2 (%s): max absolute error %.3g at x = %g over %zu values in "
        "[1e-37, 3e38]; relative near 1: %.3g\n",
        aerial::detail::simd_target_name(), worst, worst_at, x.size(), worst_relative_near_one);
    EXPECT_LE(worst, kTolerance) << "at x = " << worst_at;
    EXPECT_LE(worst_relative_near_one, 1e-4) << "log2 must stay relatively accurate near 1";
    const float one = 1.0f;
    float out = -1.0f;
    aerial::detail::simd_fast_log2(&one, &out, 1);
    EXPECT_EQ(out, 0.0f);
}

/// The 2002 kernel's exp and expm1 of minus an optical depth (ExpAndExpm1, which takes it in
/// eighths of a binary order, y = 8 log2(e) x) against the standard library in double: relative
/// errors against 2^(y/8) for the float y nearest to 8 log2(e) x, x over [-87.3, 0] (every
/// 2^-12, and densely near 0 where expm1 is small), and the values that make F_ex and L_in exact
/// at the eye and bounded.
void check_exp_and_expm1(bool fast) {
    // Accurate: table rounding (6e-8), degree-4 truncation (2.9e-8) and the rounding of the
    // polynomial for exp; expm1 also carries the table rounding through scale - 1 where it
    // cancels (measured 2.1e-7 near y = -1/2). Fast: degree-3 truncation (3.4e-6).
    const double exp_tolerance = fast ? 1e-5 : 2e-7;
    const double expm1_tolerance = fast ? 1e-5 : 5e-7;
    constexpr double kEighthsPerNat = 8.0 * 1.44269504088896340736;
    std::vector<float> y;
    for (double v = -87.3; v <= 0.0; v += 1.0 / 4096) y.push_back(float(kEighthsPerNat * v));
    for (double v = 1e-30; v < 1.0; v *= 1.001) y.push_back(float(-kEighthsPerNat * v));
    std::vector<float> e(y.size()), m(y.size());
    aerial::detail::simd_exp_and_expm1(y.data(), e.data(), m.data(), y.size(), fast);
    double worst_exp = 0.0, worst_expm1 = 0.0, exp_at = 0.0, expm1_at = 0.0;
    for (std::size_t i = 0; i < y.size(); ++i) {
        const double x = double(y[i]) / kEighthsPerNat;
        const double xe = std::abs(e[i] / std::exp(x) - 1.0);
        const double xm = std::abs(m[i] / std::expm1(x) - 1.0);
        if (!(xe <= worst_exp)) worst_exp = xe, exp_at = x;
        if (y[i] != 0.0f && !(xm <= worst_expm1)) worst_expm1 = xm, expm1_at = x;
    }
    std::printf(
        "%s exp/expm1 of the 2002 kernel (%s): max relative error %.3g at x = %g, %.3g at "
        "x = %g over %zu values in [-87.3, 0]\n",
        fast ? "fast" : "accurate", aerial::detail::simd_target_name(), worst_exp, exp_at,
        worst_expm1, expm1_at, y.size());
    EXPECT_LE(worst_exp, exp_tolerance) << "exp at x = " << exp_at;
    EXPECT_LE(worst_expm1, expm1_tolerance) << "expm1 at x = " << expm1_at;

    float special[std::size(kExpSpecialInputs)];
    for (std::size_t i = 0; i < std::size(kExpSpecialInputs); ++i) {
        special[i] = float(kEighthsPerNat * kExpSpecialInputs[i]);
    }
    float exp_out[std::size(kExpSpecialInputs)], expm1_out[std::size(kExpSpecialInputs)];
    aerial::detail::simd_exp_and_expm1(special, exp_out, expm1_out, std::size(special), fast);
    EXPECT_EQ(exp_out[0], 1.0f) << "F_ex must be 1 at the eye";
    EXPECT_EQ(expm1_out[0], 0.0f) << "L_in must be 0 at the eye";
    EXPECT_EQ(exp_out[1], 1.0f);
    EXPECT_EQ(expm1_out[1], 0.0f);
    EXPECT_LE(exp_out[2], 1.0f);
    EXPECT_LT(expm1_out[2], 0.0f);
    for (std::size_t i = 3; i < std::size(kExpSpecialInputs); ++i) {
        EXPECT_TRUE(std::isfinite(exp_out[i]) && std::isfinite(expm1_out[i]))
            << "x = " << kExpSpecialInputs[i] << " must give finite values";
        EXPECT_LE(exp_out[i], 1e-37f) << "x = " << kExpSpecialInputs[i];
        EXPECT_EQ(expm1_out[i], -1.0f) << "x = " << kExpSpecialInputs[i];
    }
}

TEST(BatchKernelMath, ErfcxIsWithinTheToleranceOfStdErfc) { check_erfcx(); }
TEST(BatchKernelMath, ExpAndExpm1OfTheHoffmanPreethamKernelAreWithinTheirBounds) {
    check_exp_and_expm1(false);
    check_exp_and_expm1(true);
}
TEST(BatchKernelMath, FastExp2IsWithinTheToleranceOfStdExp2) { check_fast_exp2(); }
TEST(BatchKernelMath, FastLog2IsWithinTheToleranceOfStdLog2) { check_fast_log2(); }

// ---- Every target this CPU can run ------------------------------------------------------------

TEST(BatchKernelTargets, DispatcherPicksTheBestTargetAndNamesIt) {
    const auto targets = aerial::validation::simd_test_targets();
    ASSERT_FALSE(targets.empty());
    std::string list;
    for (const auto& t : targets) list += " " + t;
    std::printf("SIMD target: %s (compiled and supported:%s)\n", aerial::detail::simd_target_name(),
                list.c_str());
    EXPECT_EQ(targets.front(), aerial::detail::simd_target_name());
}

TEST(BatchKernelTargets, EveryTargetMatchesTheDoubleModelAndStaysPhysical) {
    // A smaller share of the scenes and of the sweep, and the building blocks, on each target
    // (the SSE4 or SCALAR code runs on users' older CPUs).
    for (const std::string& target : aerial::validation::simd_test_targets()) {
        SCOPED_TRACE("target " + target);
        const ForcedTarget forced(target);
        ASSERT_TRUE(forced.ok());
        ASSERT_EQ(std::string(aerial::detail::simd_target_name()), target);
        check_scenes({Model::hoffman_preetham, 2, 2560, 31}, 25600);
        check_scenes({Model::height, 2, 2560, 32}, 25600);
        sweep(Model::hoffman_preetham, 33, 100, 256);
        sweep(Model::height, 34, 100, 256);
        check_erfcx();
        check_fast_exp2();
        check_fast_log2();
        check_exp_and_expm1(false);
        check_exp_and_expm1(true);
    }
}

}  // namespace
