// hairscatter — the Chiang fiber (models/chiang.hpp) over a batch of hits of one material,
// for renderers that shade many hits at once (wavefront path tracers): structure-of-arrays
// in and out, the hits processed in blocks (kWidth, then kTail), every step one loop across
// the hits of a block, so that GCC and Clang vectorise across hits (eight floats to an AVX
// register) where the one-hit calls vectorise across the four lobes.
//
//   ChiangBatch<float> batch(material);
//   batch.eval(ChiangBatchQuery<float>{n, h, {wo_x, wo_y, wo_z}, {wi_x, wi_y, wi_z}}, {f_r, f_g, f_b});
//
// Each result is the one-hit call's, ChiangFiber<T>(material, h[i]).eval(wo_i, wi_i) and so
// on, computed by the same formulas in the same order: equal to the last bit, or within
// what the compilers' contraction of products into FMAs changes between vector and scalar
// code (tests/chiang_batch_test.cpp states and enforces the bound; under -ffast-math, with
// HAIRSCATTER_ALLOW_FAST_MATH, the sums are reassociated and only the zeros for bad input
// and the absence of NaN and Inf hold). The same contract for hostile input: a non-finite
// or zero wo or wi, or non-finite u, gives 0 (eval, pdf) or the empty sample (wi 0, weight
// 0, pdf 0, SampledLobe::kNone); other lengths are normalised and u is clamped into [0, 1].
// All four lobes are kept (no lobe subsets); the material's lobe controls apply.
//
// On a GPU the model is one thread per hit: eval_at(q, i, f) and friends shade hit i alone
// (a block of one). The material and every array must then be in device memory.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../lobes/attenuation.hpp"
#include "../lobes/azimuthal.hpp"
#include "../lobes/longitudinal.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "chiang.hpp"
#include "contract.hpp"

namespace hairscatter {

// Three arrays of n values: the x, y and z components of n directions, or the r, g and b
// channels of n colours.
template <typename T> struct ConstArrays3 {
    const T* x = nullptr;
    const T* y = nullptr;
    const T* z = nullptr;
};
template <typename T> struct Arrays3 {
    T* x = nullptr;
    T* y = nullptr;
    T* z = nullptr;
};

// n hits for eval, pdf and eval_pdf: hit i at offset h[i] ∈ [-1, 1] (clamped, as the
// one-hit fiber does), seen from wo_i and lit from wi_i (fiber frame, fiber/frame.hpp).
template <typename T> struct ChiangBatchQuery {
    std::size_t n = 0;
    const T* h = nullptr;
    ConstArrays3<T> wo, wi;
};
// n hits for sample: the four uniform numbers of hit i are u[0][i] … u[3][i].
template <typename T> struct ChiangBatchSampleQuery {
    std::size_t n = 0;
    const T* h = nullptr;
    ConstArrays3<T> wo;
    const T* u[4] = {nullptr, nullptr, nullptr, nullptr};
};
// Where sample writes: wi, weight = f / pdf (RGB in x, y, z), pdf and the lobe drawn.
template <typename T> struct ChiangBatchSamples {
    Arrays3<T> wi, weight;
    T* pdf = nullptr;
    SampledLobe* lobe = nullptr;
};

namespace detail {

// The one-hit helpers in the forms whose loops across hits vectorise. GCC (under the default
// -ftrapping-math) leaves a loop scalar when it holds a floating-point `c ? a : b` (clamp's,
// a max, a fold): those are selects here (math/functions.hpp: select), each with the
// one-hit helper's result bit for bit. The elementary functions: on the host in float elem's
// own polynomials with their range choices as selects (the one-hit calls branch, or use
// vectors of the lobes); in double and on a GPU, elem's functions.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T lane_clamp(T x, T lo, T hi) {
    const T above = select(x < lo, lo, x);  // clamp's two steps
    return select(above > hi, hi, above);
}
// x, or floor where x is not above it (the one-hit code's `x > floor ? x : floor`).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T lane_floor_at(T x, T floor) {
    return select(x > floor, x, floor);
}
// max(x, 0): the argument of safe_sqrt, for a block's square roots.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T sqrt_arg(T x) { return lane_floor_at(x, T(0)); }
// (1 - s)(1 + s), floored at 0: cos_from_sin's argument.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T cos2_from_sin(T s) {
    return sqrt_arg((T(1) - s) * (T(1) + s));
}
// wrap_pi_once and wrap_pi (math/functions.hpp).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T lane_wrap_pi_once(T x) {
    x = select(x > kPi<T>, x - kTwoPi<T>, select(x < -kPi<T>, x + kTwoPi<T>, x));
    return lane_clamp(x, -kPi<T>, kPi<T>);
}
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T lane_wrap_pi(T x) {
    using std::floor;
    x -= kTwoPi<T> * floor((x + kPi<T>) * kInvTwoPi<T>);
    return lane_clamp(x, -kPi<T>, kPi<T>);
}
// TrimmedLogistic::exponent_of_difference(d, minus_inv_s).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T lane_exponent_of_difference(T d, T minus_inv_s) {
    const T a = abs_value(d);
    const T near = a * minus_inv_s, far = (kTwoPi<T> - a) * minus_inv_s;
    return select(far > near, far, near);
}

template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T lane_exp(T x) {
#if !defined(__CUDA_ARCH__)
    if constexpr (std::is_same<T, float>::value) return elem::detail::exp_float<true>(x);
#endif
    return elem::exp(x);
}
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T lane_log(T x) {
#if !defined(__CUDA_ARCH__)
    if constexpr (std::is_same<T, float>::value) return elem::detail::log_float(x);
#endif
    return elem::log(x);
}
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void lane_sincos(T x, T& s, T& c) {
#if !defined(__CUDA_ARCH__)
    if constexpr (std::is_same<T, float>::value) {
        elem::detail::sincos_float_reduced(x, s, c);  // (|x| ≤ 2π here)
        return;
    }
#endif
    elem::sincos(x, s, c);
}
// The argument of the square root elem::asin takes for |x| > 0.7, which the block computes
// for all lanes at once (elem::sqrt_each: std::sqrt in a loop keeps it scalar).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T asin_root_arg(T x) {
    return T(0.5) * (T(1) - lane_clamp(abs_value(x), T(0), T(1)));
}
// elem::asin(x) with root = √asin_root_arg(x): both of its forms, the choice a select.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T lane_asin(T x, T root) {
#if !defined(__CUDA_ARCH__)
    if constexpr (std::is_same<T, float>::value) {
        const float ax = lane_clamp(std::fabs(x), 0.0f, 1.0f);
        const float r = select(ax <= elem::kAsinSmallMax, elem::detail::asin_small_poly(ax),
                               kHalfPi<float> - 2.0f * elem::detail::asin_small_poly(root));
        return std::copysign(r, x);
    }
#endif
    (void)root;
    return elem::asin(x);
}
// elem::atan2(y, x), its maximum, minimum and the denominator's guard as selects.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T lane_atan2(T y, T x) {
#if !defined(__CUDA_ARCH__)
    if constexpr (std::is_same<T, float>::value) {
        const float ax = std::fabs(x), ay = std::fabs(y);
        const float hi = select(ay > ax, ay, ax), lo = select(ax < ay, ax, ay);
        const float a = lo / select(hi <= 0.0f, 1.0f, hi);
        const float d = ax - ay;
        const float base = (kHalfPi<float> - std::copysign(kHalfPi<float>, x)) +
                           std::copysign(kQuarterPi<float> - std::copysign(kQuarterPi<float>, d), x);
        const float signed_a = std::copysign(a, d * x);
        return std::copysign(base + signed_a * elem::detail::atan_unit_factor(a), y);
    }
#endif
    return elem::atan2(y, x);
}
// chosen_index<4>(w, target) (math/distributions.hpp) of the four lobe weights, its
// choices as integer arithmetic and the weights as values (an array of them in memory kept
// GCC's loop scalar): the count of cumulative sums at or below the target, raised to the
// first lobe with weight and capped at the last one (0 if none has weight).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE int lane_chosen_index(T w0, T w1, T w2, T w3, T target) {
    const T cum0 = T(0) + w0, cum1 = cum0 + w1, cum2 = cum1 + w2;  // (chosen_index's running sum)
    const int k = int(target >= cum0) + int(target >= cum1) + int(target >= cum2);
    const int p0 = int(w0 > T(0)), p1 = int(w1 > T(0)), p2 = int(w2 > T(0)), p3 = int(w3 > T(0));
    auto pick = [](int c, int a, int b) { return b + (a - b) * c; };  // c ? a : b, c ∈ {0, 1}
    const int first = pick(p0, 0, pick(p1, 1, pick(p2, 2, 3)));
    const int last = pick(p3, 3, pick(p2, 2, pick(p1, 1, 0)));
    const int raised = pick(int(k < first), first, k);
    return pick(int(raised > last), last, raised);
}

}  // namespace detail

// The Chiang fiber's eval, pdf, eval_pdf and sample over n hits of one material (see the
// top of this file). Refers to its material by pointer, as ChiangFiber does: the material
// must outlive it.
template <typename T> class ChiangBatch {
  public:
    using Material = ChiangMaterial<T>;
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    static constexpr int kLobes = Material::kLobes;
    // Hits per block: 32 in float (four AVX registers per step, so that the long chains of
    // neighbouring vectors overlap: faster than 8 or 16, no slower than 64; measured in
    // docs/performance.md, batched calls), 16 in double; the hits left over go in blocks
    // of kTail, padded.
    static constexpr int kWidth = std::is_same<T, float>::value ? 32 : 16;
    static constexpr int kTail = std::is_same<T, float>::value ? 8 : 4;

    HAIRSCATTER_HD explicit ChiangBatch(const Material& material) : mat_(&material) {}
    ChiangBatch(const Material&&) = delete;

    HAIRSCATTER_HD const Material& material() const { return *mat_; }

    // f of every hit into f (r, g, b in x, y, z).
    HAIRSCATTER_HD void eval(const ChiangBatchQuery<T>& q, const Arrays3<T>& f) const { run<true, false>(q, f, nullptr); }
    // The pdf of every hit.
    HAIRSCATTER_HD void pdf(const ChiangBatchQuery<T>& q, T* pdf) const { run<false, true>(q, Arrays3<T>{}, pdf); }
    // Both, sharing their terms.
    HAIRSCATTER_HD void eval_pdf(const ChiangBatchQuery<T>& q, const Arrays3<T>& f, T* pdf) const {
        run<true, true>(q, f, pdf);
    }
    // A sample of every hit.
    HAIRSCATTER_HD void sample(const ChiangBatchSampleQuery<T>& q, const ChiangBatchSamples<T>& out) const {
        std::size_t i = 0;
        for (; q.n - i >= std::size_t(kWidth); i += std::size_t(kWidth)) sample_block<kWidth>(q, i, kWidth, out);
        for (; i < q.n; i += std::size_t(kTail)) sample_block<kTail>(q, i, block_count<kTail>(q.n, i), out);
    }

    // Hit i alone (i < q.n): one GPU thread's share of the batch.
    HAIRSCATTER_HD void eval_at(const ChiangBatchQuery<T>& q, std::size_t i, const Arrays3<T>& f) const {
        query_block<1, true, false>(q, i, 1, f, nullptr);
    }
    HAIRSCATTER_HD void pdf_at(const ChiangBatchQuery<T>& q, std::size_t i, T* pdf) const {
        query_block<1, false, true>(q, i, 1, Arrays3<T>{}, pdf);
    }
    HAIRSCATTER_HD void eval_pdf_at(const ChiangBatchQuery<T>& q, std::size_t i, const Arrays3<T>& f, T* pdf) const {
        query_block<1, true, true>(q, i, 1, f, pdf);
    }
    HAIRSCATTER_HD void sample_at(const ChiangBatchSampleQuery<T>& q, std::size_t i, const ChiangBatchSamples<T>& out) const {
        sample_block<1>(q, i, 1, out);
    }

  private:
    template <int W> static HAIRSCATTER_HD int block_count(std::size_t n, std::size_t i) {
        return n - i < std::size_t(W) ? int(n - i) : W;
    }

    // The wo terms of W hits, lane j one hit (ChiangFiber's Outgoing, transposed).
    template <int W> struct Outgoing {
        T a[std::size_t(kLobes + 1)][3][std::size_t(W)];  // A_p per channel, times the lobe weights
        T w[std::size_t(kLobes + 1)][std::size_t(W)];     // the lobe selection weights, not normalised
        T w_total[std::size_t(W)], inv_w_total[std::size_t(W)];
        DeonLanes<T, W> m[std::size_t(kLobes + 1)];  // lobe p conditioned on the tilted θo' of each hit
        T phi_p[std::size_t(kLobes)][std::size_t(W)];             // Φ(p, h), wrapped (the residual's is 0)
    };
    // One block's directions, made unit; ok[j] false where the input was not valid (the lane
    // then holds a valid stand-in, and its results are replaced by zeros).
    template <int W> struct Hits {
        T h[std::size_t(W)];
        T wo[3][std::size_t(W)];
        bool ok[std::size_t(W)];
    };

    template <bool kF, bool kPdf>
    HAIRSCATTER_HD void run(const ChiangBatchQuery<T>& q, const Arrays3<T>& f, T* pdf) const {
        std::size_t i = 0;
        for (; q.n - i >= std::size_t(kWidth); i += std::size_t(kWidth)) query_block<kWidth, kF, kPdf>(q, i, kWidth, f, pdf);
        for (; i < q.n; i += std::size_t(kTail)) query_block<kTail, kF, kPdf>(q, i, block_count<kTail>(q.n, i), f, pdf);
    }

    // Reads hit i0 + j into lane j; the lanes past count repeat hit i0 (valid input whose
    // results are not written), so that every block computes whole vectors.
    template <int W>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE static std::size_t source(std::size_t i0, int j, int count) {
        return i0 + std::size_t(j < count ? j : 0);
    }

    // The common block, read as whole vectors: a whole block (count = W) whose directions
    // are all unit to within to_unit's tolerance |w|² - 1 ≤ 1e-5 (which also rules out
    // NaN and Inf), taken as they are, as unit_directions would (true); else false, and the
    // caller checks and normalises lane by lane.
    template <int W>
    static HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE bool load_directions(const ConstArrays3<T>& w, std::size_t i0, T (&out)[3][std::size_t(W)],
                                                                     int& bad) {
        for (int j = 0; j < W; ++j) {
            const std::size_t i = i0 + std::size_t(j);
            out[0][j] = w.x[i], out[1][j] = w.y[i], out[2][j] = w.z[i];
            const T l2 = out[0][j] * out[0][j] + out[1][j] * out[1][j] + out[2][j] * out[2][j];
            // (is_finite reads the bits: under -ffast-math the comparison may not see a NaN)
            bad |= int(!(abs_value(l2 - T(1)) <= T(1e-5))) | int(!is_finite(l2));
        }
        return bad == 0;
    }
    template <int W>
    static HAIRSCATTER_HD bool load_unit(const ConstArrays3<T>& wo, const ConstArrays3<T>& wi, std::size_t i0, int count,
                                         T (&wo_out)[3][std::size_t(W)], T (&wi_out)[3][std::size_t(W)]) {
        if (count != W) return false;
        int bad = 0;
        load_directions<W>(wo, i0, wo_out, bad);
        return load_directions<W>(wi, i0, wi_out, bad);
    }
    // The same for sample: wo, and u finite (then clamped into [0, 1], as unit_numbers does).
    template <int W>
    static HAIRSCATTER_HD bool load_unit_and_numbers(const ChiangBatchSampleQuery<T>& q, std::size_t i0, int count,
                                                     T (&wo_out)[3][std::size_t(W)], T (&u_out)[4][std::size_t(W)]) {
        if (count != W) return false;
        int bad = 0;
        for (int c = 0; c < 4; ++c)
            for (int j = 0; j < W; ++j) {
                const T x = q.u[c][i0 + std::size_t(j)];
                bad |= int(!is_finite(x));
                u_out[c][j] = select(x < T(0), T(0), select(x > T(1), T(1), x));
            }
        return load_directions<W>(q.wo, i0, wo_out, bad);
    }
    // clamped_offset of every hit's h (the lanes past count repeat hit i0).
    template <int W>
    static HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void load_offsets(const T* h, std::size_t i0, int count, T (&out)[std::size_t(W)]) {
        T x[std::size_t(W)];
        if (count == W)
            for (int j = 0; j < W; ++j) x[j] = h[i0 + std::size_t(j)];
        else
            for (int j = 0; j < W; ++j) x[j] = h[source<W>(i0, j, count)];
        for (int j = 0; j < W; ++j) {
            const T c = select(x[j] > T(1), T(1), select(x[j] >= T(-1), x[j], T(-1)));
            out[j] = select(is_finite(c), c, T(-1));
        }
    }

    template <int W, bool kF, bool kPdf>
    HAIRSCATTER_HD void query_block(const ChiangBatchQuery<T>& q, std::size_t i0, int count, const Arrays3<T>& f_out,
                                    T* pdf_out) const {
        Hits<W> hits;
        T wi[3][std::size_t(W)];
        if (!load_unit<W>(q.wo, q.wi, i0, count, hits.wo, wi)) {
            for (int j = 0; j < W; ++j) {
                const std::size_t s = source<W>(i0, j, count);
                V3 wo_j(q.wo.x[s], q.wo.y[s], q.wo.z[s]), wi_j(q.wi.x[s], q.wi.y[s], q.wi.z[s]);
                hits.ok[j] = unit_directions(wo_j, wi_j);  // (FiberModel's check, the same normalisation)
                if (!hits.ok[j]) wo_j = wi_j = V3(T(0), T(1), T(0));
                for (int c = 0; c < 3; ++c) {
                    hits.wo[c][j] = wo_j[c];
                    wi[c][j] = wi_j[c];
                }
            }
        } else {
            for (int j = 0; j < W; ++j) hits.ok[j] = true;
        }
        load_offsets<W>(q.h, i0, count, hits.h);
        Outgoing<W> o;
        outgoing<W, kPdf>(hits, o);
        // θi and φ of wi (ChiangFiber::query).
        T sin_i[std::size_t(W)], cos_i[std::size_t(W)], sqrt_cos_i[std::size_t(W)], phi[std::size_t(W)];
        for (int j = 0; j < W; ++j) {
            sin_i[j] = detail::lane_clamp(wi[0][j], T(-1), T(1));
            cos_i[j] = detail::cos2_from_sin(sin_i[j]);
            phi[j] = relative_azimuth(hits, j, wi[1][j], wi[2][j]);
        }
        elem::sqrt_each(cos_i);
        for (int j = 0; j < W; ++j) sqrt_cos_i[j] = cos_i[j];
        elem::sqrt_each(sqrt_cos_i);
        T f[3][std::size_t(W)], pdf[std::size_t(W)];
        combine<W, kF, kPdf>(o, sin_i, cos_i, sqrt_cos_i, phi, f, pdf);
        for (int j = 0; j < W && j < count; ++j) {
            const std::size_t i = i0 + std::size_t(j);
            if constexpr (kF) {
                f_out.x[i] = hits.ok[j] ? f[0][j] : T(0);
                f_out.y[i] = hits.ok[j] ? f[1][j] : T(0);
                f_out.z[i] = hits.ok[j] ? f[2][j] : T(0);
            }
            if constexpr (kPdf) pdf_out[i] = hits.ok[j] ? pdf[j] : T(0);
        }
    }

    template <int W>
    HAIRSCATTER_HD void sample_block(const ChiangBatchSampleQuery<T>& q, std::size_t i0, int count,
                                     const ChiangBatchSamples<T>& out) const {
        Hits<W> hits;
        T u[4][std::size_t(W)];
        if (!load_unit_and_numbers<W>(q, i0, count, hits.wo, u)) {
            for (int j = 0; j < W; ++j) {
                const std::size_t s = source<W>(i0, j, count);
                V3 wo_j(q.wo.x[s], q.wo.y[s], q.wo.z[s]);
                V4 u_j(q.u[0][s], q.u[1][s], q.u[2][s], q.u[3][s]);
                hits.ok[j] = unit_direction_and_numbers(wo_j, u_j);  // (FiberModel::sample's check)
                if (!hits.ok[j]) wo_j = V3(T(0), T(1), T(0)), u_j = V4(T(0.5));
                for (int c = 0; c < 3; ++c) hits.wo[c][j] = wo_j[c];
                for (int c = 0; c < 4; ++c) u[c][j] = u_j[c];
            }
        } else {
            for (int j = 0; j < W; ++j) hits.ok[j] = true;
        }
        load_offsets<W>(q.h, i0, count, hits.h);
        Outgoing<W> o;
        outgoing<W, true>(hits, o);

        // sinθi of every lobe from (u.y, u.z) (DeonLongitudinal::sample_sin_theta_each's
        // steps, lobe by lobe across the hits), then the lobe ∝ w (chosen_index, as the
        // one-hit sample) and its θi.
        T lobe_sin[std::size_t(kLobes + 1)][std::size_t(W)];
        T sin_az[std::size_t(W)], cos_az[std::size_t(W)];
        for (int j = 0; j < W; ++j) detail::lane_sincos(kTwoPi<T> * u[2][j], sin_az[j], cos_az[j]);
        for (int p = 0; p <= kLobes; ++p) {
            const T v = mat_->lobe_variance(p), e = mat_->lobe_exp_m2_over_v(p);
            const DeonLanes<T, W>& m = o.m[p];
            T omc[std::size_t(W)], root[std::size_t(W)];
            for (int j = 0; j < W; ++j) {
                const T arg = detail::lane_floor_at(u[1][j] + (T(1) - u[1][j]) * e, kMinNormal<T>);
                omc[j] = detail::lane_clamp(-v * detail::lane_log(arg), T(0), T(2));  // 1 - c
                root[j] = omc[j] * (T(2) - omc[j]);
            }
            elem::sqrt_each(root);
            for (int j = 0; j < W; ++j)
                lobe_sin[p][j] = detail::lane_clamp(-(T(1) - omc[j]) * m.sin_o[j] + root[j] * cos_az[j] * m.cos_o[j],
                                                    T(-1), T(1));
        }
        // N_p's sample of u.w (TrimmedLogistic::sample, one loop of its own: its constants
        // are the distribution's).
        const TrimmedLogistic<T>& n = mat_->azimuthal();
        T dphi[std::size_t(W)];
        for (int j = 0; j < W; ++j) dphi[j] = n.sample(u[3][j]);
        int lobe[std::size_t(W)];
        T sin_i[std::size_t(W)], cos_i[std::size_t(W)], phi[std::size_t(W)];
        for (int j = 0; j < W; ++j) {
            static_assert(kLobes + 1 == 4, "lane_chosen_index takes four weights");
            const int k = detail::lane_chosen_index(o.w[0][j], o.w[1][j], o.w[2][j], o.w[3][j], u[0][j] * o.w_total[j]);
            lobe[j] = k;
            sin_i[j] = select(k == 0, lobe_sin[0][j],
                              select(k == 1, lobe_sin[1][j], select(k == 2, lobe_sin[2][j], lobe_sin[3][j])));
            cos_i[j] = detail::cos2_from_sin(sin_i[j]);
            const T phi_k = select(k == 0, o.phi_p[0][j], select(k == 1, o.phi_p[1][j], o.phi_p[2][j]));
            phi[j] = detail::lane_wrap_pi(select(k < kLobes, phi_k + dphi[j], kTwoPi<T> * u[3][j] - kPi<T>));
        }
        elem::sqrt_each(cos_i);
        // wi = direction_from_azimuth(wo, sinθi, φ), and the azimuth queried back
        // (queried_azimuth): φ itself except at the poles and at |φ| = π.
        T wi[3][std::size_t(W)], phi_q[std::size_t(W)], len[std::size_t(W)], sqrt_cos_i[std::size_t(W)];
        for (int j = 0; j < W; ++j) len[j] = hits.wo[1][j] * hits.wo[1][j] + hits.wo[2][j] * hits.wo[2][j];
        elem::sqrt_each(len);
        for (int j = 0; j < W; ++j) {
            const bool has_azimuth = len[j] > T(0);
            const T l = select(has_azimuth, len[j], T(1));
            const T ay = select(has_azimuth, hits.wo[1][j] / l, T(1)), az = select(has_azimuth, hits.wo[2][j] / l, T(0));
            T s, c;
            detail::lane_sincos(phi[j], s, c);
            wi[0][j] = sin_i[j];
            wi[1][j] = cos_i[j] * (ay * c - az * s);
            wi[2][j] = cos_i[j] * (ay * s + az * c);
            const bool as_drawn = (cos_i[j] > T(0)) & (phi[j] < kPi<T>) & (phi[j] > -kPi<T>);
            phi_q[j] = select(as_drawn, phi[j], relative_azimuth(hits, j, wi[1][j], wi[2][j]));
            sqrt_cos_i[j] = cos_i[j];
        }
        elem::sqrt_each(sqrt_cos_i);
        T f[3][std::size_t(W)], pdf[std::size_t(W)];
        combine<W, true, true>(o, sin_i, cos_i, sqrt_cos_i, phi_q, f, pdf);
        for (int j = 0; j < W && j < count; ++j) {
            const std::size_t i = i0 + std::size_t(j);
            const bool ok = hits.ok[j];
            const bool weighted = ok && pdf[j] > T(0);  // (make_sample: weight 0 where the pdf underflowed)
            out.wi.x[i] = ok ? wi[0][j] : T(0);
            out.wi.y[i] = ok ? wi[1][j] : T(0);
            out.wi.z[i] = ok ? wi[2][j] : T(0);
            out.weight.x[i] = weighted ? f[0][j] / pdf[j] : T(0);
            out.weight.y[i] = weighted ? f[1][j] / pdf[j] : T(0);
            out.weight.z[i] = weighted ? f[2][j] / pdf[j] : T(0);
            out.pdf[i] = ok ? pdf[j] : T(0);
            out.lobe[i] = ok ? lobe_tag(lobe[j]) : SampledLobe::kNone;
        }
    }

    // relative_azimuth(wo, wi) of lane j, from wi's y and z.
    template <int W>
    static HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T relative_azimuth(const Hits<W>& hits, int j, T wi_y, T wi_z) {
        const T wo_y = hits.wo[1][j], wo_z = hits.wo[2][j];
        const bool on_axis = (wo_y == T(0)) & (wo_z == T(0));
        const T oy = select(on_axis, T(1), wo_y), oz = wo_z;
        return detail::lane_atan2(oy * wi_z - oz * wi_y, oy * wi_y + oz * wi_z);
    }

    // ChiangFiber::outgoing for W hits: the fiber's γo, Fresnel factor, refracted path,
    // attenuations, tilted lobes and exit azimuths, each step one loop across the hits, the
    // square roots between them one elem::sqrt_each per step.
    template <int W, bool kW> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void outgoing(const Hits<W>& hits, Outgoing<W>& o) const {
        const FiberParams<T>& prm = mat_->params();
        const T eta = prm.eta, inv_eta = T(1) / eta, inv_eta2 = T(1) / (eta * eta);
        T sin_o[std::size_t(W)], cos_o[std::size_t(W)], cos_go[std::size_t(W)], root_go[std::size_t(W)];
        for (int j = 0; j < W; ++j) {
            sin_o[j] = detail::lane_clamp(hits.wo[0][j], T(-1), T(1));
            cos_o[j] = detail::cos2_from_sin(sin_o[j]);
            cos_go[j] = detail::cos2_from_sin(hits.h[j]);
            root_go[j] = detail::asin_root_arg(hits.h[j]);
        }
        elem::sqrt_each(cos_o);
        elem::sqrt_each(cos_go);
        elem::sqrt_each(root_go);
        // fresnel_dielectric(cosθo cosγo, η) and FiberRefraction(sinθo, cosθo, η)
        // (lobes/attenuation.hpp), their square roots taken for the block.
        T cos_f[std::size_t(W)], cos_t_f[std::size_t(W)], cos_t[std::size_t(W)];
        for (int j = 0; j < W; ++j) {
            cos_f[j] = detail::lane_clamp(cos_o[j] * cos_go[j], T(0), T(1));
            cos_t_f[j] = detail::sqrt_arg(T(1) - (T(1) - cos_f[j] * cos_f[j]) * inv_eta2);
            cos_t[j] = detail::cos2_from_sin(sin_o[j] * inv_eta);
        }
        elem::sqrt_each(cos_t_f);
        elem::sqrt_each(cos_t);
        T fresnel[std::size_t(W)], chord_scale[std::size_t(W)], sin_gt[std::size_t(W)], cos_gt[std::size_t(W)],
            root_gt[std::size_t(W)];
        for (int j = 0; j < W; ++j) {
            fresnel[j] = T(0.5) * (detail::fresnel_parallel(cos_f[j], cos_t_f[j], eta) +
                                   detail::fresnel_perpendicular(cos_f[j], cos_t_f[j], eta));
            const T inv_cos_t = T(1) / detail::lane_floor_at(cos_t[j], kMinNormal<T>);
            chord_scale[j] = T(2) * inv_cos_t;
            sin_gt[j] = hits.h[j] * (cos_o[j] * inv_eta * inv_cos_t);
            cos_gt[j] = detail::cos2_from_sin(sin_gt[j]);
            root_gt[j] = detail::asin_root_arg(sin_gt[j]);
        }
        elem::sqrt_each(cos_gt);
        elem::sqrt_each(root_gt);
        // Φ(p, h) = 2p γt - 2γo + pπ, wrapped (exit_azimuth_wrapped, lobes/azimuthal.hpp).
        T chord[std::size_t(W)];
        for (int j = 0; j < W; ++j) {
            chord[j] = chord_scale[j] * cos_gt[j];
            const T gamma_o = detail::lane_asin(hits.h[j], root_go[j]);
            const T gamma_t = detail::lane_asin(sin_gt[j], root_gt[j]);
            o.phi_p[0][j] = detail::lane_wrap_pi_once(T(0) * gamma_t - T(2) * gamma_o + T(0) * kPi<T>);
            o.phi_p[1][j] = detail::lane_wrap_pi_once(T(2) * gamma_t - T(2) * gamma_o + T(1) * kPi<T>);
            o.phi_p[2][j] = detail::lane_wrap_pi_once(T(4) * gamma_t - T(2) * gamma_o + T(0) * kPi<T>);
        }
        // A_p per channel (attenuation_channels, lobes/attenuation.hpp: Chiang et al. 2016
        // eqs. 3–4, the residual's denominator floored at the smallest normal number).
        const T(&sigma_a)[kChannelLanes] = mat_->sigma_a_lanes();
        const bool weighted = mat_->has_lobe_weights();
        for (int c = 0; c < 3; ++c) {
            const T minus_sigma = -sigma_a[c];
            T g[std::size_t(kLobes + 1)];
            for (int p = 0; p <= kLobes; ++p) g[p] = weighted ? mat_->lobe_weight_lanes(p)[c] : T(1);
            for (int j = 0; j < W; ++j) {
                const T t = detail::lane_exp(minus_sigma * chord[j]), f = fresnel[j];
                const T a1 = sqr(T(1) - f) * t, a2 = a1 * t * f, tf = t * f;
                const T a3 = a2 * tf / detail::lane_floor_at(T(1) - tf, kMinNormal<T>);
                // (the lobe weights, 1 without controls: a product by 1 is exact)
                o.a[0][c][j] = f * g[0];
                o.a[1][c][j] = a1 * g[1];
                o.a[2][c][j] = a2 * g[2];
                o.a[3][c][j] = a3 * g[3];
            }
        }
        // The lobes conditioned on each hit's tilted θo' (DeonLobes::condition, lane = hit;
        // CuticleTilt::rotate, cosθo' folded to ≥ 0).
        for (int p = 0; p <= kLobes; ++p) {
            const DeonLongitudinal<T> lobe = mat_->longitudinal(p);
            const typename CuticleTilt<T>::Rotated r = mat_->tilt().rotation(p);
            for (int j = 0; j < W; ++j) {
                const T s = sin_o[j] * r.cos_theta + cos_o[j] * r.sin_theta;
                const T c = cos_o[j] * r.cos_theta - sin_o[j] * r.sin_theta;
                lobe.condition(o.m[p], j, s, select(c < T(0), -c, c));
            }
            o.m[p].take_roots();
        }
        if constexpr (kW) {
            // The selection weights w_p = Σ_c A_p,c, their total as a tree, and a subnormal
            // total scaled by 2^64 (ChiangFiber::outgoing says why).
            for (int j = 0; j < W; ++j) {
                T w[std::size_t(kLobes + 1)];
                for (int p = 0; p <= kLobes; ++p) w[p] = o.a[p][0][j] + o.a[p][1][j] + o.a[p][2][j];
                T total = pairwise_sum<kLobes + 1>(w);
                const T scale = select(total >= kMinNormal<T>, T(1), T(18446744073709551616.0));
                for (int p = 0; p <= kLobes; ++p) o.w[p][j] = w[p] * scale;
                total *= scale;
                o.w_total[j] = total;
                o.inv_w_total[j] = select(total > T(0), T(1) / select(total > T(0), total, T(1)), T(0));
            }
        }
    }

    // ChiangFiber::combine for W hits: f = Σ_p M_p A_p N_p and pdf = Σ_p M_p w_p N_p.
    template <int W, bool kF, bool kPdf>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void combine(const Outgoing<W>& o, const T (&sin_i)[std::size_t(W)],
                                                         const T (&cos_i)[std::size_t(W)],
                                                         const T (&sqrt_cos_i)[std::size_t(W)],
                                                         const T (&phi)[std::size_t(W)], T (&f)[3][std::size_t(W)],
                                                         T (&pdf)[std::size_t(W)]) const {
        const TrimmedLogistic<T>& n = mat_->azimuthal();
        const T minus_inv_s = -n.inv_scale(), scale = n.density_numerator(T(1));
        T mn[std::size_t(kLobes + 1)][std::size_t(W)];
        for (int p = 0; p <= kLobes; ++p) {
            const DeonLanes<T, W>& m = o.m[p];
            T mm[std::size_t(W)];
            for (int j = 0; j < W; ++j) {
                T e_m, m_factor;
                m.terms(j, sin_i[j], cos_i[j], sqrt_cos_i[j], e_m, m_factor);
                mm[j] = m_factor * detail::lane_exp(e_m);
            }
            if (p == kLobes) {  // the residual: uniform in φ
                for (int j = 0; j < W; ++j) mn[p][j] = mm[j] * kInvTwoPi<T>;
                continue;
            }
            // N_p's density e/(1 + e)² times its scale, M in the numerator (ChiangFiber::combine).
            const T* phi_p = o.phi_p[p];
            for (int j = 0; j < W; ++j) {
                const T e_n = detail::lane_exp(detail::lane_exponent_of_difference(phi[j] - phi_p[j], minus_inv_s));
                mn[p][j] = mm[j] * (e_n * scale) / sqr(T(1) + e_n);
            }
        }
        if constexpr (kF) {
            // The one-hit sum's order: in float with the vector extensions two accumulators,
            // lobes (0, 2) and (1, 3); else the lobes in turn.
            constexpr bool kPairs = std::is_same<T, float>::value && HAIRSCATTER_HAS_VECTOR_EXT;
            for (int c = 0; c < 3; ++c) {
                const T(&a0)[std::size_t(W)] = o.a[0][c];
                const T(&a1)[std::size_t(W)] = o.a[1][c];
                const T(&a2)[std::size_t(W)] = o.a[2][c];
                const T(&a3)[std::size_t(W)] = o.a[3][c];
                for (int j = 0; j < W; ++j) {
                    if constexpr (kPairs) {
                        T even = T(0), odd = T(0);
                        even += mn[0][j] * a0[j];
                        odd += mn[1][j] * a1[j];
                        even += mn[2][j] * a2[j];
                        odd += mn[3][j] * a3[j];
                        f[c][j] = even + odd;
                    } else {
                        T sum = T(0);
                        sum += mn[0][j] * a0[j];
                        sum += mn[1][j] * a1[j];
                        sum += mn[2][j] * a2[j];
                        sum += mn[3][j] * a3[j];
                        f[c][j] = sum;
                    }
                }
            }
        }
        if constexpr (kPdf) {
            // (pairwise_sum's tree of the four terms, written out: a loop of it vectorises)
            static_assert(kLobes + 1 == 4, "the four terms below");
            for (int j = 0; j < W; ++j)
                pdf[j] = ((mn[0][j] * o.w[0][j] + mn[1][j] * o.w[1][j]) + (mn[2][j] * o.w[2][j] + mn[3][j] * o.w[3][j])) *
                         o.inv_w_total[j];
        }
    }

    const Material* mat_;
};

}  // namespace hairscatter
