// hairscatter — the Chiang fiber (models/chiang.hpp) over a batch of hits of one material,
// for renderers that shade many hits at once (wavefront path tracers): structure-of-arrays
// in and out, the hits processed kWidth at a time, every step one loop across the hits of
// a block, so that GCC and Clang vectorise across hits (eight floats to an AVX register)
// where the one-hit calls vectorise across the four lobes.
//
//   ChiangBatch<float> batch(material);
//   batch.eval(ChiangBatchQuery<float>{n, h, {wo_x, wo_y, wo_z}, {wi_x, wi_y, wi_z}}, {f_r, f_g, f_b});
//
// Each result is the one-hit call's, ChiangFiber<T>(material, h[i]).eval(wo_i, wi_i) and so
// on, computed by the same formulas in the same order: equal to the last bit, or within
// the few ulps that the compilers' contraction of products into FMAs may differ by between
// vector and scalar code (tests/chiang_batch_test.cpp states and enforces the bound). The
// same contract for hostile input: a non-finite or zero wo or wi, or non-finite u, gives 0
// (eval, pdf) or the empty sample (wi 0, weight 0, pdf 0, SampledLobe::kNone); other
// lengths are normalised and u is clamped into [0, 1]. All four lobes are kept (no subsets).
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

// The elementary functions one lane at a time, in the forms whose loops vectorise: on the
// host in float, elem's own polynomials with their range choices as selects (the one-hit
// calls branch, or use vectors of the lobes); in double and on a GPU, elem's functions.
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
        elem::detail::sincos_float_reduced(x, s, c);  // (|x| ≤ π here)
        return;
    }
#endif
    elem::sincos(x, s, c);
}
// The argument of the square root elem::asin takes for |x| > 0.7, which the block computes
// for all lanes at once (elem::sqrt_each: std::sqrt in a loop keeps it scalar).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T asin_root_arg(T x) {
    return T(0.5) * (T(1) - clamp(abs_value(x), T(0), T(1)));
}
// elem::asin(x) with root = √asin_root_arg(x): both of its forms, the choice a select.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T lane_asin(T x, T root) {
#if !defined(__CUDA_ARCH__)
    if constexpr (std::is_same<T, float>::value) {
        const float ax = clamp(std::fabs(x), 0.0f, 1.0f);
        const float r = select(ax <= elem::kAsinSmallMax, elem::detail::asin_small_poly(ax),
                               kHalfPi<float> - 2.0f * elem::detail::asin_small_poly(root));
        return std::copysign(r, x);
    }
#endif
    (void)root;
    return elem::asin(x);
}
// elem::atan2(y, x), its minimum and the denominator's guard as selects.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T lane_atan2(T y, T x) {
#if !defined(__CUDA_ARCH__)
    if constexpr (std::is_same<T, float>::value) {
        const float ax = std::fabs(x), ay = std::fabs(y);
        const float hi = ay > ax ? ay : ax;
        const float lo = ax < ay ? ax : ay;
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
// max(x, 0): the argument of safe_sqrt, for a block's square roots.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T sqrt_arg(T x) { return select(x > T(0), x, T(0)); }
// (1 - s)(1 + s), floored at 0: cos_from_sin's argument.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T cos2_from_sin(T s) {
    return sqrt_arg((T(1) - s) * (T(1) + s));
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
    // Hits per block: one AVX register of floats; in double four (its exps are libm's).
    static constexpr int kWidth = std::is_same<T, float>::value ? 8 : 4;

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
        for (std::size_t i = 0; i < q.n; i += std::size_t(kWidth))
            sample_block<kWidth>(q, i, block_count(q.n, i), out);
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
    static HAIRSCATTER_HD int block_count(std::size_t n, std::size_t i) {
        return n - i < std::size_t(kWidth) ? int(n - i) : kWidth;
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
        for (std::size_t i = 0; i < q.n; i += std::size_t(kWidth))
            query_block<kWidth, kF, kPdf>(q, i, block_count(q.n, i), f, pdf);
    }

    // Reads hit i0 + j into lane j; the lanes past count repeat hit i0 (valid input whose
    // results are not written), so that every block computes whole vectors.
    template <int W>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE static std::size_t source(std::size_t i0, int j, int count) {
        return i0 + std::size_t(j < count ? j : 0);
    }

    template <int W, bool kF, bool kPdf>
    HAIRSCATTER_HD void query_block(const ChiangBatchQuery<T>& q, std::size_t i0, int count, const Arrays3<T>& f_out,
                                    T* pdf_out) const {
        Hits<W> hits;
        T wi[3][std::size_t(W)];
        for (int j = 0; j < W; ++j) {
            const std::size_t s = source<W>(i0, j, count);
            V3 wo_j(q.wo.x[s], q.wo.y[s], q.wo.z[s]), wi_j(q.wi.x[s], q.wi.y[s], q.wi.z[s]);
            hits.ok[j] = unit_directions(wo_j, wi_j);  // (FiberModel's check, the same normalisation)
            if (!hits.ok[j]) wo_j = wi_j = V3(T(0), T(1), T(0));
            hits.h[j] = clamped_offset(q.h[s]);
            for (int c = 0; c < 3; ++c) {
                hits.wo[c][j] = wo_j[c];
                wi[c][j] = wi_j[c];
            }
        }
        Outgoing<W> o;
        outgoing<W, kPdf>(hits, o);
        // θi and φ of wi (ChiangFiber::query).
        T sin_i[std::size_t(W)], cos_i[std::size_t(W)], sqrt_cos_i[std::size_t(W)], phi[std::size_t(W)];
        for (int j = 0; j < W; ++j) {
            sin_i[j] = clamp(wi[0][j], T(-1), T(1));
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
        for (int j = 0; j < W; ++j) {
            const std::size_t s = source<W>(i0, j, count);
            V3 wo_j(q.wo.x[s], q.wo.y[s], q.wo.z[s]);
            V4 u_j(q.u[0][s], q.u[1][s], q.u[2][s], q.u[3][s]);
            hits.ok[j] = unit_direction_and_numbers(wo_j, u_j);  // (FiberModel::sample's check)
            if (!hits.ok[j]) wo_j = V3(T(0), T(1), T(0)), u_j = V4(T(0.5));
            hits.h[j] = clamped_offset(q.h[s]);
            for (int c = 0; c < 3; ++c) hits.wo[c][j] = wo_j[c];
            for (int c = 0; c < 4; ++c) u[c][j] = u_j[c];
        }
        Outgoing<W> o;
        outgoing<W, true>(hits, o);

        // sinθi of every lobe from (u.y, u.z): DeonLongitudinal::sample_sin_theta_each's
        // steps, lobe by lobe across the hits.
        T lobe_sin[std::size_t(kLobes + 1)][std::size_t(W)];
        {
            T sin_az[std::size_t(W)], cos_az[std::size_t(W)];
            for (int j = 0; j < W; ++j) detail::lane_sincos(kTwoPi<T> * u[2][j], sin_az[j], cos_az[j]);
            for (int p = 0; p <= kLobes; ++p) {
                const T v = mat_->lobe_variance(p), e = mat_->lobe_exp_m2_over_v(p);
                T omc[std::size_t(W)], s[std::size_t(W)];
                for (int j = 0; j < W; ++j) {
                    const T a = u[1][j] + (T(1) - u[1][j]) * e;
                    omc[j] = clamp(-v * detail::lane_log(a > kMinNormal<T> ? a : kMinNormal<T>), T(0), T(2));  // 1 - c
                    s[j] = omc[j] * (T(2) - omc[j]);
                }
                elem::sqrt_each(s);
                for (int j = 0; j < W; ++j)
                    lobe_sin[p][j] = clamp(-(T(1) - omc[j]) * o.m[p].sin_o[j] + s[j] * cos_az[j] * o.m[p].cos_o[j],
                                           T(-1), T(1));
            }
        }
        // The lobe ∝ w (chosen_index, as the one-hit sample), its θi, and φ from N_p.
        const TrimmedLogistic<T>& n = mat_->azimuthal();
        int lobe[std::size_t(W)];
        T sin_i[std::size_t(W)], cos_i[std::size_t(W)], sqrt_cos_i[std::size_t(W)], phi[std::size_t(W)];
        for (int j = 0; j < W; ++j) {
            const T w[std::size_t(kLobes + 1)] = {o.w[0][j], o.w[1][j], o.w[2][j], o.w[3][j]};
            const int k = chosen_index<kLobes + 1>(w, u[0][j] * o.w_total[j]);
            lobe[j] = k;
            sin_i[j] = select(k == 0, lobe_sin[0][j],
                              select(k == 1, lobe_sin[1][j], select(k == 2, lobe_sin[2][j], lobe_sin[3][j])));
            cos_i[j] = detail::cos2_from_sin(sin_i[j]);
            const T phi_k = select(k == 0, o.phi_p[0][j], select(k == 1, o.phi_p[1][j], o.phi_p[2][j]));
            phi[j] = wrap_pi(select(k < kLobes, phi_k + n.sample(u[3][j]), kTwoPi<T> * u[3][j] - kPi<T>));
        }
        elem::sqrt_each(cos_i);
        // wi = direction_from_azimuth(wo, sinθi, φ); the azimuth queried back (queried_azimuth).
        T wi[3][std::size_t(W)], phi_q[std::size_t(W)], len[std::size_t(W)];
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
            const bool as_drawn = cos_i[j] > T(0) && phi[j] < kPi<T> && phi[j] > -kPi<T>;
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
        const bool on_axis = wo_y == T(0) && wo_z == T(0);
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
            sin_o[j] = clamp(hits.wo[0][j], T(-1), T(1));
            cos_o[j] = detail::cos2_from_sin(sin_o[j]);
            cos_go[j] = detail::cos2_from_sin(hits.h[j]);
            root_go[j] = detail::asin_root_arg(hits.h[j]);
        }
        elem::sqrt_each(cos_o);
        elem::sqrt_each(cos_go);
        elem::sqrt_each(root_go);
        // fresnel_dielectric(cosθo cosγo, η) and FiberRefraction(sinθo, cosθo, η), their
        // square roots taken here for the block.
        T cos_f[std::size_t(W)], cos_t_f[std::size_t(W)], cos_t[std::size_t(W)];
        for (int j = 0; j < W; ++j) {
            cos_f[j] = clamp(cos_o[j] * cos_go[j], T(0), T(1));
            cos_t_f[j] = detail::sqrt_arg(T(1) - (T(1) - cos_f[j] * cos_f[j]) * inv_eta2);
            cos_t[j] = detail::cos2_from_sin(sin_o[j] * inv_eta);
        }
        elem::sqrt_each(cos_t_f);
        elem::sqrt_each(cos_t);
        T fresnel[std::size_t(W)], chord_scale[std::size_t(W)], sin_gt[std::size_t(W)], cos_gt[std::size_t(W)], root_gt[std::size_t(W)];
        for (int j = 0; j < W; ++j) {
            fresnel[j] = T(0.5) * (detail::fresnel_parallel(cos_f[j], cos_t_f[j], eta) +
                                   detail::fresnel_perpendicular(cos_f[j], cos_t_f[j], eta));
            const T inv_cos_t = T(1) / (cos_t[j] > kMinNormal<T> ? cos_t[j] : kMinNormal<T>);
            chord_scale[j] = T(2) * inv_cos_t;
            sin_gt[j] = hits.h[j] * (cos_o[j] * inv_eta * inv_cos_t);
            cos_gt[j] = detail::cos2_from_sin(sin_gt[j]);
            root_gt[j] = detail::asin_root_arg(sin_gt[j]);
        }
        elem::sqrt_each(cos_gt);
        elem::sqrt_each(root_gt);
        // A_p (attenuation_channels, per hit) and Φ(p, h).
        const T(&sigma_a)[kChannelLanes] = mat_->sigma_a_lanes();
        for (int j = 0; j < W; ++j) {
            const T chord = chord_scale[j] * cos_gt[j];
            const T gamma_o = detail::lane_asin(hits.h[j], root_go[j]);
            const T gamma_t = detail::lane_asin(sin_gt[j], root_gt[j]);
            T t[3], a[std::size_t(kLobes + 1)][3];
            for (int c = 0; c < 3; ++c) t[c] = detail::lane_exp(-sigma_a[c] * chord);
            attenuation_channels<T, kLobes, 3>(fresnel[j], fresnel[j], t, a);
            for (int p = 0; p <= kLobes; ++p)
                for (int c = 0; c < 3; ++c) o.a[p][c][j] = a[p][c];
            for (int p = 0; p < kLobes; ++p) o.phi_p[p][j] = exit_azimuth_wrapped(p, gamma_o, gamma_t);
        }
        if (mat_->has_lobe_weights())
            for (int p = 0; p <= kLobes; ++p)
                for (int c = 0; c < 3; ++c) {
                    const T g = mat_->lobe_weight_lanes(p)[c];
                    for (int j = 0; j < W; ++j) o.a[p][c][j] *= g;
                }
        // The lobes conditioned on each hit's tilted θo' (DeonLobes::condition, lane = hit).
        for (int p = 0; p <= kLobes; ++p) {
            const DeonLongitudinal<T> lobe = mat_->longitudinal(p);
            for (int j = 0; j < W; ++j) {
                const typename CuticleTilt<T>::Rotated r = mat_->tilt().rotate(p, sin_o[j], cos_o[j]);
                lobe.condition(o.m[p], j, r.sin_theta, r.cos_theta);
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
                const bool tiny = !(total >= kMinNormal<T>);
                const T scale = select(tiny, T(18446744073709551616.0), T(1));
                for (int p = 0; p <= kLobes; ++p) o.w[p][j] = w[p] * scale;
                total *= scale;
                o.w_total[j] = total;
                o.inv_w_total[j] = select(total > T(0), T(1) / select(total > T(0), total, T(1)), T(0));
            }
        }
    }

    // ChiangFiber::combine for W hits: f = Σ_p M_p A_p N_p and pdf = Σ_p M_p w_p N_p.
    template <int W, bool kF, bool kPdf>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void combine(const Outgoing<W>& o, const T (&sin_i)[std::size_t(W)], const T (&cos_i)[std::size_t(W)],
                                                         const T (&sqrt_cos_i)[std::size_t(W)], const T (&phi)[std::size_t(W)], T (&f)[3][std::size_t(W)],
                                                         T (&pdf)[std::size_t(W)]) const {
        const TrimmedLogistic<T>& n = mat_->azimuthal();
        const T minus_inv_s = -n.inv_scale(), scale = n.density_numerator(T(1));
        T mn[std::size_t(kLobes + 1)][std::size_t(W)];
        for (int p = 0; p <= kLobes; ++p) {
            for (int j = 0; j < W; ++j) {
                T e_m, m_factor;
                o.m[p].terms(j, sin_i[j], cos_i[j], sqrt_cos_i[j], e_m, m_factor);
                const T m = m_factor * detail::lane_exp(e_m);
                if (p < kLobes) {
                    const T e_n = detail::lane_exp(TrimmedLogistic<T>::exponent_of_difference(phi[j] - o.phi_p[p][j], minus_inv_s));
                    mn[p][j] = m * (e_n * scale) / sqr(T(1) + e_n);
                } else {
                    mn[p][j] = m * kInvTwoPi<T>;  // the residual: uniform in φ
                }
            }
        }
        if constexpr (kF) {
            for (int c = 0; c < 3; ++c)
                for (int j = 0; j < W; ++j) {
                    if constexpr (std::is_same<T, float>::value && HAIRSCATTER_HAS_VECTOR_EXT) {
                        // The one-hit float sum: two accumulators, lobes (0, 2) and (1, 3).
                        T even = T(0), odd = T(0);
                        even += mn[0][j] * o.a[0][c][j];
                        odd += mn[1][j] * o.a[1][c][j];
                        even += mn[2][j] * o.a[2][c][j];
                        odd += mn[3][j] * o.a[3][c][j];
                        f[c][j] = even + odd;
                    } else {
                        T sum = T(0);
                        for (int p = 0; p <= kLobes; ++p) sum += mn[p][j] * o.a[p][c][j];
                        f[c][j] = sum;
                    }
                }
        }
        if constexpr (kPdf) {
            for (int j = 0; j < W; ++j) {
                T terms[std::size_t(kLobes + 1)];
                for (int p = 0; p <= kLobes; ++p) terms[p] = mn[p][j] * o.w[p][j];
                pdf[j] = pairwise_sum<kLobes + 1>(terms) * o.inv_w_total[j];
            }
        }
    }

    const Material* mat_;
};

}  // namespace hairscatter
