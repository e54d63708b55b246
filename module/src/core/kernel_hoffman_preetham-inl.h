// Internal, per SIMD target (Highway's -inl.h convention): the hoffman-preetham (2002) model's
// kernels. The geometry (distance and phases from reciprocal square root estimates) and the
// channels (one ExpAndExpm1 each) for kN vectors side by side; the float driver
// (ShadeHoffmanPreetham), the Shader of the generic RGBA8 driver, and the dedicated one-pass
// RGBA8 driver with 255 and the exposure folded into its constants (ShadeRgba8HoffmanPreetham).
#if defined(AERIAL_CORE_KERNEL_HOFFMAN_PREETHAM_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef AERIAL_CORE_KERNEL_HOFFMAN_PREETHAM_INL_H_
#undef AERIAL_CORE_KERNEL_HOFFMAN_PREETHAM_INL_H_
#else
#define AERIAL_CORE_KERNEL_HOFFMAN_PREETHAM_INL_H_
#endif

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

#include <hwy/highway.h>

#include "batch_kernels.hpp"
#include "simd_blocks-inl.h"
#include "simd_frame_constants.hpp"
#include "simd_math-inl.h"
#include "simd_outputs-inl.h"

HWY_BEFORE_NAMESPACE();
namespace aerial::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using simd::FrameConstants;

// ---- hoffman-preetham -------------------------------------------------------------------------

/// The 2002 model's per-frame constants as whole vectors, built once per call (or block): the
/// loops take them as memory operands instead of broadcasting them again in every iteration.
struct HoffmanPreethamConstants {
    VF eye_units[3];
    VF meters_per_unit;
    VF max_distance_sq_m2;
    VF hg_peak[3];
    VF hg_a, hg_b_half;
    VF log2_rate[3];  // -beta_ex 8 log2(e): y = log2_rate s (Exp2EighthsParts)
    VF rayleigh_path[3], mie_path[3];
    bool unit_scale;

    explicit HoffmanPreethamConstants(const FrameConstants& k)
        : meters_per_unit(K(k.meters_per_unit)),
          max_distance_sq_m2(K(k.max_distance_sq_m2)),
          hg_a(K(k.hg_a)),
          hg_b_half(K(0.5f * k.hg_b)),
          unit_scale(k.unit_scale) {
        for (int i = 0; i < 3; ++i) {
            eye_units[i] = K(k.eye_units[i]);
            hg_peak[i] = K(k.hg_peak[i]);
            log2_rate[i] = K(float(-double(k.hp_extinction[i]) * simd::kEighthsPerNat));
            rayleigh_path[i] = K(k.hp_rayleigh_path[i]);
            mie_path[i] = K(k.hp_mie_path[i]);
        }
    }
};

/// The 2002 model for kN vectors of positions at once (engine units): F_ex, and L_in when
/// kInScattering; invalid lanes (NaN, Inf, farther than kMaxDistanceM) get F_ex = 1, L_in = 0.
/// Sets valid[j] to the valid lanes of vector j and hands each channel's results to
/// sink(j, std::integral_constant<int, c>, F_ex, L_in) as soon as they are computed (L_in is 0
/// without kInScattering), so that the caller can turn them into codes before the next channel
/// needs the registers. The distance s and the direction d / s come from one refined reciprocal
/// square root of |d|^2 (no square root, no division); per channel one ExpAndExpm1 gives F_ex =
/// exp(-tau) and the path length s phi(tau) = -expm1(-tau) / beta_ex with tau = beta_ex s, exact
/// down to tau = 0 without a series; the phases are computed once per vertex (the
/// Henyey–Greenstein power with a second refined reciprocal square root).
///
/// Why kN vectors: one vector is a chain of dependent operations (square root, exponential
/// polynomial, codes) about as long as the out-of-order window of a core, so one vector at a
/// time leaves execution ports idle waiting on latency. Every step below is written for all kN
/// vectors before the next step, which puts independent work next to each other in program
/// order. Each lane's operations are the same for any kN: the results are bit for bit those of
/// kN = 1.
///
/// In two halves: HoffmanPreethamGeometry gives the valid lanes, s and the phases (over their
/// constants); HoffmanPreethamChannels the channels from them; HoffmanPreethamVectors calls both.
template <bool kInScattering, int kN, bool kMaskDirections = true>
HWY_INLINE void HoffmanPreethamGeometry(const HoffmanPreethamConstants& k, const VF (&x)[kN],
                                        const VF (&y)[kN], const VF (&z)[kN], MF (&valid)[kN],
                                        VF (&s)[kN], VF (&rayleigh)[kN], VF (&mie)[kN]) {
    // Offset from the eye in engine units, then scaled: the difference is exact near the eye
    // (Sterbenz), where scaling first would round both terms at the size of the distance to the
    // origin; and no fused operation, so that every target rounds alike.
    VF dx[kN], dy[kN], dz[kN], s2[kN], inv_s[kN];
#define AERIAL_EACH _Pragma("GCC unroll 8") for (int j = 0; j < kN; ++j)
    AERIAL_EACH {
        dx[j] = hn::Sub(x[j], k.eye_units[0]);
        dy[j] = hn::Sub(y[j], k.eye_units[1]);
        dz[j] = hn::Sub(z[j], k.eye_units[2]);
    }
    if (!k.unit_scale) {
        AERIAL_EACH {
            dx[j] = hn::Mul(dx[j], k.meters_per_unit);
            dy[j] = hn::Mul(dy[j], k.meters_per_unit);
            dz[j] = hn::Mul(dz[j], k.meters_per_unit);
        }
    }
    AERIAL_EACH s2[j] = Dot(dx[j], dy[j], dz[j], dx[j], dy[j], dz[j]);
    AERIAL_EACH valid[j] = hn::Le(s2[j], k.max_distance_sq_m2);  // false for NaN
    // Invalid lanes are moved onto the eye, where F_ex = exp(0) = 1 and L_in = 0 exactly.
    AERIAL_EACH s2[j] = hn::IfThenElseZero(valid[j], s2[j]);
    // |d|^2 below the smallest normal float (|d| < 1.1e-19 m, 0 at the eye) is raised to it
    // for the reciprocal square root: s = |d|^2 / |d| stays 0 at the eye and below 1.1e-19 m
    // elsewhere, and d / s finite.
    AERIAL_EACH inv_s[j] = RefinedRsqrt(hn::Max(s2[j], K(kTiny)));
    AERIAL_EACH s[j] = hn::Mul(s2[j], inv_s[j]);
    if constexpr (kInScattering) {
        // Phases (see Phases): 1 - c' from the chord |d/s - sign(g) sun|^2 / 2, at most 2 but
        // for rounding; the direction of invalid lanes is taken as 0 (their L_in is 0) when
        // kMaskDirections, else their phases are whatever they come out as (NaN, too) and the
        // caller must zero their L_in.
        if constexpr (kMaskDirections) {
            AERIAL_EACH {
                dx[j] = hn::IfThenElseZero(valid[j], dx[j]);
                dy[j] = hn::IfThenElseZero(valid[j], dy[j]);
                dz[j] = hn::IfThenElseZero(valid[j], dz[j]);
            }
        }
        AERIAL_EACH {
            const VF cx = hn::MulSub(dx[j], inv_s[j], k.hg_peak[0]);
            const VF cy = hn::MulSub(dy[j], inv_s[j], k.hg_peak[1]);
            const VF cz = hn::MulSub(dz[j], inv_s[j], k.hg_peak[2]);
            // chord = 2 (1 - c'); the halvings below are exact, so these are the values of
            // 1 - c' = min(chord / 2, 2), c = 1 - (1 - c') and hg_a + hg_b (1 - c').
            const VF chord = hn::Min(Dot(cx, cy, cz, cx, cy, cz), K(4.0f));
            const VF c = hn::NegMulAdd(chord, K(0.5f), K(1.0f));
            rayleigh[j] = hn::MulAdd(c, c, K(1.0f));  // over 3 / (16 pi)
            mie[j] = InversePow32FromEstimate(
                hn::MulAdd(k.hg_b_half, chord, k.hg_a));  // over hg_numerator
        }
    } else {
        (void)rayleigh;
        (void)mie;
    }
#undef AERIAL_EACH
}

/// The channels of HoffmanPreethamVectors from its geometry: per vector, per channel.
template <class M, bool kInScattering, int kN, class Sink>
HWY_INLINE void HoffmanPreethamChannels(const HoffmanPreethamConstants& k, const VF (&s)[kN],
                                        const VF (&rayleigh)[kN], const VF (&mie)[kN],
                                        const Sink& sink) {
    _Pragma("GCC unroll 8") for (int j = 0; j < kN; ++j) {
        ForEachChannel([&](auto channel) {
            constexpr int c = decltype(channel)::value;
            VF extinction, length;
            ExpAndExpm1<M::kExpDegree>(hn::Mul(k.log2_rate[c], s[j]), extinction, length);
            if constexpr (kInScattering) {
                // L = (beta_R P_R + beta_Ms P_M) E_eye s phi(tau), >= 0, with s phi(tau) =
                // -expm1(-tau) / beta_ex and the phase constants folded into hp_*_path (0 where
                // beta_ex is 0: then beta_R = beta_Ms = 0 and L_in is 0 anyway).
                sink(j, channel, extinction,
                     hn::Mul(hn::MulAdd(k.rayleigh_path[c], rayleigh[j],
                                        hn::Mul(k.mie_path[c], mie[j])),
                             length));
            } else {
                (void)length;
                (void)rayleigh;
                (void)mie;
                sink(j, channel, extinction, hn::Zero(DF()));
            }
        });
    }
}

/// HoffmanPreethamGeometry, then HoffmanPreethamChannels.
template <class M, bool kInScattering, int kN, class Sink>
HWY_INLINE void HoffmanPreethamVectors(const HoffmanPreethamConstants& k, const VF (&x)[kN],
                                       const VF (&y)[kN], const VF (&z)[kN], MF (&valid)[kN],
                                       const Sink& sink) {
    VF s[kN], rayleigh[kN], mie[kN];
    HoffmanPreethamGeometry<kInScattering, kN>(k, x, y, z, valid, s, rayleigh, mie);
    HoffmanPreethamChannels<M, kInScattering, kN>(k, s, rayleigh, mie, sink);
}

/// Vectors the one-pass driver of the lit colour (HoffmanPreethamShader) shades together (see
/// HoffmanPreethamVectors); the F_ex and L_in driver takes M::kInterleave, tuned per target.
constexpr int kLitInterleave = 2;

template <class M, bool kInScattering>
std::size_t ShadeHoffmanPreetham(const FrameConstants& k, const KernelBlock& b) {
    const HoffmanPreethamConstants hp(k);
    return ForEachVector(b, [&k, &hp](VF x, VF y, VF z, const VectorOut& out) {
        const VF xs[1] = {x}, ys[1] = {y}, zs[1] = {z};
        MF valid[1];
        HoffmanPreethamVectors<M, kInScattering, 1>(
            hp, xs, ys, zs, valid, [&out](int, auto channel, VF extinction, VF in_scattering) {
                out.Extinction(decltype(channel)::value, extinction);
                if constexpr (kInScattering) {
                    out.InScattering(decltype(channel)::value, in_scattering);
                }
            });
        for (int c = 0; c < 3; ++c) {
            out.SunIrradiance(c, hn::IfThenElseZero(valid[0], K(k.sun_eye[c])));
        }
        return valid[0];
    });
}

/// The 2002 model for the one-pass driver: kLitInterleave vectors at a time
/// (HoffmanPreethamVectors), E_sun = E_eye on the valid lanes when kSun. F_ex = exp(-tau) is in
/// [0, 1] (ExpAndExpm1 of x <= 0) and L_in >= 0, so their codes need fewer clamps.
template <class M, bool kInScattering, bool kSun>
struct HoffmanPreethamShader {
    static constexpr int kN = kLitInterleave;
    static constexpr bool kExtinctionInUnitInterval = true;
    static constexpr bool kInScatteringNonNegative = true;
    const FrameConstants& k;
    const HoffmanPreethamConstants hp;
    explicit HoffmanPreethamShader(const FrameConstants& frame) : k(frame), hp(frame) {}
    HWY_INLINE void operator()(const VF (&x)[kN], const VF (&y)[kN], const VF (&z)[kN],
                               MF (&valid)[kN], VF (&extinction)[kN][3], VF (&in_scattering)[kN][3],
                               VF (&sun)[kN][3]) const {
        HoffmanPreethamVectors<M, kInScattering, kN>(
            hp, x, y, z, valid, [&](int j, auto channel, VF f_ex, VF l_in) {
                extinction[j][decltype(channel)::value] = f_ex;
                in_scattering[j][decltype(channel)::value] = l_in;
            });
        if constexpr (kSun) {
            for (int j = 0; j < kN; ++j) {
                for (int c = 0; c < 3; ++c) {
                    sun[j][c] = hn::IfThenElseZero(valid[j], K(k.sun_eye[c]));
                }
            }
        }
    }
};

/// The 2002 model from positions to F_ex and L_in codes (no lit colour), with less work around
/// the model than ShadeRgba8: the same 8-bit rule on the same model, but 255 and the exposure are
/// folded into the exponential's table and the per-call constants, and each code comes from one
/// fused multiply-add (see `words`), so a code may differ from ShadeRgba8's by one where the
/// value lies within float rounding of a rounding boundary (both are within half a step of the
/// exact value there). kN vectors per step (HoffmanPreethamGeometry); each channel's codes go
/// into the RGBA8 words as soon as the channel is computed, so that only the words stay live
/// across channels; the L_in words of invalid lanes are set to alpha alone at the end (instead
/// of masking their directions: one operation for three). Full steps store the words straight
/// from registers, the last, partial step goes through zero-padded copies and StoreWords.
/// kExtinction / kInScattering: which codes are wanted (at least one).
template <class M, bool kExtinction, bool kInScattering, int kN>
std::size_t ShadeRgba8HoffmanPreetham(const FrameConstants& frame, const Rgba8Job& work) {
    static_assert(kExtinction || kInScattering, "no output");
    // Local copies: the byte stores below cannot alias them, so the constants stay put.
    const HoffmanPreethamConstants k(frame);
    const Rgba8Job job = work;
    const DF d;
    const DI di;
    const std::size_t lanes = hn::Lanes(d);
    const std::size_t step = kN * lanes;
    const bool packed_words = (!kExtinction || job.extinction_stride == 4) &&
                              (!kInScattering || job.in_scattering_stride == 4);
    // A step's geometry: the valid lanes, s and the phases of kN vectors of positions.
    struct Geometry {
        MF valid[kN];
        VF s[kN], rayleigh[kN], mie[kN];
    };
    auto geometry = [&](std::size_t at, std::size_t n, Geometry& g) AERIAL_INLINE_LAMBDA {
        VF x[kN], y[kN], z[kN];
        LoadPositions(job, at, n, x, y, z);
        HoffmanPreethamGeometry<kInScattering, kN, false>(k, x, y, z, g.valid, g.s, g.rayleigh,
                                                          g.mie);
    };
    // Its words: per channel, y = log2_rate s, its parts with the table of 255 2^(j/8)
    // (Exp2EighthsParts), then the codes with one fused multiply-add each:
    //   F_ex  255 F + 1/2 = scale q + (scale + 1/2);
    //   L_in  255 exposure L + 1/2 = t 255 expm1(-tau) + 1/2, 255 expm1 = scale q + (scale -
    //         255), t = exposure (hp_rayleigh_path P_R + hp_mie_path P_M) (exposure folded into
    //         the per-call constants; their sign makes t 255 expm1 >= 0).
    // F_ex codes need no clamp (255 F + 1/2 is in [1/2, 255.5]); L_in codes are clamped on the
    // integers (Unorm8). The caller has checked that t cannot overflow (FoldedInScattering).
    VF in_rayleigh[3], in_mie[3];
    for (int c = 0; c < 3; ++c) {
        in_rayleigh[c] = K(float(double(frame.hp_rayleigh_path[c]) * job.exposure));
        in_mie[c] = K(float(double(frame.hp_mie_path[c]) * job.exposure));
    }
    auto words = [&](const Geometry& g, hn::Vec<DI>(&extinction_words)[kN],
                     hn::Vec<DI>(&in_scattering_words)[kN]) AERIAL_INLINE_LAMBDA {
        const auto alpha = hn::Set(di, static_cast<int32_t>(0xFF000000u));
        const hn::RebindToUnsigned<DF> du;
        for (int j = 0; j < kN; ++j) extinction_words[j] = in_scattering_words[j] = alpha;
        _Pragma("GCC unroll 8") for (int j = 0; j < kN; ++j) {
            ForEachChannel([&](auto channel) {
                constexpr int c = decltype(channel)::value;
                constexpr int kShift = 8 * c;
                VF scale, q;
                Exp2EighthsParts<M::kExpDegree>(hn::Mul(k.log2_rate[c], g.s[j]),
                                                simd::kExp2Eighths255Bits, scale, q);
                if constexpr (kExtinction) {
                    const auto code =
                        TruncateInRange(hn::MulAdd(scale, q, hn::Add(scale, K(0.5f))));
                    extinction_words[j] = hn::Or(extinction_words[j], hn::ShiftLeft<kShift>(code));
                }
                if constexpr (kInScattering) {
                    const VF expm1_255 = hn::MulAdd(scale, q, hn::Sub(scale, K(255.0f)));
                    const VF t =
                        hn::MulAdd(in_rayleigh[c], g.rayleigh[j], hn::Mul(in_mie[c], g.mie[j]));
                    const auto code =
                        hn::BitCast(du, TruncateInRange(hn::MulAdd(t, expm1_255, K(0.5f))));
                    in_scattering_words[j] = hn::Or(
                        in_scattering_words[j],
                        hn::ShiftLeft<kShift>(hn::BitCast(di, hn::Min(code, hn::Set(du, 255u)))));
                }
            });
        }
        if constexpr (kInScattering) {
            for (int j = 0; j < kN; ++j) {
                in_scattering_words[j] =
                    hn::IfThenElse(hn::RebindMask(di, g.valid[j]), in_scattering_words[j], alpha);
            }
        }
    };
    std::size_t invalid = 0;
    std::size_t i = 0;
    // Full steps, words stored straight from registers. (Computing the next step's geometry
    // before this step's channels, software pipelining, was 2-4 % slower on AVX2 and AVX-512
    // with these kernels: the geometry is carried in memory.)
    auto store_step = [&](std::size_t at, const Geometry& g, const hn::Vec<DI>(&e)[kN],
                          const hn::Vec<DI>(&l)[kN]) AERIAL_INLINE_LAMBDA {
        _Pragma("GCC unroll 8") for (int j = 0; j < kN; ++j) {
            const std::size_t vertex = at + j * lanes;
            invalid += hn::CountTrue(d, hn::Not(g.valid[j]));
            if constexpr (kExtinction) {
                hn::StoreU(e[j], di, reinterpret_cast<int32_t*>(job.extinction + 4 * vertex));
            }
            if constexpr (kInScattering) {
                hn::StoreU(l[j], di, reinterpret_cast<int32_t*>(job.in_scattering + 4 * vertex));
            }
        }
    };
    if (packed_words) {
        for (; i + step <= job.count; i += step) {
            Geometry g;
            geometry(i, step, g);
            hn::Vec<DI> extinction_words[kN], in_scattering_words[kN];
            words(g, extinction_words, in_scattering_words);
            store_step(i, g, extinction_words, in_scattering_words);
        }
    }
    auto shade = [&](std::size_t at, std::size_t n, MF(&valid)[kN],
                     hn::Vec<DI>(&extinction_words)[kN], hn::Vec<DI>(&in_scattering_words)[kN])
                     AERIAL_INLINE_LAMBDA {
                         Geometry g;
                         geometry(at, n, g);
                         words(g, extinction_words, in_scattering_words);
                         for (int j = 0; j < kN; ++j) valid[j] = g.valid[j];
                     };
    // Strided words, and the last, partial step (LoadPositions zero-pads it).
    for (; i < job.count; i += step) {
        const std::size_t n = std::min(step, job.count - i);
        MF valid[kN];
        hn::Vec<DI> extinction_words[kN], in_scattering_words[kN];
        shade(i, n, valid, extinction_words, in_scattering_words);
        for (int j = 0; j < kN && j * lanes < n; ++j) {
            const std::size_t at = i + j * lanes;
            const std::size_t m = std::min(lanes, n - j * lanes);
            invalid += hn::CountTrue(d, hn::AndNot(valid[j], hn::FirstN(d, m)));
            if constexpr (kExtinction) {
                StoreWords(extinction_words[j], job.extinction + at * job.extinction_stride,
                           job.extinction_stride, m);
            }
            if constexpr (kInScattering) {
                StoreWords(in_scattering_words[j],
                           job.in_scattering + at * job.in_scattering_stride,
                           job.in_scattering_stride, m);
            }
        }
    }
    return invalid;
}

/// Whether ShadeRgba8HoffmanPreetham may fold the exposure into its L_in constants: t =
/// exposure (hp_rayleigh_path P_R + hp_mie_path P_M) must stay finite for every direction
/// (P_R = 1 + c^2 <= 2, P_M = base^(-3/2) <= hg_a^(-3/2)), else an infinite t times a zero path
/// at the eye would give NaN instead of 0. Only for exposures and irradiances near the float
/// range; ShadeRgba8 (the rule on the float values) takes those.
inline bool FoldedInScattering(const FrameConstants& k, float exposure) {
    if (!(k.hg_a > 0.0f)) return false;
    const double mie_max = std::pow(double(k.hg_a), -1.5);
    for (int c = 0; c < 3; ++c) {
        const double t = double(exposure) * (2.0 * std::abs(double(k.hp_rayleigh_path[c])) +
                                             std::abs(double(k.hp_mie_path[c])) * mie_max);
        if (!(t < 1e37)) return false;
    }
    return true;
}

// NOLINTNEXTLINE(google-readability-namespace-comments)
}  // namespace HWY_NAMESPACE
}  // namespace aerial::detail
HWY_AFTER_NAMESPACE();

#endif  // AERIAL_CORE_KERNEL_HOFFMAN_PREETHAM_INL_H_
