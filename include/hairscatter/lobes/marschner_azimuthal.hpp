// hairscatter — Marschner et al. 2003's smooth-fiber azimuthal scattering: the cubic
// approximation of the exit azimuth, its roots, the pushforward of a uniform offset h
// through it, the root sum N_p, the TRT caustic replacement and the eccentric index η*.
#pragma once

#include <cmath>

#include "../config.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"

namespace hairscatter {

// Marschner et al. 2003 eq. 10: with c = asin(1/η'), the exit azimuth of lobe p as a cubic
// in the entry angle γ = asin h ∈ [-π/2, π/2],
//   Φ̂(p, γ) = (6pc/π - 2) γ - (8pc/π³) γ³ + pπ = f(γ) + pπ,
// exact at γ = 0 and ±π/2 (where Φ = 2pγt - 2γ + pπ). f is odd, so everything below works
// with f and a target x = φ - pπ. R (p = 0) is linear; TT is monotone for η' > 2/√3; TRT
// folds back (a caustic, f' = 0) at ±γc for η' < 2.
template <typename T> class MarschnerCubic {
  public:
    static constexpr int kMaxRoots = 3;

    MarschnerCubic() = default;
    // inv_eta_prime = 1/η' ∈ [0, 1] (clamped: 0 is the η' → ∞ limit, where f = -2γ).
    HAIRSCATTER_HD MarschnerCubic(int p, T inv_eta_prime) : p_(p) {
        using std::sqrt;
        const T c = elem::asin(clamp(inv_eta_prime, T(0), T(1)));
        a1_ = T(6 * p) * c * kInvPi<T> - T(2);
        a3_ = T(-8 * p) * c * (kInvPi<T> * kInvPi<T> * kInvPi<T>);
        half_range_ = abs_(f(kHalfPi<T>));
        // An interior extremum exists iff f'(0) = a1 > 0 (a3 < 0); it lies inside
        // (-π/2, π/2) because f'(π/2) = -2 < 0 for every c.
        if (a1_ > T(0) && a3_ < T(0)) {
            fold_ = sqrt(-a1_ / (T(3) * a3_));
            const T v = f(fold_);
            half_range_ = v > half_range_ ? v : half_range_;
        }
    }

    HAIRSCATTER_HD int lobe() const { return p_; }
    HAIRSCATTER_HD T f(T gamma) const { return (a1_ + a3_ * gamma * gamma) * gamma; }      // Φ̂ - pπ
    HAIRSCATTER_HD T df(T gamma) const { return a1_ + T(3) * a3_ * gamma * gamma; }        // dΦ̂/dγ
    HAIRSCATTER_HD T d2f(T gamma) const { return T(6) * a3_ * gamma; }                      // d²Φ̂/dγ²
    HAIRSCATTER_HD T exit_azimuth(T gamma) const { return f(gamma) + T(p_) * kPi<T>; }    // Φ̂(p, γ)
    // max |f| over [-π/2, π/2]: f maps the fiber onto [-half_range, half_range].
    HAIRSCATTER_HD T half_range() const { return half_range_; }
    // γc > 0 of the fold (caustic), or 0 when f is monotone.
    HAIRSCATTER_HD T fold() const { return fold_; }

    // The real roots γ ∈ [-π/2, π/2] of f(γ) = x, ascending; returns their number (0–3).
    // Linear when a3 = 0 (R, or η' → ∞). Otherwise the depressed cubic γ³ + Pγ + Q = 0,
    // P = a1/a3, Q = -x/a3: one real root by Cardano in the form without cancellation
    // (A = -sign(Q) ∛(|Q|/2 + √D), γ = A - P/3A, for D = Q²/4 + P³/27 > 0), three by the
    // trigonometric form (D ≤ 0). Each root is polished by Newton steps on f that are kept
    // only while they reduce the residual, which restores full precision where the closed
    // forms lose it (near the fold, and for η' → ∞ where P and Q grow without bound).
    HAIRSCATTER_HD int roots(T x, T out[kMaxRoots]) const {
        using std::acos;
        using std::cbrt;
        using std::cos;
        using std::sqrt;
        T r[kMaxRoots];
        int n = 0;
        if (a3_ == T(0)) {
            r[n++] = x / a1_;
        } else {
            const T P = a1_ / a3_, Q = -x / a3_;
            const T D = T(0.25) * Q * Q + P * P * P * T(1.0 / 27.0);
            if (D > T(0)) {
                const T A = (Q > T(0) ? T(-1) : T(1)) * cbrt(T(0.5) * abs_(Q) + sqrt(D));
                r[n++] = A != T(0) ? A - P / (T(3) * A) : T(0);
            } else {
                // P < 0 here. γ_k = 2m cos(ψ/3 - 2πk/3), cos ψ = (3Q / 2P) √(-3/P).
                const T m = sqrt(-P * T(1.0 / 3.0));
                const T psi = acos(clamp(T(1.5) * Q / P * sqrt(T(-3) / P), T(-1), T(1)));
                for (int k = 0; k < 3; ++k) r[n++] = T(2) * m * cos((psi - kTwoPi<T> * T(k)) * T(1.0 / 3.0));
            }
        }
        int kept = 0;
        // Roots a few ulp outside the fiber come from a target at the end of the range.
        const T lim = kHalfPi<T> * (T(1) + T(16) * kEpsilon<T>);
        for (int i = 0; i < n; ++i) {
            T g = polish(r[i], x);
            if (!(g >= -lim && g <= lim)) continue;
            out[kept++] = clamp(g, -kHalfPi<T>, kHalfPi<T>);
        }
        // Ascending order (at most three: a fixed sorting network).
        if (kept > 1 && out[1] < out[0]) swap_(out[0], out[1]);
        if (kept > 2 && out[2] < out[1]) swap_(out[1], out[2]);
        if (kept > 1 && out[1] < out[0]) swap_(out[0], out[1]);
        return kept;
    }

    // The pushforward of a uniform h ∈ [-1, 1] through f: C(x) = ½ |{h : f(asin h) ≤ x}|.
    HAIRSCATTER_HD T cdf(T x) const {
        if (!(x < half_range_)) return T(1);
        if (!(x >= -half_range_)) return T(0);
        return mass(-half_range_ - T(1), x);
    }

    // ½ |{h : lo < f(asin h) ≤ hi}| for lo ≤ hi. The roots of f = lo and f = hi split
    // [-π/2, π/2] into pieces on which f lies on one side of each; a piece counts when its
    // midpoint's f lies in (lo, hi] (robust to double roots and to rounding of the roots).
    // A piece [a, b] holds sin b - sin a = 2 cos((a + b)/2) sin((b - a)/2) of h, taken in
    // that form: a difference of two CDFs near 0 or 1 (a window at the end of f's range)
    // would keep only the rounding of h there (6e-8 in float).
    HAIRSCATTER_HD T mass(T lo, T hi) const {
        using std::cos;
        using std::sin;
        T b[2 * kMaxRoots + 2];
        int n = 0;
        b[n++] = -kHalfPi<T>;
        if (lo >= -half_range_ && lo <= half_range_) n += roots(lo, b + n);
        if (hi >= -half_range_ && hi <= half_range_) n += roots(hi, b + n);
        b[n++] = kHalfPi<T>;
        for (int i = 1; i < n; ++i)  // insertion sort, at most 8 entries
            for (int j = i; j > 0 && b[j] < b[j - 1]; --j) swap_(b[j], b[j - 1]);
        T m = T(0);
        for (int i = 0; i + 1 < n; ++i) {
            if (!(b[i + 1] > b[i])) continue;
            const T mid = T(0.5) * (b[i] + b[i + 1]);
            const T fm = f(mid);
            const T c = cos(mid);  // float(π/2) rounds up: cos would be -4e-8 at the end
            if (fm > lo && fm <= hi && c > T(0)) m += c * sin(T(0.5) * (b[i + 1] - b[i]));
        }
        return m;
    }

    // Probability that Φ̂(p, asin h), read on the circle, falls in the arc [a, a + len]
    // (len ≥ 0) for a uniform h: whole turns count 1 each; the rest of the arc, shifted to
    // start in [-π, π] relative to pπ, meets f's range [-R, R] (R < 2π) in at most the
    // images n = -2 … 1.
    HAIRSCATTER_HD T arc_mass(T a, T len) const {
        using std::floor;
        const T turns = floor(len * kInvTwoPi<T>);
        const T rest = len - turns * kTwoPi<T>;
        const T x0 = wrap_pi(a - T(p_) * kPi<T>);
        T total = turns;
        for (int n = -2; n <= 1; ++n) {
            const T lo = x0 + T(n) * kTwoPi<T>, hi = lo + rest;
            if (hi < -half_range_ || lo > half_range_) continue;
            total += mass(lo, hi);
        }
        return total;
    }

  private:
    HAIRSCATTER_HD static T abs_(T x) { return x < T(0) ? -x : x; }
    HAIRSCATTER_HD static void swap_(T& a, T& b) {
        const T t = a;
        a = b;
        b = t;
    }
    HAIRSCATTER_HD T polish(T g, T x) const {
        T res = abs_(f(g) - x);
        for (int it = 0; it < 3 && res > T(0); ++it) {
            const T d = df(g);
            if (d == T(0)) break;
            const T next = g - (f(g) - x) / d;
            const T next_res = abs_(f(next) - x);
            if (!(next_res < res)) break;
            g = next;
            res = next_res;
        }
        return g;
    }

    int p_ = 0;
    T a1_ = T(-2), a3_ = T(0), half_range_ = kPi<T>, fold_ = T(0);
};

// Marschner et al. 2003 eq. 8: the smooth fiber's azimuthal function
//   N_p(φ) = Σ_r A_p(h_r) / |2 dΦ/dh (h_r)|,   dΦ/dh = Φ̂'(γ) / cos γ,
// over every root h_r = sin γ_r of Φ̂(p, γ) ≡ φ (mod 2π). attenuation(h, cos γ) gives A_p
// at one root (scalar or RGB). At a fold Φ̂' = 0 and N is infinite (TRT's caustics, which
// the model replaces, and TT's for η' < 2/√3): |Φ̂'| is floored at √ε so that a φ exactly
// on a fold gives a large finite value instead of Inf.
template <typename T, typename Attenuation>
HAIRSCATTER_HD auto marschner_root_sum(const MarschnerCubic<T>& cubic, T phi, const Attenuation& attenuation)
    -> decltype(attenuation(T(0), T(1))) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    using R = decltype(attenuation(T(0), T(1)));
    R sum = R(T(0));
    const T x = wrap_pi(phi - T(cubic.lobe()) * kPi<T>);
    const T floor_df = sqrt(kEpsilon<T>);
    // f's range [-R, R] has R < 3.5 < 3π: the images x - 2π, x, x + 2π cover it.
    for (int n = -1; n <= 1; ++n) {
        const T xn = x + T(n) * kTwoPi<T>;
        if (xn < -cubic.half_range() || xn > cubic.half_range()) continue;
        T g[MarschnerCubic<T>::kMaxRoots];
        const int m = cubic.roots(xn, g);
        for (int i = 0; i < m; ++i) {
            const T d = cubic.df(g[i]);
            const T ad = d < T(0) ? -d : d;
            const T cg = cos(g[i]);
            const T cos_g = cg > T(0) ? cg : T(0);  // float(π/2) rounds up: cos would be -4e-8
            sum += attenuation(sin(g[i]), cos_g) * (cos_g / (T(2) * (ad > floor_df ? ad : floor_df)));
        }
    }
    return sum;
}

// Marschner et al. 2003 §4.3: the TRT caustics. Where the cubic folds (η' < 2) N_TRT is
// infinite at ±φc = ±f(γc); the model multiplies the root sum by
//   (1 - t g(wc; φ - φc)/g(wc; 0)) (1 - t g(wc; φ + φc)/g(wc; 0)),
// which vanishes quadratically at ±φc and so cancels the 1/√ singularity, and adds
//   t kG A_TRT(hc) Δh (g(wc; φ - φc) + g(wc; φ + φc)),
//   Δh = min(Δh_M, 2 √(2 wc / |∂²Φ/∂h²(hc)|)),   ∂²Φ/∂h² = Φ̂''(γc)/cos²γc at a fold.
// For η' ≥ 2 the caustics have merged at φ = 0 (hc = 0, Δh = Δh_M) and fade out with
// t = 1 - smoothstep(2, 2 + Δη', η'). Here φc, γc come from the cubic itself, so the
// removed singularity is exactly the one the root sum has.
template <typename T> struct MarschnerCaustic {
    T t = T(0);          // fade: 1 while the fold exists, → 0 over [2, 2 + Δη']
    T gamma_c = T(0);    // γc of the fold (0 once merged)
    T phi_c = T(0);      // φc - 2π, relative to the TRT centre
    T dh = T(0);         // Δh
    T width = T(1);      // wc

    MarschnerCaustic() = default;
    HAIRSCATTER_HD MarschnerCaustic(const MarschnerCubic<T>& trt, T eta_prime, T width_c, T fade, T dh_max)
        : width(width_c) {
        using std::cos;
        using std::sqrt;
        if (trt.fold() > T(0)) {
            t = T(1);
            gamma_c = trt.fold();
            phi_c = trt.f(gamma_c);
            const T d2 = trt.d2f(gamma_c) / sqr(cos(gamma_c));
            const T ad2 = d2 < T(0) ? -d2 : d2;
            const T lim = ad2 > T(0) ? T(2) * sqrt(T(2) * width_c / ad2) : dh_max;
            dh = lim < dh_max ? lim : dh_max;
        } else {
            const T s = clamp((eta_prime - T(2)) / fade, T(0), T(1));
            t = T(1) - s * s * (T(3) - T(2) * s);
            dh = dh_max;
        }
    }

    // The two factors that remove the fold from the root sum, at φ relative to the centre.
    HAIRSCATTER_HD T smooth_factor(T x) const {
        const T e1 = elem::exp(T(-0.5) * sqr(wrap_pi(x - phi_c) / width));
        const T e2 = elem::exp(T(-0.5) * sqr(wrap_pi(x + phi_c) / width));
        // t e ≤ 1 analytically; a float exp a few ulp above 1 must not flip the sign.
        const T f1 = T(1) - t * e1, f2 = T(1) - t * e2;
        return (f1 > T(0) ? f1 : T(0)) * (f2 > T(0) ? f2 : T(0));
    }
    // t Δh (g(wc; φ - φc) + g(wc; φ + φc)); the caller multiplies by kG A_TRT(hc).
    HAIRSCATTER_HD T lobes(T x) const {
        return t * dh * (gaussian(width, wrap_pi(x - phi_c)) + gaussian(width, wrap_pi(x + phi_c)));
    }
};

// Marschner et al. 2003 §4.4: an elliptical cross-section of eccentricity a changes the
// index the azimuthal geometry sees, η*(φh) = ½((η*1 + η*2) + cos 2φh (η*1 - η*2)),
// η*1 = 2(η - 1)a² - η + 2, η*2 = 2(η - 1)/a² - η + 2 (φh measured from the major axis,
// the frame's y). The linearisation leaves (1, ∞) for strong eccentricity (η = 1.55,
// a = 0.5 gives 0.725); η* is floored at 1.001, just above the vacuum, where the cubic
// and the Fresnel factors stay defined.
template <typename T> struct EccentricIndex {
    T eta1 = T(1.55), eta2 = T(1.55);

    EccentricIndex() = default;
    HAIRSCATTER_HD EccentricIndex(T eta, T a) {
        const T a2 = a * a;
        eta1 = T(2) * (eta - T(1)) * a2 - eta + T(2);
        eta2 = T(2) * (eta - T(1)) / a2 - eta + T(2);
    }
    HAIRSCATTER_HD T operator()(T cos_2phi_h) const {
        const T e = T(0.5) * ((eta1 + eta2) + cos_2phi_h * (eta1 - eta2));
        return e > T(1.001) ? e : T(1.001);
    }
};

}  // namespace hairscatter
