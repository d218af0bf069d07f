// hairscatter — the per-fiber tables of dual scattering (Zinke et al. 2008 §4.1; docs/dual.md):
// forward and backward albedos a_f, a_b, their albedo-weighted lobe shifts ᾱ and variances
// β̄², the local backscattering A_b, Δ_b, σ_b derived from them, and per lobe the window
// W_p(θ, ψ): the lobe's h-averaged A_p N_p averaged over the half-circle of azimuths
// |φ - ψ| < π/2, which is what the global term needs once the forward-scattered light is
// spread over azimuth. Built once per fiber parameter set and settings on the host from any
// model that reports per-lobe A_p and half-circle masses (lobe_split); looked up by the
// light's inclination on the host or, through view(), on a GPU.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/constants.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "../io/table_file.hpp"
#include "../math/quadrature.hpp"
#include "settings.hpp"

namespace hairscatter {

// Conventions. θ is the inclination of the direction light arrives from (tables are built
// with wo at θ and integrated over wi, read through the fiber's reciprocity; the lookups
// use θi, as Sadeghi & Tamstorf 2010 note Zinke's θd really is). Shifts and variances are
// in θi + θo (d'Eon et al. 2011's corrected 2θh): lobe p peaks at θi = α_p - θo with
// variance β_p² = v_p, so Δ_b is a shift of θi + θo too. Everything is per RGB channel.
template <typename T> struct DualScatteringEntry {
    using V3 = glm::vec<3, T>;
    V3 a_f{T(0)}, a_b{T(0)};                      // ∫ f over the forward (|φ| > π/2) / backward half
    V3 alpha_f{T(0)}, alpha_b{T(0)};              // ᾱ_f, ᾱ_b
    V3 beta2_f{T(0)}, beta2_b{T(0)};              // β̄²_f, β̄²_b
    V3 A_b{T(0)}, delta_b{T(0)}, sigma2_b{T(0)};  // A_1 + A_3, Δ_b, σ_b²
    // The mean cosine of the azimuthal turn of forward-scattered light away from straight
    // through (E[cos(φ − π)] over |φ| > π/2) and of backscattered light away from straight
    // back (E[cos φ] over |φ| < π/2), energy-weighted: how far one event spreads the light
    // around the fiber (the two-stream source kernels' azimuths, two_stream.hpp).
    V3 mu_f{T(0)}, mu_b{T(0)};
    // The share of a_b that goes back along a stack of fibers at this θ (two_stream.hpp,
    // docs/theory.md §5.7 "Stacks inclined to the fibers"): a fiber keeps the component of
    // the light's travel along its axis, so backscattered light whose travel still runs on
    // along the stack (wo · wi < 0 for light from wo leaving along wi) passes on. 1 across the
    // fibers (θ = 0), falling toward 0 as the stack tilts toward them; 1 is the 1D stack of
    // Zinke et al. 2008, whatever θ (a default-built entry's value).
    V3 rho_b{T(1)};

    static constexpr int kFields = 12;  // V3 fields, in the order of fields()
    static constexpr int kFieldA_b = 6, kFieldDelta_b = 7, kFieldSigma2_b = 8, kFieldMu_f = 9;  // their indices there
    HAIRSCATTER_HD V3* fields() { return &a_f; }
    HAIRSCATTER_HD const V3* fields() const { return &a_f; }
};
// fields() walks the entry as an array of vec3 (of whatever size GLM gives vec3: aligned
// vec3 under GLM_FORCE_DEFAULT_ALIGNED_GENTYPES is 16 bytes, and the walk still holds).
static_assert(offsetof(DualScatteringEntry<float>, A_b) == DualScatteringEntry<float>::kFieldA_b * sizeof(glm::vec3) &&
                  offsetof(DualScatteringEntry<float>, delta_b) == DualScatteringEntry<float>::kFieldDelta_b * sizeof(glm::vec3) &&
                  offsetof(DualScatteringEntry<float>, sigma2_b) == DualScatteringEntry<float>::kFieldSigma2_b * sizeof(glm::vec3) &&
                  offsetof(DualScatteringEntry<float>, mu_f) == DualScatteringEntry<float>::kFieldMu_f * sizeof(glm::vec3),
              "DualScatteringEntry's field indices");
static_assert(sizeof(DualScatteringEntry<float>) == DualScatteringEntry<float>::kFields * sizeof(glm::vec3) &&
                  sizeof(DualScatteringEntry<double>) == DualScatteringEntry<double>::kFields * sizeof(glm::dvec3),
              "DualScatteringEntry must be a flat array of vec3 for fields()");

// Zinke et al. 2008 eqs. 13–15, the backscattering quantities from a_f, a_b, ᾱ and β̄² of
// one θ; d_b enters σ_b. 1 - a_f² → 0 only for a lossless fiber that scatters everything
// forward, where A_b → 0 anyway: the floor keeps the quotients finite.
template <typename T> void derive_backscattering(DualScatteringEntry<T>& e, T d_b) {
    for (int c = 0; c < 3; ++c) {
        const T af = e.a_f[c], ab = e.a_b[c];
        const T af2 = af * af, ab2 = ab * ab, ab3 = ab2 * ab;
        const T one = std::max(T(1) - af2, T(1e-6));
        const T one2 = one * one, one3 = one2 * one;
        e.A_b[c] = ab * af2 / one + ab3 * af2 / one3;  // A_1 + A_3
        e.delta_b[c] = e.alpha_b[c] * (T(1) - T(2) * ab2 / one2) + e.alpha_f[c] * (T(2) * one2 + T(4) * af2 * ab2) / one3;
        const T bf2 = e.beta2_f[c], bb2 = e.beta2_b[c];
        const T bf = std::sqrt(bf2), bb = std::sqrt(bb2);
        const T num = ab * std::sqrt(T(2) * bf2 + bb2) + ab3 * std::sqrt(T(2) * bf2 + T(3) * bb2);
        const T den = ab + ab3 * (T(2) * bf + T(3) * bb);
        const T sigma_b = den > T(0) ? (T(1) + d_b * af2) * num / den : T(0);
        e.sigma2_b[c] = sigma_b * sigma_b;
    }
}

// Reflectance R_N and transmittance T_N of N layers that each reflect a_b and transmit a_f,
// by the adding formula of 1D transport (R_{N+1} = a_b + a_f² R_N / (1 - a_b R_N),
// T_{N+1} = a_f T_N / (1 - a_b R_N), R_0 = 0, T_0 = 1), in closed form: one layer's transfer
// matrix P = [[a_f² - a_b², a_b], [-a_b, 1]] / a_f has determinant 1 and trace 2 cosh κ, so
// P^N = (S_N P - S_{N-1} I) with S_k = sinh(kκ) / sinh κ, which gives
//     R_N = a_b / (1 - a_f ρ),   T_N = (a_f / S_N) / (1 - a_f ρ),   ρ = S_{N-1} / S_N,
// smooth in N (a fractional number of layers needs no interpolation). ρ and 1/S_N are
// written with expm1 so that they stay finite for any N and exact as κ → 0, the lossless
// limit where R_N = N a_b / (1 + (N - 1) a_b). Depths below one layer interpolate to none.
// R_∞, the reflectance of a deep stack: the fixed point of the adding formula,
// a_b R² − (1 − a_f² + a_b²) R + a_b = 0, its smaller root in the form without cancellation.
template <typename T> HAIRSCATTER_HD T deep_reflectance(T a_f, T a_b) {
    const T s = T(1) - a_f * a_f + a_b * a_b;
    return a_b > T(0) ? T(2) * a_b / (s + safe_sqrt(s * s - T(4) * a_b * a_b)) : T(0);
}

template <typename T> struct LayerStack {
    T R = T(0), T_ = T(1);
};
// What one layer's (a_f, a_b) fix for any depth, computed once per channel and shared by
// every stack of that layer: κ = acosh(1 + δ), e^{-κ} and q = 1 - e^{-2κ}. e^κ = 1 + δ +
// √(δ(δ + 2)) exactly, so only κ itself needs a logarithm, and 1 - e^{-κ} = x / (1 + x)
// (x = e^κ - 1) keeps q free of cancellation as κ → 0.
template <typename T> struct LayerCoefficients {
    T a_f = T(0), a_b = T(0);
    T kappa = T(0), e_k = T(1), q = T(0);
};

// The same for N layers at once (the dual BCSDF's three channels, padded to four), as a
// structure of arrays: every branch is a select, so that in float the loops over the lanes
// vectorise. layer_coefficients and layered_stack below are these with N = 1.
template <typename T, int N> struct LayerLanes {
    T a_f[std::size_t(N)], a_b[std::size_t(N)];
    T kappa[std::size_t(N)], e_k[std::size_t(N)], q[std::size_t(N)];
};
// κ, e^{-κ} and q from the lanes' a_f and a_b. An opaque layer (a_f = 0) keeps κ = 0,
// e^{-κ} = 1, q = 0: layered_stacks treats it apart.
template <typename T, int N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void layer_lanes(LayerLanes<T, N>& c) {
    T delta[std::size_t(N)], x[std::size_t(N)];
    for (int k = 0; k < N; ++k) {
        // cosh κ = 1 + δ, δ = ((1 - a_f)² - a_b²) / 2a_f without cancellation.
        const T af = select(c.a_f[k] > T(0), c.a_f[k], T(1));
        const T gap = T(1) - af - c.a_b[k];
        delta[k] = select(gap > T(0), gap, T(0)) * (T(1) - af + c.a_b[k]) / (T(2) * af);
    }
    // The roots as one batch (elem::sqrt_each: a loop of std::sqrt, which may set errno,
    // stays scalar with a branch per lane).
    for (int k = 0; k < N; ++k) x[k] = delta[k] * (delta[k] + T(2));
    elem::sqrt_each(x);
    for (int k = 0; k < N; ++k) x[k] += delta[k];  // e^κ - 1
    for (int k = 0; k < N; ++k) c.kappa[k] = x[k];
    elem::log1p_each(c.kappa);
    for (int k = 0; k < N; ++k) {
        const bool lit = c.a_f[k] > T(0);
        const T e_k = T(1) / (T(1) + x[k]);
        c.kappa[k] = select(lit, c.kappa[k], T(0));
        c.e_k[k] = select(lit, e_k, T(1));
        c.q[k] = select(lit, x[k] * e_k * (T(1) + e_k), T(0));  // (1 - e^{-κ})(1 + e^{-κ})
    }
}
// Four lanes' coefficients twice over, lanes k and k + 4 alike: two depths of the same
// layers as one batch of eight (each array written whole, elem::repeat4).
template <typename T>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void repeat_lanes(const LayerLanes<T, 4>& c, LayerLanes<T, 8>& out) {
    elem::repeat4(c.a_f, out.a_f);
    elem::repeat4(c.a_b, out.a_b);
    elem::repeat4(c.kappa, out.kappa);
    elem::repeat4(c.e_k, out.e_k);
    elem::repeat4(c.q, out.q);
}
template <typename T> HAIRSCATTER_HD LayerCoefficients<T> layer_coefficients(T a_f, T a_b) {
    LayerLanes<T, 1> l;
    l.a_f[0] = a_f;
    l.a_b[0] = a_b;
    layer_lanes(l);
    LayerCoefficients<T> c;
    c.a_f = a_f;
    c.a_b = a_b;
    c.kappa = l.kappa[0];
    c.e_k = l.e_k[0];
    c.q = l.q[0];
    return c;
}
// R_∞ of the same layer, a_b / (1 - a_f e^{-κ}): equal to deep_reflectance and consistent
// with layered_stack as the depth grows (the ratio of the two tends to exactly 1).
template <typename T> HAIRSCATTER_HD T deep_reflectance(T a_f, T a_b, T e_k) {
    if (!(a_b > T(0))) return T(0);
    const T den = T(1) - a_f * e_k;
    return den > T(0) ? a_b / den : T(1);
}
template <typename T> HAIRSCATTER_HD T deep_reflectance(const LayerCoefficients<T>& c) {
    return deep_reflectance(c.a_f, c.a_b, c.e_k);
}
// R_N and T_N of every lane at its depth layers[k] (clamped to [0, 1e12]; NaN → 0).
template <typename T, int N>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void layered_stacks(const LayerLanes<T, N>& c, const T (&layers)[std::size_t(N)],
                                                            T (&R)[std::size_t(N)], T (&T_)[std::size_t(N)]) {
    T n[std::size_t(N)], big[std::size_t(N)], d[std::size_t(N)];
    for (int k = 0; k < N; ++k) {
        const T l = layers[k];
        n[k] = select(l > T(0), select(l < T(1e12), l, T(1e12)), T(0));  // NaN → 0, +Inf → 1e12
        big[k] = select(n[k] > T(1), n[k], T(1));
        d[k] = -(big[k] - T(1)) * c.kappa[k];
    }
    elem::expm1_each(d);
    for (int k = 0; k < N; ++k) {
        // κ N ≈ 0, the lossless limit: ρ = (N - 1)/N, 1/S_N = 1/N. Otherwise, with
        // d = 1 - e^{-(N-1)κ}: 1 - e^{-2(N-1)κ} = d (2 - d) and 1 - e^{-2Nκ} = q + d (2 - d)(1 - q),
        // sums of non-negative terms.
        const bool lossless = T(2) * big[k] * c.kappa[k] < T(1e-12);
        const T dk = -d[k];
        const T a = dk * (T(2) - dk);
        const T s = c.q[k] + a * (T(1) - c.q[k]);
        const T inv = T(1) / select(lossless, big[k], s);
        const T rho = select(lossless, big[k] - T(1), c.e_k[k] * a) * inv;
        const T inv_s = select(lossless, T(1), (T(1) - dk) * c.q[k]) * inv;
        const T den = T(1) - c.a_f[k] * rho;
        const bool ok = den > T(0);
        const T inv_den = T(1) / select(ok, den, T(1));
        T r = select(ok, c.a_b[k] * inv_den, T(1));
        T t = select(ok, c.a_f[k] * inv_s * inv_den, T(0));
        const bool part = n[k] < T(1);  // between no layer and one
        r = select(part, n[k] * r, r);
        t = select(part, T(1) + n[k] * (t - T(1)), t);
        // An opaque layer: the first one reflects, nothing passes.
        const bool opaque = !(c.a_f[k] > T(0));
        const bool whole = n[k] >= T(1);
        R[k] = select(opaque, select(whole, c.a_b[k], n[k] * c.a_b[k]), r);
        T_[k] = select(opaque, select(whole, T(0), T(1) - n[k]), t);
    }
}
template <typename T> HAIRSCATTER_HD LayerStack<T> layered_stack(const LayerCoefficients<T>& c, T layers) {
    LayerLanes<T, 1> l;
    l.a_f[0] = c.a_f;
    l.a_b[0] = c.a_b;
    l.kappa[0] = c.kappa;
    l.e_k[0] = c.e_k;
    l.q[0] = c.q;
    const T depth[1] = {layers};
    T R[1], T_[1];
    layered_stacks(l, depth, R, T_);
    LayerStack<T> r;
    r.R = R[0];
    r.T_ = T_[0];
    return r;
}
template <typename T> HAIRSCATTER_HD LayerStack<T> layered_stack(T a_f, T a_b, T layers) {
    return layered_stack(layer_coefficients(a_f, a_b), layers);
}

template <typename T> struct DualTableOptions {
    int theta_samples = 64;  // table entries over θ ∈ [-π/2, π/2] (≥ 8)
    int psi_samples = 33;    // window nodes over ψ ∈ [0, π] (≥ 9)
    int h_nodes = 32;        // Gauss–Legendre nodes in γ = asin h for near-field models (≥ 8)
    DualScatteringSettings<T> settings{};
};

// Everything the dual BCSDF reads, as plain pointers and numbers: trivially copyable, so
// it can be passed to a GPU kernel once the arrays live in device memory (with_arrays).
template <typename T> struct DualTablesView {
    using V3 = glm::vec<3, T>;
    using Entry = DualScatteringEntry<T>;
    static constexpr int kMaxLobes = 4;  // R, TT, TRT, residual; models with fewer leave zeros

    const Entry* entries = nullptr;  // [theta]
    const V3* window = nullptr;      // [theta][lobe][psi]: W_p, per channel
    const T* window_cdf = nullptr;   // [theta][lobe][psi]: ∫_0^ψ of the channel mean of W_p
    int n_theta = 0, n_psi = 0, lobes = 0;
    T lobe_angle[kMaxLobes] = {};     // θo' = θo + angle: each lobe's tilt (-α_p)
    T lobe_variance[kMaxLobes] = {};  // v_p
    T lobe_sin[kMaxLobes] = {}, lobe_cos[kMaxLobes] = {};  // sin, cos of lobe_angle
    DualScatteringSettings<T> settings{};

    // (sinθo', cosθo') of lobe p: θo rotated by the lobe's tilt, cosθo' folded to ≥ 0.
    HAIRSCATTER_HD void rotate(int p, T sin_o, T cos_o, T& s, T& c) const {
        s = sin_o * lobe_cos[p] + cos_o * lobe_sin[p];
        c = cos_o * lobe_cos[p] - sin_o * lobe_sin[p];
        c = c < T(0) ? -c : c;
    }

    // Nodes θ_i = (π/2) sin(π x_i / 2) for x_i uniform in [-1, 1]: uniform near θ = 0 and
    // denser toward the poles, where the albedos and A_b change fastest (a uniform grid of
    // 64 samples leaves 12 % of A_b's range as interpolation error within 3° of grazing).
    static T node_theta(int i, int n) {
        const T x = T(-1) + T(2) * T(i) / T(n - 1);
        return kHalfPi<T> * std::sin(kHalfPi<T> * x);
    }
    struct Cell {
        int i;
        T t;
    };
    // The θ cell of inclination sinθ (clamped; NaN reads the first cell).
    HAIRSCATTER_HD Cell cell(T sin_theta) const {
        const T s = clamp(sin_theta, T(-1), T(1));
        return cell_of_angle(elem::asin(is_finite(s) ? s : T(-1)));
    }
    // The same from θ ∈ [-π/2, π/2] itself, for a caller that has it (one asin fewer).
    HAIRSCATTER_HD Cell cell_of_angle(T theta) const { return cell_of_node(node_of_angle(theta)); }
    // The node coordinate x ∈ [-1, 1] of θ (node_theta's inverse), and the cell of x: -x is
    // the cell of -θ exactly (asin is odd), with no second asin.
    HAIRSCATTER_HD T node_of_angle(T theta) const {
        return clamp(elem::asin(clamp(theta * (T(2) * kInvPi<T>), T(-1), T(1))) * (T(2) * kInvPi<T>), T(-1), T(1));
    }
    HAIRSCATTER_HD Cell cell_of_node(T u) const {
        // A NaN θ reads the first row, never outside the table.
        const T x = clamp_nan_to_lo((u + T(1)) * T(0.5), T(0), T(1)) * T(n_theta - 1);
        int i = int(x);
        i = i > n_theta - 2 ? n_theta - 2 : i;
        return {i, clamp(x - T(i), T(0), T(1))};
    }
    HAIRSCATTER_HD Entry lookup(T sin_theta) const { return lookup(cell(sin_theta)); }
    // The entry at cell c: every field's lerp, as flat loops over the entry's reals (which the
    // compilers vectorise; a loop over the vec3 fields stayed scalar).
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE Entry lookup(const Cell& c) const {
        constexpr int kReals = int(sizeof(Entry) / sizeof(T));
        T a[std::size_t(kReals)], b[std::size_t(kReals)], o[std::size_t(kReals)];
        std::memcpy(a, &entries[c.i], sizeof a);
        std::memcpy(b, &entries[c.i + 1], sizeof b);
        // GCC -O2 vectorises only loops whose trip count the vector divides: a body of a
        // multiple of 8, then the rest.
        constexpr int kBody = kReals / 8 * 8;
        for (int k = 0; k < kBody; ++k) o[k] = a[k] + c.t * (b[k] - a[k]);
        for (int k = kBody; k < kReals; ++k) o[k] = a[k] + c.t * (b[k] - a[k]);
        Entry r;
        std::memcpy(static_cast<void*>(&r), o, sizeof o);
        return r;
    }
    // Field k of the entry at cell c alone (k: its index in fields()).
    HAIRSCATTER_HD V3 lookup_field(const Cell& c, int k) const {
        const V3 a = entries[c.i].fields()[k], b = entries[c.i + 1].fields()[k];
        return a + c.t * (b - a);
    }
    HAIRSCATTER_HD std::size_t window_index(int i, int p, int j) const {
        return (std::size_t(i) * std::size_t(lobes) + std::size_t(p)) * std::size_t(n_psi) + std::size_t(j);
    }
    // The ψ cell of |ψ| (ψ ∈ [-π, π]): nodes j and j + 1, weight s of the second. A NaN ψ
    // (from directions too long to square) reads ψ = 0, never outside the table.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE Cell psi_cell(T abs_psi) const {
        const T x = clamp_nan_to_lo(abs_psi * kInvPi<T>, T(0), T(1)) * T(n_psi - 1);
        int j = int(x);
        j = j > n_psi - 2 ? n_psi - 2 : j;
        return {j, x - T(j)};
    }
    // Σ_p m[p] W_p(c, |ψ|) over the lobes: window_at's lerps, with the ψ cell and the two
    // rows found once for every lobe.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE V3 window_sum(const Cell& c, T abs_psi, const T* m) const {
        const Cell q = psi_cell(abs_psi);
        const T s = q.t;
        const V3* lo = window + window_index(c.i, 0, q.i);
        const V3* hi = window + window_index(c.i + 1, 0, q.i);
        V3 g(T(0));
        for (int p = 0; p < lobes; ++p, lo += n_psi, hi += n_psi) {
            const V3 a = lo[0] + s * (lo[1] - lo[0]);
            const V3 b = hi[0] + s * (hi[1] - hi[0]);
            g += (a + c.t * (b - a)) * m[p];
        }
        return g;
    }
    // W_p at the θ cell c and |ψ| (ψ ∈ [-π, π]), bilinear.
    HAIRSCATTER_HD V3 window_at(const Cell& c, int p, T abs_psi) const {
        const Cell q = psi_cell(abs_psi);
        const int j = q.i;
        const T s = q.t;
        const V3 lo = window[window_index(c.i, p, j)] + s * (window[window_index(c.i, p, j + 1)] - window[window_index(c.i, p, j)]);
        const V3 hi = window[window_index(c.i + 1, p, j)] +
                      s * (window[window_index(c.i + 1, p, j + 1)] - window[window_index(c.i + 1, p, j)]);
        return lo + c.t * (hi - lo);
    }
};

namespace detail {
// Whether a fiber offers lobe_windows(wo, n_psi): every centre's lobe_split at once.
template <typename F, typename = void> struct has_lobe_windows : std::false_type {};
template <typename F>
struct has_lobe_windows<F, std::void_t<decltype(std::declval<const F&>().lobe_windows(std::declval<typename F::V3>(), 2))>>
    : std::true_type {};
// Whether a material offers h_break(sin θo): the offset |h| at which its fiber's lobes have a
// square-root edge inside the fiber (FurMaterial: where the refracted chord grazes the
// medulla), ≥ 1 when there is none at this θo.
template <typename M, typename T, typename = void> struct has_h_break : std::false_type {};
template <typename M, typename T>
struct has_h_break<M, T, std::void_t<decltype(std::declval<const M&>().h_break(std::declval<T>()))>> : std::true_type {};
}  // namespace detail

template <typename T> class DualScatteringTables {
  public:
    using V3 = glm::vec<3, T>;
    using Entry = DualScatteringEntry<T>;
    using View = DualTablesView<T>;
    static constexpr int kMaxLobes = View::kMaxLobes;
    static constexpr std::uint32_t kFileVersion = 4;

    DualScatteringTables() = default;

    // Builds the tables of a single-fiber model type Fiber (e.g. ChiangFiber<T>, a lobe
    // subset, or a far-field fiber) from its material. The fiber must provide kLobes and
    // lobe_split(wo, centre) (per lobe A_p and the mass of N_p on |φ - centre| < π/2), the
    // material lobe_shift(p) and lobe_variance(p). A fiber constructed from (material, h)
    // is averaged over h by Gauss–Legendre quadrature in γ = asin h: ½∫ f(h) dh =
    // ½∫ f(sin γ) cos γ dγ removes the square-root behaviour of γ (and of Fresnel) at h = ±1,
    // where a rule in h converges slowly (32 nodes in h: 2e-3 relative error in a lobe's
    // forward albedo; in γ: 1e-7). One built from (material) is already h-integrated.
    // A material with an inner edge at |h| = h_b (material.h_break(sin θo) < 1: the fur
    // fibre's medulla, whose chord √(κ² − sin²γt) has the same square-root behaviour there)
    // is integrated in three pieces per θ, each with h_nodes nodes: |h| < h_b in ψ with
    // h = h_b sin ψ, and h_b < |h| < 1 in γ (one rule over the edge: up to 7 % error in a
    // lobe's backward albedo of a dense medulla at 32 nodes; split: below 1e-4, measured).
    template <typename Fiber, typename Material>
    static DualScatteringTables build(const Material& material, const DualTableOptions<T>& opt = {}) {
        static_assert(std::is_same_v<typename Fiber::V3, V3>, "the fiber's real type must match the tables'");
        constexpr int L = Fiber::kLobes + 1;
        static_assert(L <= kMaxLobes, "the model has more lobes than the tables hold");
        check(opt);
        std::vector<Fiber> fibers;
        std::vector<T> h_weight;
        const GaussLegendre<T> gl(opt.h_nodes);
        // The nodes over h for wo at sin θo (the same for every θo without an inner edge).
        auto place_fibers = [&](T sin_o) {
            fibers.clear();
            h_weight.clear();
            if constexpr (std::is_constructible_v<Fiber, const Material&, T>) {
                T h_b = T(1);
                if constexpr (detail::has_h_break<Material, T>::value) h_b = clamp(material.h_break(sin_o), T(0), T(1));
                const bool split = h_b > T(0) && h_b < T(1);
                const T g_b = split ? std::asin(h_b) : kHalfPi<T>;
                for (int k = 0; k < opt.h_nodes; ++k) {
                    const T x = gl.nodes[std::size_t(k)], w = gl.weights[std::size_t(k)];
                    const T psi = kHalfPi<T> * x;  // |h| < h_b (all of [-1, 1] without an edge)
                    fibers.emplace_back(material, (split ? h_b : T(1)) * std::sin(psi));
                    h_weight.push_back(T(0.5) * kHalfPi<T> * w * (split ? h_b : T(1)) * std::cos(psi));
                    if (!split) continue;
                    const T half = T(0.5) * (kHalfPi<T> - g_b), gamma = g_b + half * (T(1) + x);  // γ ∈ (γ_b, π/2)
                    for (T sign : {T(-1), T(1)}) {
                        fibers.emplace_back(material, sign * std::sin(gamma));
                        h_weight.push_back(T(0.5) * half * w * std::cos(gamma));
                    }
                }
            } else {
                fibers.emplace_back(material);
                h_weight.push_back(T(1));
            }
        };
        constexpr bool kPerTheta = detail::has_h_break<Material, T>::value;
        if constexpr (!kPerTheta) place_fibers(T(0));

        DualScatteringTables t;
        t.n_theta_ = opt.theta_samples;
        t.n_psi_ = opt.psi_samples;
        t.lobes_ = L;
        t.h_nodes_ = opt.h_nodes;
        t.settings_ = opt.settings;
        for (int p = 0; p < kMaxLobes; ++p)
            t.set_lobe(p, p < L ? -material.lobe_shift(p) : T(0), p < L ? material.lobe_variance(p) : T(0));
        t.entries_.resize(std::size_t(opt.theta_samples));
        t.window_.assign(std::size_t(opt.theta_samples) * std::size_t(L) * std::size_t(opt.psi_samples), V3(T(0)));
        const View v = t.shape_view();
        for (int i = 0; i < opt.theta_samples; ++i) {
            const T theta = View::node_theta(i, opt.theta_samples);
            const V3 wo(std::sin(theta), std::cos(theta), T(0));
            if constexpr (kPerTheta) place_fibers(wo.x);
            for (std::size_t k = 0; k < fibers.size(); ++k) {
                // A fiber that splits every centre at once (lobe_windows) is asked once.
                std::vector<decltype(fibers[k].lobe_split(wo, T(0)))> all;
                if constexpr (detail::has_lobe_windows<Fiber>::value) all = fibers[k].lobe_windows(wo, opt.psi_samples);
                for (int j = 0; j < opt.psi_samples; ++j) {
                    const T psi = kPi<T> * T(j) / T(opt.psi_samples - 1);
                    const auto split = all.empty() ? fibers[k].lobe_split(wo, psi) : all[std::size_t(j)];
                    for (int p = 0; p < L; ++p)
                        t.window_[v.window_index(i, p, j)] += h_weight[k] * kInvPi<T> * split.a[p] * split.backward[p];
                }
            }
            // a_b,p = π W_p(0), a_f,p = π W_p(π): the backward and forward halves.
            Entry& e = t.entries_[std::size_t(i)];
            azimuthal_turns(fibers, h_weight, wo, e);
            for (int p = 0; p < L; ++p) {
                const V3 ab = kPi<T> * t.window_[v.window_index(i, p, 0)];
                const V3 af = kPi<T> * t.window_[v.window_index(i, p, opt.psi_samples - 1)];
                const T alpha = material.lobe_shift(p), var = material.lobe_variance(p);
                e.a_f += af;
                e.a_b += ab;
                e.alpha_f += alpha * af;
                e.alpha_b += alpha * ab;
                e.beta2_f += var * af;
                e.beta2_b += var * ab;
            }
            // Lobe gains above 1 (lobes/lobe_controls.hpp) let a fiber return more light than
            // it receives, and every sum over fiber counts (a_f^n, the adding formula, Zinke
            // et al. 2008 eqs. 13–15) then diverges. The shaded fiber keeps its gains (its own
            // f); the fibers that carry light to it are capped at a lossless fiber's a_f + a_b
            // = 1, per channel, with the window's shape kept (docs/controls.md).
            for (int c = 0; c < 3; ++c) {
                const T total = e.a_f[c] + e.a_b[c];
                if (!(total > T(1))) continue;
                const T k = T(1) / total;
                e.a_f[c] *= k;
                e.a_b[c] *= k;
                for (int p = 0; p < L; ++p)
                    for (int j = 0; j < opt.psi_samples; ++j) t.window_[v.window_index(i, p, j)][c] *= k;
            }
            for (int c = 0; c < 3; ++c) {
                const T f = e.a_f[c], b = e.a_b[c];
                e.alpha_f[c] = f > T(0) ? e.alpha_f[c] / f : T(0);
                e.beta2_f[c] = f > T(0) ? e.beta2_f[c] / f : T(0);
                e.alpha_b[c] = b > T(0) ? e.alpha_b[c] / b : T(0);
                e.beta2_b[c] = b > T(0) ? e.beta2_b[c] / b : T(0);
            }
            derive_backscattering(e, opt.settings.d_b);
        }
        // rho_b on a θ grid of its own, kRhoNodes midpoints uniform in θ, interpolated onto
        // the table's nodes: a smooth ratio, and its cost then does not grow with theta_samples.
        constexpr int kRhoNodes = 32;
        std::vector<V3> rho(std::size_t(kRhoNodes), V3(T(1)));
        for (int j = 0; j < kRhoNodes; ++j) {
            const T theta = kPi<T> * (T(j) + T(0.5)) / T(kRhoNodes) - kHalfPi<T>;
            const V3 wo(std::sin(theta), std::cos(theta), T(0));
            if constexpr (kPerTheta) place_fibers(wo.x);
            rho[std::size_t(j)] = back_returns(fibers, h_weight, wo);
        }
        for (int i = 0; i < opt.theta_samples; ++i) {
            const T x = clamp((View::node_theta(i, opt.theta_samples) + kHalfPi<T>) * kInvPi<T> * T(kRhoNodes) - T(0.5), T(0),
                              T(kRhoNodes - 1));
            const int j = std::min(kRhoNodes - 2, int(x));
            const T f = x - T(j);
            t.entries_[std::size_t(i)].rho_b = rho[std::size_t(j)] + f * (rho[std::size_t(j) + 1] - rho[std::size_t(j)]);
        }
        t.finish();
        return t;
    }

    int size() const { return n_theta_; }
    int psi_samples() const { return n_psi_; }
    int lobes() const { return lobes_; }
    int h_nodes() const { return h_nodes_; }
    const DualScatteringSettings<T>& settings() const { return settings_; }
    const Entry& entry(int i) const { return entries_[std::size_t(i)]; }
    T theta_of(int i) const { return View::node_theta(i, n_theta_); }
    // Linear interpolation between the nodes (θ clamped to [-π/2, π/2]).
    Entry lookup(T theta) const { return view().lookup(std::sin(clamp(theta, -kHalfPi<T>, kHalfPi<T>))); }
    // W_p(θ, ψ) for lobe p (0 for a lobe the model does not have).
    V3 window(T theta, int p, T psi) const {
        if (p < 0 || p >= lobes_) return V3(T(0));
        const View v = view();
        return v.window_at(v.cell(std::sin(clamp(theta, -kHalfPi<T>, kHalfPi<T>))), p, std::abs(wrap_pi(psi)));
    }

    // The host view; on a GPU, copy entries(), window_data() and window_cdf_data() to device
    // memory and pass with_arrays(…) of the result.
    View view() const {
        View v = shape_;
        v.entries = entries_.data();
        v.window = window_.data();
        v.window_cdf = cdf_.data();
        return v;
    }
    static View with_arrays(View v, const Entry* entries, const V3* window, const T* window_cdf) {
        v.entries = entries;
        v.window = window;
        v.window_cdf = window_cdf;
        return v;
    }
    const std::vector<Entry>& entries() const { return entries_; }
    const std::vector<V3>& window_data() const { return window_; }
    const std::vector<T>& window_cdf_data() const { return cdf_; }

    // A small versioned binary file: "HSDT", version, the shape, the settings and the lobes'
    // shapes, entries and windows as doubles, and an FNV-1a checksum of everything before it.
    void save(const std::string& path) const {
        std::vector<unsigned char> buf;
        detail::put_bytes(buf, "HSDT", 4);
        for (std::uint32_t u : {kFileVersion, std::uint32_t(n_theta_), std::uint32_t(n_psi_), std::uint32_t(lobes_),
                                std::uint32_t(h_nodes_), std::uint32_t(settings_.formulation)})
            detail::put_bytes(buf, &u, 4);
        for (double d : {double(settings_.d_f), double(settings_.d_b)}) detail::put_bytes(buf, &d, 8);
        for (int p = 0; p < kMaxLobes; ++p)
            for (double d : {double(lobe_angle_[p]), double(lobe_variance_[p])}) detail::put_bytes(buf, &d, 8);
        for (const Entry& e : entries_)
            for (int k = 0; k < Entry::kFields; ++k) put_v3(buf, e.fields()[k]);
        for (const V3& w : window_) put_v3(buf, w);
        detail::write_table_file(path, std::move(buf), "dual-scattering tables");
    }

    // Reads a file written by save(). Rejects, with a message, a wrong magic, version,
    // size or checksum, and values that are not finite in T or outside what a fiber can
    // produce (albedos outside [0, 1], negative variances, …). The header's shape fixes the
    // file's size: a file of another size is refused before its payload is read or any of
    // it allocated (a 1 GiB file cost 1 GB and 31 s before), and a stream of unknown size
    // (a pipe) is read no further than the header promises.
    static DualScatteringTables load(const std::string& path) {
        std::ifstream f(path, std::ios::binary);
        if (!f) HAIRSCATTER_THROW(std::runtime_error("hairscatter: cannot open dual-scattering tables '" + path + "'"));
        auto fail = [&](const std::string& why) {
            return std::runtime_error("hairscatter: '" + path + "' is not a valid dual-scattering table file: " + why);
        };
        const std::size_t header = 4 + 6 * 4 + 2 * 8 + 2 * kMaxLobes * 8;
        // The file's size where the stream can seek (-1 for a pipe).
        f.seekg(0, std::ios::end);
        const std::streamoff size = f ? std::streamoff(f.tellg()) : std::streamoff(-1);
        f.clear();
        f.seekg(0, std::ios::beg);
        f.clear();
        std::vector<unsigned char> buf(header);
        f.read(reinterpret_cast<char*>(buf.data()), std::streamsize(header));
        buf.resize(std::size_t(f.gcount()));
        if (buf.size() < header || (size >= 0 && std::size_t(size) < header + 8) || std::memcmp(buf.data(), "HSDT", 4) != 0)
            HAIRSCATTER_THROW(fail("bad magic or too short"));
        std::size_t at = 4;
        std::uint32_t u[6];
        for (std::uint32_t& x : u) x = detail::get_bytes<std::uint32_t>(buf, at);
        if (u[0] != kFileVersion)
            HAIRSCATTER_THROW(fail("version " + std::to_string(u[0]) + ", this library reads version " + std::to_string(kFileVersion)));
        DualScatteringTables t;
        if (u[1] < 8 || u[1] > 65536) HAIRSCATTER_THROW(fail("implausible number of θ samples"));
        if (u[2] < 9 || u[2] > 65536) HAIRSCATTER_THROW(fail("implausible number of ψ samples"));
        if (u[3] < 1 || u[3] > std::uint32_t(kMaxLobes)) HAIRSCATTER_THROW(fail("number of lobes outside [1, 4]"));
        if (u[4] > 1000000) HAIRSCATTER_THROW(fail("implausible number of h nodes"));
        if (u[5] > 1) HAIRSCATTER_THROW(fail("unknown formulation"));
        t.n_theta_ = int(u[1]), t.n_psi_ = int(u[2]), t.lobes_ = int(u[3]), t.h_nodes_ = int(u[4]);
        t.settings_.formulation = DualFormulation(u[5]);
        const std::uint64_t values = std::uint64_t(t.n_theta_) * (Entry::kFields + std::uint64_t(t.lobes_) * std::uint64_t(t.n_psi_)) * 3;
        const std::uint64_t expected = header + values * 8 + 8;
        auto wrong_size = [&](std::uint64_t got) {
            return fail("size " + std::to_string(got) + " bytes, expected " + std::to_string(expected) +
                        (got < expected ? " (truncated?)" : " (data after the tables)"));
        };
        if (size >= 0 && std::uint64_t(size) != expected) HAIRSCATTER_THROW(wrong_size(std::uint64_t(size)));
        // The payload; from a pipe in chunks, so that a header promising more than the pipe
        // delivers allocates no more than what arrives.
        if (size >= 0) buf.reserve(std::size_t(expected));
        while (buf.size() < expected) {
            const std::size_t have = buf.size(), most = std::size_t(1) << 24;
            const std::size_t chunk = expected - have < most ? std::size_t(expected - have) : most;
            buf.resize(have + chunk);
            f.read(reinterpret_cast<char*>(buf.data() + have), std::streamsize(chunk));
            buf.resize(have + std::size_t(f.gcount()));
            if (std::size_t(f.gcount()) < chunk) HAIRSCATTER_THROW(wrong_size(buf.size()));
        }
        if (f.peek() != std::ifstream::traits_type::eof())
            HAIRSCATTER_THROW(fail("longer than the " + std::to_string(expected) + " bytes its header announces"));
        std::uint64_t sum;
        std::memcpy(&sum, buf.data() + std::size_t(expected) - 8, 8);
        if (sum != detail::fnv1a(buf.data(), std::size_t(expected) - 8)) HAIRSCATTER_THROW(fail("checksum mismatch (corrupt file)"));
        // Every value is checked after its conversion to T (1e300 is finite as a double,
        // not as a float) and against the range a fiber can produce.
        auto value = [&](double lo, double hi, const char* what) {
            const T v = T(detail::get_bytes<double>(buf, at));
            if (!(std::isfinite(double(v)) && double(v) >= lo && double(v) <= hi))
                HAIRSCATTER_THROW(fail(std::string(what) + " = " + std::to_string(double(v)) + " outside [" + std::to_string(lo) +
                           ", " + std::to_string(hi) + "]"));
            return v;
        };
        t.settings_.d_f = value(0, 1, "d_f");
        t.settings_.d_b = value(0, 1, "d_b");
        for (int p = 0; p < kMaxLobes; ++p) {
            const T angle = value(-kHalfPi<double>, kHalfPi<double>, "a lobe's tilt");
            t.set_lobe(p, angle, value(p < t.lobes_ ? 1e-12 : 0, 1e6, "a lobe's variance"));
        }
        // Albedos are ≤ 1 up to the build's rounding; the derived A_b of Zinke's series may
        // exceed 1 for a nearly lossless fiber, so only finiteness and sign are required.
        static const double kField[Entry::kFields][2] = {{0, 1.001}, {0, 1.001}, {-kPi<double>, kPi<double>},
                                                        {-kPi<double>, kPi<double>}, {0, 1e6}, {0, 1e6},
                                                        {0, 1e6}, {-1e6, 1e6}, {0, 1e6}, {-1, 1}, {-1, 1}, {0, 1}};
        static const char* kName[Entry::kFields] = {"a_f", "a_b", "alpha_f", "alpha_b", "beta2_f", "beta2_b",
                                                    "A_b", "delta_b", "sigma2_b", "mu_f", "mu_b", "rho_b"};
        t.entries_.resize(std::size_t(t.n_theta_));
        for (Entry& e : t.entries_) {
            for (int k = 0; k < Entry::kFields; ++k)
                for (int c = 0; c < 3; ++c) e.fields()[k][c] = value(kField[k][0], kField[k][1], kName[k]);
            for (int c = 0; c < 3; ++c)
                if (double(e.a_f[c]) + double(e.a_b[c]) > 1.001) HAIRSCATTER_THROW(fail("a_f + a_b exceeds 1"));
        }
        t.window_.resize(std::size_t(t.n_theta_) * std::size_t(t.lobes_) * std::size_t(t.n_psi_));
        for (V3& w : t.window_)
            for (int c = 0; c < 3; ++c) w[c] = value(0, 1.001 / kPi<double>, "a window value W_p");
        t.finish();
        return t;
    }

  private:
    // Entry::mu_f and mu_b at wo: the fiber's f over the sphere of wi, averaged over the
    // fibers' h with their weights: Gauss–Legendre in sin θi (dω = d sin θi dφ) times the
    // trapezoid rule of the periodic φ. 8 × 32 nodes resolve the h-averaged lobes at the
    // shipped roughness (against Monte Carlo of the fiber over the whole sphere within 0.01,
    // dual_tables_test); the mean cosine is a ratio, so the rule's error largely cancels.
    template <typename Fiber>
    static void azimuthal_turns(const std::vector<Fiber>& fibers, const std::vector<T>& h_weight, const V3& wo, Entry& e) {
        constexpr int kThetaNodes = 8, kPhiNodes = 32;
        static const GaussLegendre<T> gl(kThetaNodes);
        T cos_phi[kPhiNodes], sin_phi[kPhiNodes];
        for (int j = 0; j < kPhiNodes; ++j) {
            const T phi = kTwoPi<T> * (T(j) + T(0.5)) / T(kPhiNodes) - kPi<T>;
            cos_phi[j] = std::cos(phi);
            sin_phi[j] = std::sin(phi);
        }
        V3 f_sum(T(0)), f_cos(T(0)), b_sum(T(0)), b_cos(T(0));
        for (int i = 0; i < kThetaNodes; ++i) {
            const T u = gl.nodes[std::size_t(i)], w = gl.weights[std::size_t(i)], r = std::sqrt(std::max(T(1) - u * u, T(0)));
            for (int j = 0; j < kPhiNodes; ++j) {
                const V3 wi(u, r * cos_phi[j], r * sin_phi[j]);
                V3 f(T(0));
                for (std::size_t k = 0; k < fibers.size(); ++k) f += h_weight[k] * fibers[k].eval(wo, wi);
                f *= w;
                const T c = cos_phi[j];
                if (c < T(0)) {  // the forward half: the turn is φ − π
                    f_sum += f;
                    f_cos -= c * f;
                } else {
                    b_sum += f;
                    b_cos += c * f;
                }
            }
        }
        for (int ch = 0; ch < 3; ++ch) {
            e.mu_f[ch] = f_sum[ch] > T(0) ? clamp(f_cos[ch] / f_sum[ch], T(-1), T(1)) : T(0);
            e.mu_b[ch] = b_sum[ch] > T(0) ? clamp(b_cos[ch] / b_sum[ch], T(-1), T(1)) : T(0);
        }
    }

    // rho_b at wo: of the light the fibers scatter into the backward half (wi on wo's
    // side of the fiber), the share with wo · wi > 0, whose travel (−wo, then wi) runs back
    // along the stack. The boundary wo · wi = 0 cuts through the lobes, which a product rule
    // over the sphere resolves poorly where they are narrow (8 × 32 nodes: 0.15 off for brown
    // hair at 45°), so each fiber's own sampler draws the directions instead: the points of
    // one Kronecker sequence (the R₄ sequence of the generalised golden ratio, Roberts 2018;
    // each fiber the next ones), weighted by f/pdf and the fiber's h weight; deterministic,
    // within 0.03 of Monte Carlo of the fiber (dual_tables_test).
    template <typename Fiber>
    static V3 back_returns(const std::vector<Fiber>& fibers, const std::vector<T>& h_weight, const V3& wo) {
        // 4,096 directions per θ over the fibers (128 each over the 32 h nodes), at least 32 a
        // fiber and at most 1,024 (a far-field model's one fiber: its sampler costs more).
        const int points = int(std::min<std::size_t>(1024, std::max<std::size_t>(32, 4096 / std::max<std::size_t>(1, fibers.size()))));
        // R₄: 1/g, 1/g², 1/g³, 1/g⁴ with g the real root of x⁵ = x + 1.
        constexpr double g = 1.1673039782614187, a1 = 1 / g, a2 = a1 / g, a3 = a2 / g, a4 = a3 / g;
        const auto frac = [](double v) { return v - std::floor(v); };
        V3 back(T(0)), returned(T(0));
        for (std::size_t k = 0; k < fibers.size(); ++k) {
            for (int i = 0; i < points; ++i) {
                const double x = 0.5 + double(k * std::size_t(points) + std::size_t(i));  // each fiber its own points
                const glm::vec<4, T> u(T(frac(x * a1)), T(frac(x * a2)), T(frac(x * a3)), T(frac(x * a4)));
                const auto s = fibers[k].sample(wo, u);
                if (!(s.pdf > T(0)) || !(s.wi.y >= T(0))) continue;  // none, or the forward half
                const V3 w = h_weight[k] * s.weight;
                back += w;
                if (glm::dot(wo, s.wi) > T(0)) returned += w;
            }
        }
        V3 rho(T(1));
        for (int ch = 0; ch < 3; ++ch) rho[ch] = back[ch] > T(0) ? clamp(returned[ch] / back[ch], T(0), T(1)) : T(1);
        return rho;
    }

    static void check(const DualTableOptions<T>& opt) {
        if (opt.theta_samples < 8 || opt.theta_samples > 65536)
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DualTableOptions::theta_samples must lie in [8, 65536]"));
        if (opt.psi_samples < 9 || opt.psi_samples > 65536)
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DualTableOptions::psi_samples must lie in [9, 65536]"));
        // One or two nodes in γ cannot integrate cos γ (1 node: a lossless albedo of π/2).
        if (opt.h_nodes < 8 || opt.h_nodes > 4096)
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DualTableOptions::h_nodes must lie in [8, 4096]"));
        const DualScatteringSettings<T>& s = opt.settings;
        if (!(s.d_f >= T(0) && s.d_f <= T(1)))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DualScatteringSettings::d_f must lie in [0, 1]"));
        if (!(s.d_b >= T(0) && s.d_b <= T(1)))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DualScatteringSettings::d_b must lie in [0, 1]"));
        if (s.formulation != DualFormulation::kImproved && s.formulation != DualFormulation::kZinke2008)
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DualScatteringSettings::formulation is not a known formulation"));
    }

    View shape_view() const {
        View v;
        v.n_theta = n_theta_;
        v.n_psi = n_psi_;
        v.lobes = lobes_;
        v.settings = settings_;
        for (int p = 0; p < kMaxLobes; ++p) {
            v.lobe_angle[p] = lobe_angle_[p];
            v.lobe_variance[p] = lobe_variance_[p];
            v.lobe_sin[p] = lobe_sin_[p];
            v.lobe_cos[p] = lobe_cos_[p];
        }
        return v;
    }
    // A lobe's tilt and variance, and the tilt's sine and cosine (computed here once, not at
    // every view(): a renderer may take a view per hit).
    void set_lobe(int p, T angle, T variance) {
        lobe_angle_[p] = angle;
        lobe_variance_[p] = variance;
        lobe_sin_[p] = std::sin(angle);
        lobe_cos_[p] = std::cos(angle);
    }

    // The sampler's per-row, per-lobe CDF over ψ ∈ [0, π] of the channel mean of W_p
    // (trapezoids: the exact integral of the piecewise-linear interpolant); and the view's
    // shape, kept whole so that view() is one copy (a renderer may take a view per hit).
    // Build and load end here, once every field of the shape is set.
    void finish() {
        const View v = shape_view();
        shape_ = v;
        cdf_.assign(window_.size(), T(0));
        const T h = kPi<T> / T(n_psi_ - 1);
        for (int i = 0; i < n_theta_; ++i)
            for (int p = 0; p < lobes_; ++p) {
                T acc = T(0);
                for (int j = 1; j < n_psi_; ++j) {
                    const V3& a = window_[v.window_index(i, p, j - 1)];
                    const V3& b = window_[v.window_index(i, p, j)];
                    acc += T(0.5) * h * ((a.x + a.y + a.z) + (b.x + b.y + b.z)) * T(1.0 / 3.0);
                    cdf_[v.window_index(i, p, j)] = acc;
                }
            }
    }

    static void put_v3(std::vector<unsigned char>& b, const V3& v) {
        for (int c = 0; c < 3; ++c) {
            const double d = double(v[c]);
            detail::put_bytes(b, &d, 8);
        }
    }

    std::vector<Entry> entries_;
    std::vector<V3> window_;
    std::vector<T> cdf_;
    View shape_;  // shape_view() as of finish(), without the arrays
    int n_theta_ = 0, n_psi_ = 0, lobes_ = 0, h_nodes_ = 0;
    T lobe_angle_[std::size_t(kMaxLobes)] = {}, lobe_variance_[std::size_t(kMaxLobes)] = {};
    T lobe_sin_[std::size_t(kMaxLobes)] = {}, lobe_cos_[std::size_t(kMaxLobes)] = {T(1), T(1), T(1), T(1)};
    DualScatteringSettings<T> settings_{};
};

}  // namespace hairscatter
