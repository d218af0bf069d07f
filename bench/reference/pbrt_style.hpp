// bench_ref — a straightforward re-implementation of the algorithm that pbrt-v4's
// HairBxDF::f / Sample_f / PDF uses, written for this project from the equations of
// docs/theory.md §3–4 (not copied from pbrt). It exists only as the speed (and accuracy)
// reference of bench/: the same model as hairscatter::ChiangFiber, computed the way pbrt
// computes it, so that "reference / ours" can be measured in one binary.
//
// What it reproduces on purpose (the costs of pbrt's structure):
//   - The constructor is per hit (pbrt builds a HairBxDF per intersection): v_p, the
//     logistic scale s and sin/cos(2^k α) are computed there; everything else per call.
//   - Every call recomputes θo, θi from the components, φo and φi each by atan2, γo by
//     asin, η', γt, T = exp(-σa ℓ) and A_p (PDF and Sample_f through a separate
//     "ApPDF" routine that recomputes them again).
//   - I0 is the plain 10-term power series Σ_{k=0}^{9} x^(2k) / (4^k (k!)²), with x^(2k),
//     4^k and k! accumulated in the working type. In float its last terms underflow into
//     subnormals for small arguments (the β_m = 1 slow path), and it is off by ~1.5 % at
//     x = 12 from truncation.
//   - M_p switches to log space for v ≤ 0.1, with log I0(x) from the series for x ≤ 12
//     and the asymptotic x + ½(-log 2π + log(1/x) + 1/(8x)) above (see LogI0).
//   - The trimmed logistic N_p recomputes its normaliser (two logistic CDFs) every call.
//   - Sample_f picks the lobe by the channel-mean A_p, samples M_p with
//     cosθ = 1 + v ln(max(u, 1e-5) + (1 - u) e^(-2/v)), samples N_p by the logistic
//     inverse CDF, sums the full pdf over all lobes, and finally calls f() again.
// Deliberate differences from pbrt-v4: std::exp instead of pbrt's FastExp (a 2^x
// polynomial), three RGB channels instead of four spectral samples, and four explicit
// uniforms (u0 lobe, u1 u2 for θ, u3 for φ) instead of pbrt's reuse of one remapped
// uniform — the same inputs as ChiangFiber::sample, so both can be fed one array.
// Frame: hairscatter's fiber frame (= pbrt's hair frame): sinθ = w.x, φ = atan2(w.z, w.y).
// HairBxDF<T, true> replaces the I0 series and log I0 by accurate forms: bench_crosscheck's
// "truth" (double), never benchmarked.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace bench_ref {

template <typename T> inline constexpr T kPi = T(3.14159265358979323846);
template <typename T> inline constexpr T kInv2Pi = T(0.159154943091895335768883763372514362);
constexpr int kPMax = 3;

template <typename T> inline T Sqr(T x) { return x * x; }
template <typename T> inline T SafeSqrt(T x) { return std::sqrt(std::max(x, T(0))); }
template <typename T> inline T SafeASin(T x) { return std::asin(std::clamp(x, T(-1), T(1))); }

// I0 by its power series, x^(2k) / (4^k (k!)²), accumulated term by term.
template <typename T, int kTerms> inline T I0(T x) {
    T val = T(0), x2i = T(1), four_i = T(1);
    T fact = T(1);
    for (int i = 0; i < kTerms; ++i) {
        if (i > 1) fact *= T(i);
        val += x2i / (four_i * Sqr(fact));
        x2i *= x * x;
        four_i *= T(4);
    }
    return val;
}

// log I0 as pbrt computes it: the series up to x = 12, then the asymptotic form
// x + ½(-log 2π + log(1/x) + 1/(8x)). Its last term should be 1/(8x), not 1/(16x): that
// costs it a relative error of ~1/(16x) in M_p (5e-3 at x = 12) on top of the series'
// truncation error just below 12.
template <typename T, int kTerms> inline T LogI0(T x) {
    if (x > T(12))
        return x + T(0.5) * (-std::log(T(2) * kPi<T>) + std::log(T(1) / x) + T(1) / (T(8) * x));
    return std::log(I0<T, kTerms>(x));
}

// Accurate I0 and log I0 for the cross-check's "truth" (double only): the series by the
// term recurrence t_k = t_{k-1} (x²/4) / k² (no overflow), summed to convergence, up to
// x = 50, beyond it the asymptotic expansion e^x / √(2πx) Σ_k ((2k-1)!!)² / (k! (8x)^k)
// to 12 terms (the first omitted term is below 1e-17 there).
template <typename T> inline T I0Accurate(T x) {
    const T y = T(0.25) * x * x;
    T term = T(1), sum = T(1);
    for (int k = 1; k < 400 && term > T(1e-18) * sum; ++k) {
        term *= y / T(k * k);
        sum += term;
    }
    return sum;
}

template <typename T> inline T LogI0Accurate(T x) {
    if (x > T(50)) {
        T term = T(1), sum = T(0);
        for (int k = 1; k <= 12; ++k) {
            term *= T((2 * k - 1) * (2 * k - 1)) / (T(8 * k) * x);
            sum += term;
        }
        return x - T(0.5) * std::log(T(2) * kPi<T> * x) + std::log1p(sum);
    }
    return std::log(I0Accurate(x));
}

// d'Eon et al. 2011's M_p, direct for v > 0.1, in log space for v ≤ 0.1 (ln 2 rounded to
// 0.6931 as pbrt has it). kAccurate (cross-check only): exact ln 2, I0Accurate and
// LogI0Accurate.
template <typename T, bool kAccurate> inline T Mp(T cos_i, T cos_o, T sin_i, T sin_o, T v) {
    const T a = cos_i * cos_o / v, b = sin_i * sin_o / v;
    if constexpr (kAccurate) {
        if (v <= T(0.1))
            return std::exp(LogI0Accurate(a) - b - T(1) / v + std::log(T(2)) + std::log(T(1) / (T(2) * v)));
        return (std::exp(-b) * I0Accurate(a)) / (std::sinh(T(1) / v) * T(2) * v);
    } else {
        if (v <= T(0.1))
            return std::exp(LogI0<T, 10>(a) - b - T(1) / v + T(0.6931) + std::log(T(1) / (T(2) * v)));
        return (std::exp(-b) * I0<T, 10>(a)) / (std::sinh(T(1) / v) * T(2) * v);
    }
}

template <typename T> inline T Logistic(T x, T s) {
    x = std::abs(x);
    return std::exp(-x / s) / (s * Sqr(T(1) + std::exp(-x / s)));
}
template <typename T> inline T LogisticCDF(T x, T s) { return T(1) / (T(1) + std::exp(-x / s)); }
template <typename T> inline T TrimmedLogistic(T x, T s, T a, T b) {
    return Logistic(x, s) / (LogisticCDF(b, s) - LogisticCDF(a, s));
}
template <typename T> inline T SampleTrimmedLogistic(T u, T s, T a, T b) {
    const T k = LogisticCDF(b, s) - LogisticCDF(a, s);
    const T x = -s * std::log(T(1) / (u * k + LogisticCDF(a, s)) - T(1));
    return std::clamp(x, a, b);
}

template <typename T> inline T Phi(int p, T gamma_o, T gamma_t) {
    return T(2 * p) * gamma_t - T(2) * gamma_o + T(p) * kPi<T>;
}
template <typename T> inline T Np(T phi, int p, T s, T gamma_o, T gamma_t) {
    T dphi = phi - Phi(p, gamma_o, gamma_t);
    while (dphi > kPi<T>) dphi -= T(2) * kPi<T>;
    while (dphi < -kPi<T>) dphi += T(2) * kPi<T>;
    return TrimmedLogistic(dphi, s, -kPi<T>, kPi<T>);
}

template <typename T> inline T FrDielectric(T cos_i, T eta) {
    cos_i = std::clamp(cos_i, T(-1), T(1));
    if (cos_i < T(0)) {
        eta = T(1) / eta;
        cos_i = -cos_i;
    }
    const T sin2_i = T(1) - Sqr(cos_i);
    const T sin2_t = sin2_i / Sqr(eta);
    if (sin2_t >= T(1)) return T(1);
    const T cos_t = SafeSqrt(T(1) - sin2_t);
    const T r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const T r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return (Sqr(r_parl) + Sqr(r_perp)) / T(2);
}

template <typename T> using V3 = glm::vec<3, T>;

template <typename T> struct Ap {
    V3<T> a[kPMax + 1];
};

template <typename T> inline Ap<T> ComputeAp(T cos_theta_o, T eta, T h, const V3<T>& tr) {
    Ap<T> ap;
    const T cos_gamma_o = SafeSqrt(T(1) - h * h);
    const T f = FrDielectric(cos_theta_o * cos_gamma_o, eta);
    ap.a[0] = V3<T>(f);
    ap.a[1] = Sqr(T(1) - f) * tr;
    for (int p = 2; p < kPMax; ++p) ap.a[p] = ap.a[p - 1] * tr * f;
    for (int c = 0; c < 3; ++c) {
        const T d = T(1) - tr[c] * f;
        ap.a[kPMax][c] = d != T(0) ? ap.a[kPMax - 1][c] * f * tr[c] / d : T(0);
    }
    return ap;
}

template <typename T> struct Sample {
    V3<T> f{T(0)};  // pbrt's f (already divided by |wi.z|)
    V3<T> wi{T(0)};
    T pdf = T(0);
};

template <typename T, bool kAccurate = false> class HairBxDF {
  public:
    using V = V3<T>;

    // Per hit, like pbrt: roughness mappings and the cuticle-tilt double angles.
    HairBxDF(T h, T eta, const V& sigma_a, T beta_m, T beta_n, T alpha)
        : h_(h), eta_(eta), sigma_a_(sigma_a) {
        v_[0] = Sqr(T(0.726) * beta_m + T(0.812) * Sqr(beta_m) + T(3.7) * std::pow(beta_m, T(20)));
        v_[1] = T(0.25) * v_[0];
        v_[2] = T(4) * v_[0];
        for (int p = 3; p <= kPMax; ++p) v_[p] = v_[2];
        s_ = std::sqrt(kPi<T> / T(8)) *
             (T(0.265) * beta_n + T(1.194) * Sqr(beta_n) + T(5.372) * std::pow(beta_n, T(22)));
        sin2k_[0] = std::sin(alpha);
        cos2k_[0] = SafeSqrt(T(1) - Sqr(sin2k_[0]));
        for (int i = 1; i < 3; ++i) {
            sin2k_[i] = T(2) * cos2k_[i - 1] * sin2k_[i - 1];
            cos2k_[i] = Sqr(cos2k_[i - 1]) - Sqr(sin2k_[i - 1]);
        }
    }

    // The un-divided sum Σ_p M_p A_p N_p (= hairscatter's eval): pbrt's fsum.
    V fsum(const V& wo, const V& wi) const {
        const T sin_o = wo.x, cos_o = SafeSqrt(T(1) - Sqr(sin_o));
        const T phi_o = std::atan2(wo.z, wo.y);
        const T gamma_o = SafeASin(h_);
        const T sin_i = wi.x, cos_i = SafeSqrt(T(1) - Sqr(sin_i));
        const T phi_i = std::atan2(wi.z, wi.y);

        const T sin_t = sin_o / eta_, cos_t = SafeSqrt(T(1) - Sqr(sin_t));
        const T etap = SafeSqrt(Sqr(eta_) - Sqr(sin_o)) / cos_o;
        const T sin_gt = h_ / etap, cos_gt = SafeSqrt(T(1) - Sqr(sin_gt));
        const T gamma_t = SafeASin(sin_gt);
        const V tr = glm::exp(-sigma_a_ * (T(2) * cos_gt / cos_t));
        const Ap<T> ap = ComputeAp(cos_o, eta_, h_, tr);

        const T phi = phi_i - phi_o;
        V sum(T(0));
        for (int p = 0; p < kPMax; ++p) {
            T sop, cop;
            tilt(p, sin_o, cos_o, sop, cop);
            sum += Mp<T, kAccurate>(cos_i, cop, sin_i, sop, v_[p]) * ap.a[p] *
                   Np(phi, p, s_, gamma_o, gamma_t);
        }
        sum += Mp<T, kAccurate>(cos_i, cos_o, sin_i, sin_o, v_[kPMax]) * ap.a[kPMax] * kInv2Pi<T>;
        return sum;
    }

    // pbrt's f: fsum / |cosθ| of wi in the shading frame, here |wi.z|.
    V f(const V& wo, const V& wi) const {
        V sum = fsum(wo, wi);
        const T c = std::abs(wi.z);
        if (c > T(0)) sum /= c;
        return sum;
    }

    T PDF(const V& wo, const V& wi) const {
        const T sin_o = wo.x, cos_o = SafeSqrt(T(1) - Sqr(sin_o));
        const T phi_o = std::atan2(wo.z, wo.y);
        const T gamma_o = SafeASin(h_);
        const T sin_i = wi.x, cos_i = SafeSqrt(T(1) - Sqr(sin_i));
        const T phi_i = std::atan2(wi.z, wi.y);
        const T etap = SafeSqrt(Sqr(eta_) - Sqr(sin_o)) / cos_o;
        const T sin_gt = h_ / etap;
        const T gamma_t = SafeASin(sin_gt);
        T ap_pdf[kPMax + 1];
        ApPDF(cos_o, ap_pdf);
        const T phi = phi_i - phi_o;
        T pdf = T(0);
        for (int p = 0; p < kPMax; ++p) {
            T sop, cop;
            tilt(p, sin_o, cos_o, sop, cop);
            pdf += Mp<T, kAccurate>(cos_i, cop, sin_i, sop, v_[p]) * ap_pdf[p] *
                   Np(phi, p, s_, gamma_o, gamma_t);
        }
        pdf += Mp<T, kAccurate>(cos_i, cos_o, sin_i, sin_o, v_[kPMax]) * ap_pdf[kPMax] * kInv2Pi<T>;
        return pdf;
    }

    // u.x picks the lobe, (u.y, u.z) sample θi, u.w samples φ.
    Sample<T> Sample_f(const V& wo, const glm::vec<4, T>& u) const {
        const T sin_o = wo.x, cos_o = SafeSqrt(T(1) - Sqr(sin_o));
        const T phi_o = std::atan2(wo.z, wo.y);
        const T gamma_o = SafeASin(h_);
        T ap_pdf[kPMax + 1];
        ApPDF(cos_o, ap_pdf);
        int p = 0;
        T uc = u.x;
        for (p = 0; p < kPMax; ++p) {
            if (uc < ap_pdf[p]) break;
            uc -= ap_pdf[p];
        }
        T sop, cop;
        tilt(p, sin_o, cos_o, sop, cop);

        const T cos_theta =
            T(1) + v_[p] * std::log(std::max(u.y, T(1e-5)) + (T(1) - u.y) * std::exp(T(-2) / v_[p]));
        const T sin_theta = SafeSqrt(T(1) - Sqr(cos_theta));
        const T cos_phi = std::cos(T(2) * kPi<T> * u.z);
        const T sin_i = -cos_theta * sop + sin_theta * cos_phi * cop;
        const T cos_i = SafeSqrt(T(1) - Sqr(sin_i));

        const T etap = SafeSqrt(Sqr(eta_) - Sqr(sin_o)) / cos_o;
        const T sin_gt = h_ / etap;
        const T gamma_t = SafeASin(sin_gt);
        T dphi;
        if (p < kPMax)
            dphi = Phi(p, gamma_o, gamma_t) + SampleTrimmedLogistic(u.w, s_, -kPi<T>, kPi<T>);
        else
            dphi = T(2) * kPi<T> * u.w;
        const T phi_i = phi_o + dphi;

        Sample<T> r;
        r.wi = V(sin_i, cos_i * std::cos(phi_i), cos_i * std::sin(phi_i));
        const T phi = phi_i - phi_o;
        T pdf = T(0);
        for (int q = 0; q < kPMax; ++q) {
            T sq, cq;
            tilt(q, sin_o, cos_o, sq, cq);
            pdf += Mp<T, kAccurate>(cos_i, cq, sin_i, sq, v_[q]) * ap_pdf[q] *
                   Np(phi, q, s_, gamma_o, gamma_t);
        }
        pdf += Mp<T, kAccurate>(cos_i, cos_o, sin_i, sin_o, v_[kPMax]) * ap_pdf[kPMax] * kInv2Pi<T>;
        r.pdf = pdf;
        r.f = f(wo, r.wi);
        return r;
    }

  private:
    // θo rotated by the cuticle tilt, pbrt-v4's convention: -2α (R), +α (TT), +4α (TRT).
    void tilt(int p, T sin_o, T cos_o, T& s, T& c) const {
        if (p == 0) {
            s = sin_o * cos2k_[1] - cos_o * sin2k_[1];
            c = cos_o * cos2k_[1] + sin_o * sin2k_[1];
        } else if (p == 1) {
            s = sin_o * cos2k_[0] + cos_o * sin2k_[0];
            c = cos_o * cos2k_[0] - sin_o * sin2k_[0];
        } else if (p == 2) {
            s = sin_o * cos2k_[2] + cos_o * sin2k_[2];
            c = cos_o * cos2k_[2] - sin_o * sin2k_[2];
        } else {
            s = sin_o;
            c = cos_o;
        }
        c = std::abs(c);
    }

    // Lobe selection probabilities: channel-mean A_p, normalised; recomputes T and A_p.
    void ApPDF(T cos_o, T (&out)[kPMax + 1]) const {
        const T sin_o = SafeSqrt(T(1) - Sqr(cos_o));
        const T sin_t = sin_o / eta_, cos_t = SafeSqrt(T(1) - Sqr(sin_t));
        const T etap = SafeSqrt(Sqr(eta_) - Sqr(sin_o)) / cos_o;
        const T sin_gt = h_ / etap, cos_gt = SafeSqrt(T(1) - Sqr(sin_gt));
        const V tr = glm::exp(-sigma_a_ * (T(2) * cos_gt / cos_t));
        const Ap<T> ap = ComputeAp(cos_o, eta_, h_, tr);
        T sum = T(0);
        for (int p = 0; p <= kPMax; ++p) {
            out[p] = (ap.a[p].x + ap.a[p].y + ap.a[p].z) / T(3);
            sum += out[p];
        }
        for (int p = 0; p <= kPMax; ++p) out[p] /= sum;
    }

    T h_, eta_;
    V sigma_a_;
    T v_[kPMax + 1];
    T s_;
    T sin2k_[3], cos2k_[3];
};

}  // namespace bench_ref
