// The SIMD block kernels: the hoffman-preetham and height models of scattering.cpp, vectorised
// with Google Highway and dispatched at run time to the best target the CPU offers (SSE4, AVX2,
// AVX-512, ...). Every branch of the scalar models is a mask here (IfThenElse); uniform
// per-frame decisions stay `if`s. Two precisions (batch_kernels.hpp):
//   accurate  Highway's Exp/Log/Expm1/Log1p (about 1 ulp);
//   fast      polynomial exp2/log2 with exponent bit manipulation (relative error 5.4e-6,
//             absolute 2e-6 in log2).
// Both take expm1(z) from its Taylor series for |z| < 1/2 and from an exp already computed
// beyond it where there is one (F_ex), which keeps the per-vertex cost at one exp per channel.
// The 2002 model, whose cost is all in the exponentials, has its own (Exp2EighthsParts): exp and
// expm1 from one range reduction in eighths of a binary order, a table of 2^(j/8) and a
// degree-4 (accurate) or degree-3 (fast) polynomial, and the distance and the Henyey–Greenstein
// power from reciprocal square root estimates and a Newton step; it also runs from positions
// straight to RGBA8 codes in one pass, 255 and the exposure folded into its constants
// (ShadeRgba8HoffmanPreetham; ShadeRgba8 takes the height model and the lit colour).
// The scaled complementary error function of the Chapman factor is the rational form of
// Numerical Recipes (erfcc, fractional error below 1.2e-7 for every y >= 0), kept in log form so
// that log(H Ch) costs one log and no exp.
//
// Where float rounding makes the scalar code ill-conditioned the kernel is more accurate than it
// (and closer to the double model): the Henyey–Greenstein base near either peak (see Phases),
// the planet-shadow test for planets whose radius float resolves to metres (see
// FrameConstants::shadow_*), and 1 / tau_total for subnormal depths.
//
// This file is the driver: Highway compiles it once per target (foreach_target.h) with the
// per-target files it includes, and it holds the entry points of each target, their dispatch
// (HWY_EXPORT / HWY_DYNAMIC_DISPATCH) and the test hooks. The parts:
//   simd_frame_constants.hpp       per-frame constants (target-independent);
//   simd_math-inl.h                vector types, exp/log/expm1/erfcx, the two precisions;
//   simd_blocks-inl.h              loads from and stores to the caller's arrays, block loops;
//   simd_outputs-inl.h             8-bit codes, RGBA8 words, the one-pass RGBA8 driver;
//   kernel_hoffman_preetham-inl.h  the 2002 model (float and RGBA8 drivers);
//   kernel_height-inl.h            the height model.
#include <cstdint>
#include <string>
#include <vector>

#include "batch_kernels.hpp"
#include "simd_frame_constants.hpp"

// The kernels keep vectors in small arrays and structs, which scalable vectors (SVE, RVV) do not
// allow: those targets are not compiled (Arm gets NEON).
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SVE | HWY_SVE2 | HWY_SVE_256 | HWY_SVE2_128 | HWY_RVV)
#endif
// Highway re-includes this file once per SIMD target. The path is relative to module/include,
// the include directory every translation unit of aerial_core has.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "../src/core/batch_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include "kernel_height-inl.h"
#include "kernel_hoffman_preetham-inl.h"
#include "simd_blocks-inl.h"
#include "simd_math-inl.h"
#include "simd_outputs-inl.h"

// ---- Per-target part --------------------------------------------------------------------------
HWY_BEFORE_NAMESPACE();
namespace aerial::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using simd::FrameConstants;

/// The driver for the job's model, precision and outputs.
template <class M>
std::size_t ShadeRgba8For(const FrameConstants& k, Model model, const Rgba8Job& job) {
    const bool in_scattering = job.in_scattering != nullptr;
    const bool lit = job.lit != nullptr;
    if (model == Model::hoffman_preetham) {
        if (lit) {
            return in_scattering
                       ? ShadeRgba8<M, HoffmanPreethamShader<M, true, true>, true, true>(k, job)
                       : ShadeRgba8<M, HoffmanPreethamShader<M, false, true>, false, true>(k, job);
        }
        if (!in_scattering) {
            return ShadeRgba8HoffmanPreetham<M, true, false, M::kInterleave>(k, job);
        }
        // The folded kernel's exposure is the clamp's.
        if (job.exponential_tone || !FoldedInScattering(k, job.exposure)) {
            return ShadeRgba8<M, HoffmanPreethamShader<M, true, false>, true, false>(k, job);
        }
        return job.extinction ? ShadeRgba8HoffmanPreetham<M, true, true, M::kInterleave>(k, job)
                              : ShadeRgba8HoffmanPreetham<M, false, true, M::kInterleave>(k, job);
    }
    if (lit) {
        return in_scattering ? ShadeRgba8<M, HeightShader<M, true, true>, true, true>(k, job)
                             : ShadeRgba8<M, HeightShader<M, false, true>, false, true>(k, job);
    }
    return in_scattering ? ShadeRgba8<M, HeightShader<M, true, false>, true, false>(k, job)
                         : ShadeRgba8<M, HeightShader<M, false, false>, false, false>(k, job);
}

// ---- Per-target entry points ------------------------------------------------------------------

template <class M>
std::size_t ShadeWith(const FrameConstants& k, Model model, const KernelBlock& b) {
    const bool in_scattering = b.in_scattering[0] || b.in_scattering[1] || b.in_scattering[2];
    const bool sun = b.sun_irradiance[0] || b.sun_irradiance[1] || b.sun_irradiance[2];
    if (model == Model::hoffman_preetham) {
        return in_scattering ? ShadeHoffmanPreetham<M, true>(k, b)
                             : ShadeHoffmanPreetham<M, false>(k, b);
    }
    if (in_scattering) {
        return sun ? ShadeHeight<M, true, true>(k, b) : ShadeHeight<M, true, false>(k, b);
    }
    return sun ? ShadeHeight<M, false, true>(k, b) : ShadeHeight<M, false, false>(k, b);
}

std::size_t ShadeBlockSimd(const Frame<float>& frame, const KernelBlock& block, bool fast) {
    if (block.count == 0) return 0;
    const FrameConstants k = simd::make_frame_constants(frame);
    return fast ? ShadeWith<FastMath>(k, frame.model, block)
                : ShadeWith<AccurateMath>(k, frame.model, block);
}

std::size_t ShadeRgba8Simd(const Frame<float>& frame, const Rgba8Job& job, bool fast) {
    if (job.count == 0) return 0;
    const FrameConstants k = simd::make_frame_constants(frame);
    return fast ? ShadeRgba8For<FastMath>(k, frame.model, job)
                : ShadeRgba8For<AccurateMath>(k, frame.model, job);
}

const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

/// Applies a vector function to n floats (any n), through padded copies for the tail.
template <class F>
void ApplyToArray(const float* in, float* out, std::size_t n, const F& f) {
    const DF d;
    const std::size_t lanes = hn::Lanes(d);
    HWY_ALIGN float pad[kMaxLanes] = {};
    for (std::size_t i = 0; i < n; i += lanes) {
        const std::size_t m = std::min(lanes, n - i);
        std::memcpy(pad, in + i, m * sizeof(float));
        hn::Store(f(hn::Load(d, pad)), d, pad);
        std::memcpy(out + i, pad, m * sizeof(float));
    }
}

void ErfcxArray(const float* in, float* out, std::size_t n) {
    ApplyToArray(in, out, n, [](VF y) { return Erfcx<AccurateMath>(y); });
}
void FastExp2Array(const float* in, float* out, std::size_t n) {
    ApplyToArray(in, out, n, [](VF x) { return FastExp2(x); });
}
void FastLog2Array(const float* in, float* out, std::size_t n) {
    ApplyToArray(in, out, n, [](VF x) { return FastLog2(x); });
}
void ExpAndExpm1Array(const float* in, float* exp_out, float* expm1_out, std::size_t n, bool fast) {
    ApplyToArray(in, exp_out, n, [fast](VF x) {
        VF e, m;
        fast ? ExpAndExpm1<FastMath::kExpDegree>(x, e, m)
             : ExpAndExpm1<AccurateMath::kExpDegree>(x, e, m);
        return e;
    });
    ApplyToArray(in, expm1_out, n, [fast](VF x) {
        VF e, m;
        fast ? ExpAndExpm1<FastMath::kExpDegree>(x, e, m)
             : ExpAndExpm1<AccurateMath::kExpDegree>(x, e, m);
        return m;
    });
}

// NOLINTNEXTLINE(google-readability-namespace-comments)
}  // namespace HWY_NAMESPACE
}  // namespace aerial::detail
HWY_AFTER_NAMESPACE();

// ---- Dispatch ---------------------------------------------------------------------------------
#if HWY_ONCE
namespace aerial::detail {

HWY_EXPORT(ShadeBlockSimd);
HWY_EXPORT(ShadeRgba8Simd);
HWY_EXPORT(TargetName);
HWY_EXPORT(PackRgba8);
HWY_EXPORT(Deinterleave3);
HWY_EXPORT(ErfcxArray);
HWY_EXPORT(FastExp2Array);
HWY_EXPORT(FastLog2Array);
HWY_EXPORT(ExpAndExpm1Array);

std::size_t shade_block_simd(const Frame<float>& frame, const KernelBlock& block,
                             KernelPrecision precision) {
    if (frame.model != Model::hoffman_preetham && frame.model != Model::height) {
        return shade_block_scalar(frame, block);  // the reference model has no SIMD kernel
    }
    return HWY_DYNAMIC_DISPATCH(ShadeBlockSimd)(frame, block, precision == KernelPrecision::fast);
}

std::size_t shade_rgba8(const Frame<float>& frame, const Rgba8Job& job, KernelPrecision precision) {
    return HWY_DYNAMIC_DISPATCH(ShadeRgba8Simd)(frame, job, precision == KernelPrecision::fast);
}

const char* simd_target_name() { return HWY_DYNAMIC_DISPATCH(TargetName)(); }

void pack_rgba8(const float* r, const float* g, const float* b, std::size_t n, float scale,
                std::uint32_t* out) {
    HWY_DYNAMIC_DISPATCH(PackRgba8)(r, g, b, n, scale, out);
}

void deinterleave3(const float* xyz, std::size_t n, float* x, float* y, float* z) {
    HWY_DYNAMIC_DISPATCH(Deinterleave3)(xyz, n, x, y, z);
}

// Test hooks (declared by tests/core/test_batch_kernels.cpp): the dispatched target's building
// blocks applied to arrays, for accuracy tests against the standard library in double.
void simd_erfcx(const float* y, float* out, std::size_t n) {
    HWY_DYNAMIC_DISPATCH(ErfcxArray)(y, out, n);
}
void simd_fast_exp2(const float* x, float* out, std::size_t n) {
    HWY_DYNAMIC_DISPATCH(FastExp2Array)(x, out, n);
}
void simd_fast_log2(const float* x, float* out, std::size_t n) {
    HWY_DYNAMIC_DISPATCH(FastLog2Array)(x, out, n);
}
void simd_exp_and_expm1(const float* x, float* exp_out, float* expm1_out, std::size_t n,
                        bool fast) {
    HWY_DYNAMIC_DISPATCH(ExpAndExpm1Array)(x, exp_out, expm1_out, n, fast);
}

// Test hooks: the targets compiled here that this CPU runs, and forcing one of them (an empty
// name goes back to the best), so that the tests cover every code path a user's CPU may take.
std::vector<std::string> simd_test_targets() {
    std::vector<std::string> names;
    for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
        names.emplace_back(hwy::TargetName(target));
    }
    return names;
}
bool simd_test_use_target(const std::string& name) {
    hwy::SetSupportedTargetsForTest(0);
    if (name.empty()) return true;
    for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
        if (name == hwy::TargetName(target)) {
            hwy::SetSupportedTargetsForTest(target);
            return true;
        }
    }
    return false;
}

}  // namespace aerial::detail
#endif  // HWY_ONCE
