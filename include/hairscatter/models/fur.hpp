// hairscatter — fur: a fibre whose cortex surrounds a scattering medulla, after Yan, Tseng,
// Jensen & Ramamoorthi 2015 ("Physically-accurate fur reflectance: modeling, measurement
// and rendering", ACM TOG 34(6)) and Yan, Jensen & Ramamoorthi 2017 ("An efficient and
// practical near and far field fur reflectance model", ACM TOG 36(4)).
//
// The fibre is a double cylinder: a dielectric cortex of radius 1 (index η, absorption σa^c
// per unit radius) around a concentric, index-matched medulla of radius κ that scatters
// (σs^m, Henyey–Greenstein g) and absorbs (σa^m). Light that crosses the medulla without
// scattering forms Chiang et al. 2016's lobes R, TT, TRT and the residual, each chord now
// attenuated by the cortex and the medulla in turn (Yan et al. 2015 §4); light that
// scatters there leaves as one broad lobe, whose energy follows from the same extinction
// integrals and whose azimuthal shape is tabulated per material by a small simulation of
// the double cylinder (docs/models.md, "Fur with a medulla").
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../fiber/frame.hpp"
#include "../fiber/params.hpp"
#include "../io/table_file.hpp"
#include "../lobes/attenuation.hpp"
#include "../lobes/azimuthal.hpp"
#include "../lobes/deon_lobes.hpp"
#include "../lobes/lobe_controls.hpp"
#include "../lobes/microfacet.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "../math/splitmix.hpp"
#include "contract.hpp"

namespace hairscatter {

// The fur fibre's parameters: the cortex as a hair fibre's, and the medulla.
template <typename T> struct FurParams {
    FiberParams<T> cortex;                  // η, β_m, β_n, α and the cortex's σa^c (per unit radius)
    T kappa = T(0);                         // medulla radius over the fibre's, [0, 1)
    T sigma_s = T(0);                       // σs^m per unit fibre radius, ≥ 0
    glm::vec<3, T> sigma_a_medulla{T(0)};   // σa^m per unit fibre radius, RGB, ≥ 0
    T g = T(0);                             // Henyey–Greenstein anisotropy of the medulla, (-1, 1)
    // Whether the cortex's boundary is rough for the light inside (RoughCortexTables): the
    // orders of exit follow a walk over microfacets, total internal reflection at tilted
    // facets included, instead of the smooth F at every internal event. Off, the unscattered
    // lobes are Chiang's exactly.
    bool rough_cortex = false;
    // The rough cortex's microsurface: GGX (Trowbridge–Reitz) of this roughness about the
    // cuticle-tilted normal, in [0, 1]; 0 (the default): the GGX roughness whose reflections
    // spread R as β_m does (facet_alpha_from_beta, 0.182 at β_m 0.3). Read only with
    // rough_cortex.
    T facet_alpha = T(0);
};

// Every field checked (the cortex by validate(FiberParams)); an empty string when valid,
// else one message per bad field naming it, its value and its range. Never throws.
template <typename T> std::string validate(const FurParams<T>& p) {
    using detail::in_range;
    const T inf = std::numeric_limits<T>::max();
    detail::Complaints bad;
    const std::string cortex = validate(p.cortex);
    if (!cortex.empty()) bad.add_text(cortex);
    if (!(in_range(p.kappa, T(0), T(1)) && p.kappa < T(1))) bad.add("kappa", double(p.kappa), "[0, 1)");
    if (!in_range(p.sigma_s, T(0), inf)) bad.add("sigma_s", double(p.sigma_s), "[0, inf) (finite)");
    const char* channel[3] = {"sigma_a_medulla.r", "sigma_a_medulla.g", "sigma_a_medulla.b"};
    for (int c = 0; c < 3; ++c)
        if (!in_range(p.sigma_a_medulla[c], T(0), inf))
            bad.add(channel[c], double(p.sigma_a_medulla[c]), "[0, inf) (finite)");
    if (!(in_range(p.g, T(-1), T(1)) && p.g > T(-1) && p.g < T(1))) bad.add("g", double(p.g), "(-1, 1)");
    if (!in_range(p.facet_alpha, T(0), T(1))) bad.add("facet_alpha", double(p.facet_alpha), "[0, 1]");
    return bad.str();
}

template <typename T> void require_valid(const FurParams<T>& p) { detail::throw_if_invalid(validate(p), "fur parameters"); }

template <typename T> const FurParams<T>& validated(const FurParams<T>& p) {
    require_valid(p);
    return p;
}

// The fur fibre's lobe controls (docs/controls.md): LobeControls' gains, tints and tilts on
// R, TT, TRT and the residual, and a gain and tint of its own for S, the light scattered in
// the medulla. Like LobeControls, they scale each lobe's energy, so f, the lobe selection
// weights, the albedo and lobe_split all follow. The defaults change nothing.
template <typename T> struct FurControls {
    LobeControls<T> lobes;
    T gain_s = T(1);                          // [0, kMaxLobeGain]
    glm::vec<3, T> tint_s{T(1)};              // channels in [0, kMaxLobeGain]

    HAIRSCATTER_HD glm::vec<3, T> weight_s() const { return gain_s * tint_s; }
};

// Empty when valid, else one message per bad field naming it (the four lobes' names as
// validate(LobeControls)). Never throws.
template <typename T> std::string validate(const FurControls<T>& c) {
    using detail::in_range;
    detail::Complaints bad;
    const std::string lobes = validate(c.lobes);
    if (!lobes.empty()) bad.add_text(lobes);
    if (!in_range(c.gain_s, T(0), kMaxLobeGain<T>)) bad.add("gain_s", double(c.gain_s), "[0, 1e6]");
    const char* channel[3] = {"tint_s.r", "tint_s.g", "tint_s.b"};
    for (int ch = 0; ch < 3; ++ch)
        if (!in_range(c.tint_s[ch], T(0), kMaxLobeGain<T>)) bad.add(channel[ch], double(c.tint_s[ch]), "[0, 1e6]");
    return bad.str();
}

template <typename T> void require_valid(const FurControls<T>& c) { detail::throw_if_invalid(validate(c), "fur lobe controls"); }

template <typename T> const FurControls<T>& validated(const FurControls<T>& c) {
    require_valid(c);
    return c;
}

// The medulla-scattered lobe's tables: per bin of |θo|, the azimuthal density of the
// scattered light's exit over |φ| (relative azimuth, symmetric), its longitudinal density
// over sin θi (two numbers, below) and the fraction of the light scattered in the medulla
// that leaves the fibre, per channel (the rest is absorbed on its way out). Trivially
// copyable.
//
// The longitudinal density per unit sin θi, with x = sin θi · sign(sin θo):
//   q(x) = (1 + b x) · (w U(|x|) + (1 − w) C(|x|)) / 2,
// a mix of the exit of light that leaves after one isotropic scattering and of light
// diffused by a dense medulla, skewed by b toward −sin θo (forward scattering, g > 0, keeps
// the light's inclination). U: scattered once near the axis, the light leaves uniformly over
// the sphere (uniform in sin θi) along the radius, so it meets the boundary at its own
// inclination, and the boundary passes 1 − F(cos θi) of it (Fresnel at the exit, the same
// both ways): U ∝ 1 − F(√(1 − x²)), which vanishes toward grazing exits (sin θi → ±1, where
// the light inside is past the critical angle along the axis). C: the far field of a
// cylinder diffusely lit from inside, the cos θi law of a Lambertian exit, ∝ √(1 − x²),
// each surface point's exit weighted by its transmission at its own incidence, cos θi cos φn
// for a point whose normal is φn round the section: C ∝ √(1 − x²) ∫ (1 − F(√(1 − x²) cos φn))
// cos φn dφn. Both depend on η alone, tabulated over |x| (exit_density, piecewise constant,
// with their cdfs; exact to sample). w ∈ [0, 1] and b ∈ [−1, 1] match the simulated exits'
// E[x²] and E[x]. (Before, U uniform and C the semicircle: S's grazing sixteenth of sin θi
// held 40–65 % more light than the physical fur's; with the transmission still ~50 % at κ 0.6,
// σs^m 1, 30° — fur_breakdown_tool --marginals — but S's error against the reference's
// scattered light fell in 34 of its 46 entries, rose by 0.1 point in 4: FurPhysical,
// bench/results/fur_tt_tail_2026-12-08.txt.)
template <typename T> struct MedullaTables {
    static constexpr int kThetaBins = 6;   // |θo| in [0, π/2), equal widths
    static constexpr int kPhiBins = 32;    // |φ| in [0, π], equal widths
    static constexpr int kExitBins = 64;   // |sin θi| in [0, 1], equal widths (U and C)
    T density[kThetaBins][kPhiBins];       // q(|φ|), ∫_0^π q = 1 (N_s(φ) = q(|φ|) / 2)
    T cdf[kThetaBins][kPhiBins + 1];       // its integral at the bins' edges (0 … 1)
    T escape[kThetaBins][3];               // a_esc per channel, in [0, 1]
    T longitudinal[kThetaBins][2];         // w ∈ [0, 1] and b ∈ [−1, 1] of q(x)
    // U and C over |x| (∫_0^1 = 1) and their integrals at the bins' edges: from η alone
    // (detail::fill_exit_shapes; not in the file, rebuilt on load).
    T exit_density[2][kExitBins];
    T exit_cdf[2][kExitBins + 1];
    // Per bin of |θo|, (w U + (1 − w) C)/2 over |x|: q's symmetric part, one read per query
    // (detail::fill_exit_mix, after w is set or loaded).
    T exit_mix[kThetaBins][kExitBins];

    // q(x) for the bin t and the sign of sin θo, per unit sin θi (x = sin θi here).
    HAIRSCATTER_HD T longitudinal_pdf(int t, T sin_o, T sin_i, T cos_i) const {
        (void)cos_i;
        const T b = sin_o < T(0) ? -longitudinal[t][1] : longitudinal[t][1];
        return (T(1) + b * sin_i) * exit_mix[t][exit_bin(abs_value(sin_i))];
    }
    // sin θi drawn from q: the component by u1 (U with probability w), |x| by inverting its
    // cdf at u2, then the sign + with probability (1 + b|x|)/2 by u3 — q(x) = (1 + bx) ·
    // symmetric(x) exactly.
    HAIRSCATTER_HD T sample_longitudinal(int t, T sin_o, T u1, T u2, T u3) const {
        const T w = longitudinal[t][0], b = sin_o < T(0) ? -longitudinal[t][1] : longitudinal[t][1];
        const int c = u1 < w ? 0 : 1;
        T a = invert_cdf(exit_cdf[c], exit_density[c], kExitBins, clamp(u2, T(0), T(1))) / T(kExitBins);
        a = clamp(a, T(0), T(1));
        return u3 < T(0.5) * (T(1) + b * a) ? a : -a;
    }

    HAIRSCATTER_HD static int theta_bin(T abs_sin_o) {
        const T theta = elem::asin(clamp(abs_sin_o, T(0), T(1)));
        const int k = int(theta * (T(2) * kInvPi<T>) * T(kThetaBins));
        return k < 0 ? 0 : (k < kThetaBins ? k : kThetaBins - 1);
    }
    // N_s(φ), per radian over φ ∈ [-π, π].
    HAIRSCATTER_HD T azimuthal_pdf(int t, T phi) const {
        const int k = phi_bin(abs_value(phi));
        return T(0.5) * density[t][k];
    }
    // φ from u ∈ [0, 1]: the sign from which half u falls in, |φ| by inverting the cdf.
    HAIRSCATTER_HD T sample_azimuth(int t, T u) const {
        const T sign = u < T(0.5) ? T(-1) : T(1);
        const T v = clamp(abs_value(T(2) * u - T(1)), T(0), T(1));
        const T width = kPi<T> / T(kPhiBins);
        return sign * invert_cdf(cdf[t], density[t], kPhiBins, v) * width;
    }
    // A piecewise-constant density's inverse cdf at v ∈ [0, 1], in bins: the bin lo with
    // cdf[lo] ≤ v < cdf[lo + 1] (bisection; never an empty bin) plus v's fraction of its mass.
    HAIRSCATTER_HD static T invert_cdf(const T* cdf, const T* density, int bins, T v) {
        int lo = 0, hi = bins;
        while (hi - lo > 1) {
            const int mid = (lo + hi) / 2;
            if (cdf[mid] <= v) lo = mid;
            else hi = mid;
        }
        while (lo > 0 && !(density[lo] > T(0))) --lo;
        const T mass = cdf[lo + 1] - cdf[lo];
        const T frac = mass > T(0) ? clamp((v - cdf[lo]) / mass, T(0), T(1)) : T(0.5);
        return T(lo) + frac;
    }
    // The mass of N_s in the arc |φ - centre| < π/2.
    HAIRSCATTER_HD T arc_mass(int t, T centre) const {
        const T a = wrap_pi(centre - kHalfPi<T>);
        const T b = a + kPi<T>;  // may pass π: the rest wraps to -π
        return b <= kPi<T> ? signed_cdf(t, b) - signed_cdf(t, a)
                           : (T(1) - signed_cdf(t, a)) + signed_cdf(t, b - kTwoPi<T>);
    }

  private:
    HAIRSCATTER_HD static int exit_bin(T abs_x) {
        const int k = int(abs_x * T(kExitBins));
        return k < 0 ? 0 : (k < kExitBins ? k : kExitBins - 1);
    }
    HAIRSCATTER_HD static int phi_bin(T abs_phi) {
        const int k = int(abs_phi * kInvPi<T> * T(kPhiBins));
        return k < 0 ? 0 : (k < kPhiBins ? k : kPhiBins - 1);
    }
    // ∫_{-π}^{φ} N_s.
    HAIRSCATTER_HD T signed_cdf(int t, T phi) const {
        const T x = clamp(abs_value(phi), T(0), kPi<T>);
        const int k = phi_bin(x);
        const T one_sided = cdf[t][k] + (x - T(k) * kPi<T> / T(kPhiBins)) * density[t][k];
        return phi < T(0) ? T(0.5) * (T(1) - one_sided) : T(0.5) * (T(1) + one_sided);
    }
};

namespace detail {

// The per-chord terms of the unscattered light at offset h (Yan et al. 2015 §4): the refracted
// ray crosses the section along a chord of in-plane half length cosγt, of which the medulla
// (radius κ) takes √(κ² − sin²γt); the 3D lengths are these over cosθt. Per channel c:
//   T_c      = exp(−σa^c (ℓ − ℓ_m) − σt^m_c ℓ_m)   (one chord through cortex and medulla)
//   first_c  = exp(−σa^c (ℓ − ℓ_m)/2) · σs/σt_c · (1 − exp(−σt_c ℓ_m))
// (first_c: the light of one pass that scatters in the medulla; the cortex's first half is
// crossed before it). σs (1 − e^(−σt ℓ))/σt is written σs ℓ · (−expm1(−x)/x), finite at σt = 0.
// cortex_scale multiplies the cortex's length ℓ − ℓ_m (the rough cortex's entry lengthens the
// path through it: RoughCortexTables' k; 1 for the smooth cylinder).
template <typename T> struct MedullaChord {
    T transmittance[3];
    T first_scatter[3];
};

template <typename T>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE MedullaChord<T> medulla_chord(const FurParams<T>& p, T sin_gamma_t, T chord, T chord_scale,
                                                                     T cortex_scale = T(1)) {
    using std::sqrt;
    const T inside = sqr(p.kappa) - sqr(sin_gamma_t);  // < 0: the chord misses the medulla
    const T half_m = inside > T(0) ? sqrt(inside) : T(0);
    const T lm = half_m * chord_scale;  // ℓ_m, 3D
    const T lc = (chord > lm ? chord - lm : T(0)) * cortex_scale;
    // The cortex's half chord exp(−σa^c (ℓ − ℓ_m)/2) and the medulla's expm1(−σt ℓ_m), each
    // one batch (in float one vector: math/elementary.hpp); T is the half chord squared
    // times e^(−σt ℓ_m), first_c the half chord times σs ℓ_m (1 − e^(−x))/x.
    T half[4], m1[4], x[3];
    for (int c = 0; c < 3; ++c) {
        x[c] = (p.sigma_s + p.sigma_a_medulla[c]) * lm;
        half[c] = T(-0.5) * p.cortex.sigma_a[c] * lc;
        m1[c] = -x[c];
    }
    half[3] = m1[3] = T(0);  // (padding)
    elem::exp_each_nonpositive(half);
    elem::expm1_each(m1);
    MedullaChord<T> r;
    for (int c = 0; c < 3; ++c) {
        r.transmittance[c] = half[c] * half[c] * (T(1) + m1[c]);
        const T frac = x[c] > T(1e-6) ? -m1[c] / x[c] : T(1) - T(0.5) * x[c];  // (1 − e^(−x))/x
        r.first_scatter[c] = half[c] * p.sigma_s * lm * frac;
    }
    return r;
}

// How a rough cortex shares the light that enters it among the orders of exit. Inside a
// smooth circular cylinder every chord meets the boundary at the angle it entered by, below
// the critical angle: total internal reflection never happens, and Chiang's A_p reflect
// with the one smooth F at every internal event. A rough boundary's microfacets tilt that
// angle at every event, and a reflection from a tilted facet turns the chord by twice the
// tilt: the internal direction random-walks, and light that wanders past the critical
// angle stays trapped for many events. In a circle the state of that walk is the internal
// direction alone (its angle to the local normal is the same at both ends of a chord, and
// its component along the tangent is conserved, the angular momentum about the axis), so it
// is simulated per material on directions only: light from wo meets the boundary at offset
// h, then the boundary once per chord. Each meeting is Heitz et al. 2016's random walk on
// the microsurface (RoughFacets::walk): visible facets (Heitz 2014, "Understanding the
// masking-shadowing function", eq. 2) reflect or refract with their Fresnel factor, and
// light that a facet sends back into the microsurface (Smith's masking) meets another
// facet, until it leaves it outside or inside. The facets are GGX, centred on the cuticle
// tilt α, of the roughness FurParams::facet_alpha where the cortex's microsurface is known,
// else of the one whose reflections give R the longitudinal spread the model's own β_m
// gives it (facet_alpha_from_beta: a reflection doubles the tilt of the normal that makes
// it). Nothing is fitted to a reference. Per node (θo, γ) the table keeps, of the light that entered, the
// shares that leave at the first internal meeting (TT), the second (TRT) and later, and the
// ratio r of the later orders' geometric tail (r / (1 − r) is their mean number of chords
// past the third); and the entry's own reflectance F_r, the rough boundary's R: the light
// the entry's walk leaves outside, its first facet's reflection counted by its expectation
// F(wo·m) C1(h)^Λ(o_m) (the chance that it rises out of the microsurface from the height h
// it met the facet at, Smith's G1 there). The table holds F_r over the smooth F at the node,
// which the fibre multiplies by its exact smooth F at h: F rises steeply toward h = 1, and a
// bilinear F_r between nodes 1/8 apart in h overstated it there by a quarter at θo 0° (0.082
// against 0.068). Toward grazing wo the facets it sees lean toward it, and F_r falls below
// the smooth F. The fibre attenuates TT's and TRT's chords as its first one at h. The light
// that stays inside longer has chords the facets have turned: a chord at γ' to the normal in
// the section is 2 cos γ' long there and crosses the medulla where |sin γ'| < κ, and since
// the tangential part is nearly kept from chord to chord, light whose chords miss the
// medulla tends to keep missing it. So the walk carries each path's light per channel
// through every chord of its own (the transmittance and first scattering of medulla_chord),
// and the table keeps, of the entered light, the later orders' light that leaves
// unscattered, L_c, and that first scatters in the medulla on the way, S_c (the material's
// σ's enter the walk; lossless, L_c + S_c is the later orders' share).
// The same reflections give R's shape at the node: the d'Eon lobe (variance v_R, centre θc)
// whose quartiles of sin θi are theirs (deon_lobe_from_quartiles), kept as v_R and
// δ_R = θo − 2α + θc, the turn from the smooth tilt's conditioning angle θo − 2α to −θc. A
// facet of longitudinal slope a turns sin θi by 2a cos θo cos γ to first order (γ the
// incidence angle in the section, sin γ = h): toward the rim, where F is largest, the
// facets' spread and tilt nearly stop acting on R (v_R ≈ v cos²γ at θo 0°), a narrowing
// Chiang's single v per lobe does not have. And R's azimuth: the facets wo sees lean toward
// it (visible normals, Heitz 2014 eq. 2), and Smith's masking keeps more of the reflections
// that rise steeply than of those that graze, so toward grazing incidence on the mean
// surface (the rim, and θo toward ±90°) the reflections turn from the smooth mirror's
// azimuth Φ(0, h) = −2γ toward wo's; the table keeps their weighted median turn ψ_R
// (a median, as R's quartiles: GGX's tail would throw a mean), and the fibre centres N_R on
// −2γ + sign(h) ψ_R. TT's azimuth likewise: the walk carries the light round the section
// chord by chord, and the exit's median turn from the smooth cylinder's Φ(1, h), ψ_TT, centres
// N_TT on Φ(1, h) + sign(h) ψ_TT: toward the rim the facets wo sees lean toward it, refract
// the light less far round, and the exits turn toward the forward direction. TRT's likewise
// (its two chords at γ'_1, γ'_2 carry the light by 2π − 2γ'_1 − 2γ'_2): its median turn
// ψ_TRT from Φ(2, h) centres N_TRT. And their spreads: Chiang's N_p is one trimmed logistic
// of β_n's scale for every lobe, a smooth cylinder's lobes blurred alike, where on the rough
// cortex the facets set each lobe's azimuthal spread at h. A facet tilted by δ across the
// fibre turns a refracted chord by δ (1 − cos θi / (η cos θt)), δ (1 − 1/η) at normal
// incidence, and a reflected one by 2δ, so TRT's internal reflection spreads it several
// times as wide as TT's two crossings do.
// The table keeps s_TT and s_TRT, the scale of the logistic with the mean absolute deviation
// of the exits' turns about their median (2 s ln 2 for a logistic), and the fibre evaluates and
// samples N_TT and N_TRT with them (R keeps β_n's: R's own width from the walk did not
// improve the comparison with the physical fur, docs/models.md). The nodes are
// uniform in γ = asin |h|, denser toward the rim, where F_r, v_R, ψ_R and ψ_TT change fastest.
// And the entry's facets lengthen the first chord's path to the medulla: at grazing light the
// facets wo sees refract the light across the section, so it crosses more cortex before the
// medulla (docs/fur_breakdown.md, last section). A chord at γ' to the normal in the section
// meets the concentric medulla where |sin γ'| < κ, after (cos γ' − √(κ² − sin²γ')) over its
// in-section share in 3D; the table keeps k, the mean of that over the walk's first chords
// that meet the medulla divided by the smooth chord's at the node's h (1 where the smooth
// chord misses it), and the fibre scales the cortex's part of every chord by k before its
// absorption (σa^c alone: lossless light is unchanged).
// And TRT's and the later orders' longitudinal lobes. Chiang et al. 2016 give both one
// d'Eon lobe of 4v (eq. 7 and §4.1), TRT's about θo + 4α and the residual's about θo, a
// smooth cylinder's. On the rough cortex TRT's one internal reflection leaves it narrower
// (fewer facet events spread it than the 4v assumes), and trapped light meets the tilted
// scales at every event, each reflection turning it by about 2α the same way along the
// fibre, so the later orders drift from −θo and spread wider. The table keeps, per θo node,
// the d'Eon lobe closest in L1 to the walk's TRT exits and to its later exits over sin θi
// (fit_deon_lobe_l1; pooled over the row's nodes, a beam uniform in h, the later exits
// weighted by their unscattered light), as v_TRT, v_res and the turns sin δ from the
// material's conditioning angles to −θc; the fibre conditions and samples those lobes.
template <typename T> struct RoughCortexTables {
    static constexpr int kTheta = 13, kH = 9;  // θo nodes over ±kThetaMax, |γ| nodes over [0, π/2]
    static constexpr double kThetaMax = 1.5;   // (beyond, the nearest node: cos θo → 0 there)
    // Per node: the shares of the entered light that leave after one chord (TT) and two (TRT),
    // F_r / F, the widths (R's v_R, s_TT, s_TRT and R's tail's v_t: R's M_p is the mixture
    // (1 − w) M(v_R) + w M(v_t), fit_deon_tail), R's δ_R and ψ_R, TT's ψ_TT, the entry's k,
    // v_TRT and v_res after v_t (TRT's and the residual's lobes; lanes of the widths' vector),
    // ψ_TRT, the tail's weight w, sin δ_TRT and sin δ_res (their turns), the later orders'
    // light (over the entered light) that leaves
    // unscattered, L_c (RGB), and that first scatters in the medulla, S_c (RGB): the fibre's
    // values, which at() interpolates (padded to whole vectors: GCC's -O2 vectorises only a
    // loop without a remainder); then, for the tests, the later orders' share, their tail's
    // ratio r and the one lobe of the reflections' quartiles' v (fit_deon_tail's start).
    enum Value : int {
        kTT, kTRT, kFr, kVR, kScaleTT, kScaleTRT, kTailR, kVTRT, kVRes, kDeltaR, kPsiR, kPsiTT, kEntryPath,
        kPsiTRT, kTailWeightR, kSinDeltaTRT, kSinDeltaRes, kLaterOut, kLaterScatter = kLaterOut + 3,
        kEvalEnd = kLaterScatter + 3,
        kEvalValues = (kEvalEnd + 7) / 8 * 8,  // (zeros past kEvalEnd)
        kLater = kEvalValues, kTailRatio, kQuartileVR, kValues
    };
    static_assert(kTailR == kVR + 3 && kVRes == kVR + 5 && kEvalValues >= kVR + 8,
                  "the widths v_R, s_TT, s_TRT, v_t, v_TRT and v_res are read as one vector of eight");
    T share[kTheta][kH][kValues];

    // The fibre's values at (θo, γ), h = sin γ, bilinear between the nodes.
    HAIRSCATTER_HD void at(T theta, T gamma, T (&out)[kEvalValues]) const {
        const T u = clamp((theta / T(kThetaMax) + T(1)) * T(0.5), T(0), T(1)) * T(kTheta - 1);
        const T v = clamp(abs_value(gamma) * T(2) * kInvPi<T>, T(0), T(1)) * T(kH - 1);
        const int i = u < T(kTheta - 1) ? int(u) : kTheta - 2, j = v < T(kH - 1) ? int(v) : kH - 2;
        const T s = u - T(i), t = v - T(j);
        // (into an array of its own, then copied: out might alias the table, which keeps the
        // loop from vectorising)
        const T *a = share[i][j], *b = share[i][j + 1], *c = share[i + 1][j], *d = share[i + 1][j + 1];
        T r[kEvalValues];
        for (int k = 0; k < kEvalValues; ++k) {
            const T lo = a[k] + t * (b[k] - a[k]);
            const T hi = c[k] + t * (d[k] - c[k]);
            r[k] = lo + s * (hi - lo);
        }
        for (int k = 0; k < kEvalValues; ++k) out[k] = r[k];
    }
};

// The table simulation's generator (math/splitmix.hpp): the tables are the same for the
// same parameters, run after run.
using FurRng = SplitMix64;

// The table simulation's budget: scattered paths per |θo| bin, medulla events per bin
// (what bounds the build time for dense medullas) and per path (beyond it a path is dropped),
// and the Fourier terms the azimuthal density is smoothed to.
inline constexpr int kFurPathsPerBin = 12000;
inline constexpr long long kFurEventsPerBin = 1500000;
inline constexpr int kFurEventsPerPath = 20000;
inline constexpr int kFurFourierTerms = 8;

// Unpolarised Fresnel reflectance at a smooth interface into relative index n (either side),
// 1 on total internal reflection.
inline double fur_fresnel(double cos_i, double n) {
    const double s2t = (1 - cos_i * cos_i) / (n * n);
    if (s2t >= 1) return 1;
    const double ct = std::sqrt(1 - s2t);
    return 0.5 * (sqr((cos_i - n * ct) / (cos_i + n * ct)) + sqr((n * cos_i - ct) / (n * cos_i + ct)));
}

// MedullaTables' U and C, the exits' longitudinal shapes, for index η (Fresnel at the exit:
// MedullaTables): per bin of |x| = |sin θi| each one's mean over 16 points, C's transmission
// over the section's normals by 32 midpoints in φn; each normalised to ∫_0^1 = 1, with its
// cdf. The same bits on build and load.
template <typename T> void fill_exit_shapes(MedullaTables<T>& tab, double eta) {
    constexpr int kB = MedullaTables<T>::kExitBins, kSub = 16, kNormals = 32;
    for (int c = 0; c < 2; ++c) {
        double mass[std::size_t(kB)], total = 0;
        for (int k = 0; k < kB; ++k) {
            double m = 0;
            for (int s = 0; s < kSub; ++s) {
                const double x = (k + (s + 0.5) / kSub) / kB, cos_i = std::sqrt(1 - x * x);
                if (c == 0) {
                    m += 1 - fur_fresnel(cos_i, eta);
                    continue;
                }
                double t = 0;
                for (int j = 0; j < kNormals; ++j) {
                    const double cn = std::cos(kHalfPi<double> * (j + 0.5) / kNormals);
                    t += (1 - fur_fresnel(cos_i * cn, eta)) * cn;
                }
                m += cos_i * t;
            }
            mass[k] = m;
            total += m;
        }
        double run = 0;
        tab.exit_cdf[c][0] = T(0);
        for (int k = 0; k < kB; ++k) {
            tab.exit_density[c][k] = T(mass[k] / total * kB);
            run += mass[k] / total;
            tab.exit_cdf[c][k + 1] = k + 1 < kB ? T(std::min(1.0, run)) : T(1);
        }
    }
}
// MedullaTables' exit_mix from U, C and each bin's w.
template <typename T> void fill_exit_mix(MedullaTables<T>& tab) {
    for (int t = 0; t < MedullaTables<T>::kThetaBins; ++t) {
        const T w = tab.longitudinal[t][0];
        for (int k = 0; k < MedullaTables<T>::kExitBins; ++k)
            tab.exit_mix[t][k] = T(0.5) * (w * tab.exit_density[0][k] + (T(1) - w) * tab.exit_density[1][k]);
    }
}
// E[x²] of U (c 0) or C (c 1), piecewise constant over |x|.
inline double exit_second_moment(const MedullaTables<double>& tab, int c) {
    constexpr int kB = MedullaTables<double>::kExitBins;
    double m = 0;
    for (int k = 0; k < kB; ++k) {
        const double a = double(k) / kB, b = double(k + 1) / kB;
        m += (tab.exit_cdf[c][k + 1] - tab.exit_cdf[c][k]) * (a * a + a * b + b * b) / 3;
    }
    return m;
}

// The far root of the in-plane line p + s d (d unit) with the circle of radius r, or -1.
inline double fur_circle_exit(const glm::dvec2& p, const glm::dvec2& d, double r) {
    const double b = glm::dot(p, d), c = glm::dot(p, p) - r * r, disc = b * b - c;
    return disc > 0 ? -b + std::sqrt(disc) : -1;
}

// A Henyey–Greenstein deflection of the unit direction d (Henyey & Greenstein 1941).
inline glm::dvec3 fur_scatter(const glm::dvec3& d, double g, double u1, double u2) {
    double c = 1 - 2 * u1;
    if (std::fabs(g) > 1e-4) {
        const double s = (1 - g * g) / (1 - g + 2 * g * u1);
        c = clamp((1 + g * g - s * s) / (2 * g), -1.0, 1.0);
    }
    const double sn = std::sqrt(std::max(0.0, 1 - c * c)), phi = 2 * kPi<double> * u2;
    const glm::dvec3 a = std::fabs(d.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 t = glm::normalize(glm::cross(a, d)), b = glm::cross(d, t);
    return glm::normalize(c * d + sn * (std::cos(phi) * t + std::sin(phi) * b));
}

// The d'Eon lobe whose quartiles of x = sin θi are x1 < x2 < x3. d'Eon et al. 2011's M_p of
// variance v is the θ-marginal of a von Mises–Fisher lobe of concentration 1/v about a
// direction c of inclination θc: a direction at cos t from c (t drawn by inverting its cdf,
// t = 1 + v ln(u + (1 − u) e^(−2/v)), the lobe's own sampling) and at a uniform angle ψ about
// it has x = t sin θc + √(1 − t²) cos θc cos ψ, so the cdf of x is the mean over u of
// 1 − acos(clamp((x − t sin θc) / (√(1 − t²) cos θc)))/π (midpoint rule, 32 points). The
// median fixes θc for a given v (bisection: the cdf at x2 falls as θc rises), then v is the
// one whose central half spans [x1, x3] (bisection in log v). Quartiles, not moments: the
// GGX facets' reflections have a heavy tail that moments would spread over the lobe's core.
struct DeonLobeFit {
    double v, theta_c;
};
inline double deon_lobe_cdf(double x, double v, double sin_c, double cos_c) {
    constexpr int kPoints = 32;
    const double floor = std::exp(-2 / v);  // (0 for narrow lobes: t = 1 + v ln u)
    double p = 0;
    for (int k = 0; k < kPoints; ++k) {
        const double u = (k + 0.5) / kPoints;
        const double t = clamp(1 + v * std::log(u + (1 - u) * floor), -1.0, 1.0);
        const double r = std::sqrt(std::max(0.0, 1 - t * t)) * cos_c, a = x - t * sin_c;
        p += r > 1e-12 ? 1 - std::acos(clamp(a / r, -1.0, 1.0)) * kInvPi<double> : (a >= 0 ? 1.0 : 0.0);
    }
    return p / kPoints;
}
inline DeonLobeFit deon_lobe_from_quartiles(double x1, double x2, double x3) {
    double lo = std::log(longitudinal_variance(1e-3)), hi = std::log(4.0), theta_c = 0;
    for (int i = 0; i < 24; ++i) {
        const double mid = 0.5 * (lo + hi), v = std::exp(mid);
        double a = -kHalfPi<double>, b = kHalfPi<double>;
        for (int j = 0; j < 24; ++j) {
            const double c = 0.5 * (a + b);
            (deon_lobe_cdf(x2, v, std::sin(c), std::cos(c)) > 0.5 ? a : b) = c;
        }
        theta_c = 0.5 * (a + b);
        const double sc = std::sin(theta_c), cc = std::cos(theta_c);
        (deon_lobe_cdf(x3, v, sc, cc) - deon_lobe_cdf(x1, v, sc, cc) > 0.5 ? lo : hi) = mid;
    }
    return {std::exp(0.5 * (lo + hi)), theta_c};
}

// The GGX roughness of the cortex's facets that the model's own β_m implies, when the
// microsurface is not given (FurParams::facet_alpha 0): the α whose facets' reflections
// spread R along the fibre as β_m does. R is the one lobe a single facet event forms, and
// β_m sets its longitudinal spread, d'Eon et al. 2011's M_p of variance v(β_m) (Chiang et
// al. 2016 eq. 7). Both are compared where the cylinder's shape does not enter, light
// along the normal (θo 0, h 0), and by quartiles, as R's lobe is fitted to the facets'
// reflections (deon_lobe_from_quartiles): GGX's slopes have no variance. R's lobe about
// the normal puts a quarter of its light beyond sin θi = x_q (deon_lobe_cdf); a facet of
// normal m, seen in proportion to ⟨wo·m⟩ D(m) (GGX's visible normals, Heitz 2014 eq. 2),
// reflects wo = n to r = 2 m_z m − n, whose sin θi is r·axis = 2 m_z m_x, weighted by its
// Fresnel factor F(m_z) and Smith's G1(r) (the walk's first facet event, RoughFacets), and α
// is the roughness for which a quarter of that weight lies beyond x_q (it rises with α:
// bisection). The visible normals are taken at 128 × 128 midpoints of Dupuy & Benyoub
// 2023's cap (lobes/microfacet.hpp). For narrow lobes a facet of slope a along the fibre
// alone turns the reflection by 2 atan a, and GGX's slope quartile α/√3 gives α ≈ 0.584 √v;
// the slope across the fibre and the visible normals' weight narrow R (sin θi = 2a / (1 + a²
// + b²) for slopes a along and b across), so α is 0.182 at β_m 0.3 (0.169 by slopes along
// the fibre alone), 0.46 at 0.5, and 1 from β_m ≈ 0.62 on, where R's lobe is wider than any
// GGX microsurface's reflections (the bisection's end). β_n does not enter: R's azimuthal spread is mostly the cylinder's.
inline double facet_alpha_from_beta(double beta_m, double eta) {
    const double v = longitudinal_variance(beta_m);
    double lo = 0, hi = 1;
    for (int i = 0; i < 50; ++i) {
        const double mid = 0.5 * (lo + hi);
        (deon_lobe_cdf(mid, v, 0, 1) < 0.75 ? lo : hi) = mid;
    }
    const double x_q = 0.5 * (lo + hi);
    constexpr int kN = 128;
    const auto beyond = [&](double alpha) {  // the share of the reflections' weight beyond x_q
        const Ggx<double> facets(alpha);
        double above = 0, total = 0;
        for (int i = 0; i < kN; ++i) {
            const double phi = kTwoPi<double> * (i + 0.5) / kN, c = std::cos(phi), s = std::sin(phi);
            for (int j = 0; j < kN; ++j) {
                const glm::dvec3 m = facets.sample_visible_local(glm::dvec3(0, 0, 1), c, s, (j + 0.5) / kN);
                const double rz = 2 * m.z * m.z - 1, w = fur_fresnel(m.z, eta) * facets.g1(rz);
                total += w;
                if (2 * m.z * m.x > x_q) above += w;
            }
        }
        return total > 0 ? above / total : 0.0;
    };
    lo = 1e-4, hi = 1;
    if (!(beyond(hi) > 0.25)) return hi;  // (R wider than GGX 1's reflections: the roughest facets)
    for (int i = 0; i < 24; ++i) {
        const double mid = 0.5 * (lo + hi);
        (beyond(mid) < 0.25 ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// The rough cortex's microfacets (RoughCortexTables): GGX (Trowbridge & Reitz 1975; Walter,
// Marschner, Li & Torrance 2007, "Microfacet models for refraction through rough surfaces",
// EGSR, who found it closer than Gaussian slopes to measured rough dielectrics) about the
// normal tilted by the cuticle angle α toward the tip, of roughness FurParams::facet_alpha,
// or where that is 0 the roughness the model's β_m implies (facet_alpha_from_beta).
// Directions in the frame (axis, normal, tangent).
struct RoughFacets {
    double mean_a = 0;  // μ = tan α: the tilted normal is ∝ (μ, 1, 0)
    double ggx = 0;     // GGX α
    static constexpr int kMaxEvents = 100;  // per boundary interaction (a walk this long is ~never seen)

    static RoughFacets of(double eta, double alpha, double beta_m, double facet_alpha) {
        return {std::tan(alpha), facet_alpha > 0 ? facet_alpha : facet_alpha_from_beta(beta_m, eta)};
    }
    // v's projection on the mean surface, c = v·(μ, 1, 0) (its sign: above or below).
    double mean_projection(const glm::dvec3& v) const { return v.x * mean_a + v.y; }

    // Smith's Λ (Smith 1967; Heitz 2014, "Understanding the masking-shadowing function"): the
    // facets' projected area toward v over the mean surface's, less 1; GGX's closed form
    // (lobes/microfacet.hpp) about the tilted normal. Below the mean surface it is
    // −1 − Λ(−v), the convention of Heitz et al. 2016's walk.
    double lambda(const glm::dvec3& v) const {
        const double c = to_tilted(v).z;
        const Ggx<double> facets(ggx);
        return c > 0 ? facets.lambda(c) : -1 - facets.lambda(-c);
    }
    // Smith's masking G1 = 1 / (1 + Λ) of a direction v above the mean surface; 0 below.
    double unmasked(const glm::dvec3& v) const { return mean_projection(v) > 0 ? 1 / (1 + lambda(v)) : 0.0; }

    // A facet seen from d, with density ∝ ⟨d·m⟩ D(m): the visible normals of Heitz 2014
    // (eq. 2), by Dupuy & Benyoub 2023's spherical cap ("Sampling visible GGX normals with
    // spherical caps"; lobes/microfacet.hpp), whose cap z ≥ −d.z (stretched) serves d below
    // the horizon too, as a ray the walk sends upward into the microsurface sees it.
    glm::dvec3 sample(const glm::dvec3& d, FurRng& rng) const {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        return from_tilted(Ggx<double>(ggx).sample_visible_local(to_tilted(d), u1, u2));
    }

    // Heitz, Hanika, d'Eon & Dachsbacher 2016 ("Multiple-scattering microfacet BSDFs with the
    // Smith model", ACM TOG 35(4)): light travelling along w meets the microsurface at random
    // heights (uniform on [−1, 1]; the result does not depend on it), each time on a visible
    // facet that reflects or refracts it with its Fresnel factor, until it leaves the
    // microsurface above (outside the fibre) or below (inside). Masked and shadowed light thus
    // scatters again instead of being lost or leaving through a facet's back. Below, the
    // microsurface is seen mirrored: heights and directions negated. The height starts beyond
    // the microsurface (a ray from afar).
    struct Exit {
        glm::dvec3 dir;
        bool outside;
        int events;  // facet events after the start
    };
    Exit walk(const glm::dvec3& w, bool outside, double eta, FurRng& rng) const {
        return walk_from(w, outside, outside ? 2.0 : -2.0, eta, rng);
    }
    // The walk picked up at height h (a ray that has just left a facet there).
    Exit walk_from(glm::dvec3 w, bool outside, double height, double eta, FurRng& rng) const {
        int k = 0;
        for (; k < kMaxEvents; ++k) {
            const double side = outside ? 1 : -1;
            const double next = next_height(side * w, side * height, rng.uniform());
            if (!(next < 2)) break;  // leaves the microsurface on its side
            height = side * next;
            const Event e = event(w, outside, eta, rng);
            w = e.dir;
            outside = e.outside;
        }
        return {w, outside, k};
    }
    // One facet event of the walk: the facet the ray meets (facing it), Fresnel by choice.
    struct Event {
        glm::dvec3 dir, normal;
        double fresnel;
        bool outside;
    };
    Event event(const glm::dvec3& w, bool outside, double eta, FurRng& rng) const {
        const double side = outside ? 1 : -1;
        const glm::dvec3 m = side * sample(-side * w, rng);  // faces the ray
        const double ci = -glm::dot(w, m), n = outside ? eta : 1 / eta;
        const double f = fur_fresnel(ci, n);
        if (rng.uniform() < f) return {w + 2 * ci * m, m, f, outside};
        const double ct = std::sqrt(std::max(0.0, 1 - (1 - ci * ci) / (n * n)));
        return {w / n + (ci / n - ct) * m, m, f, !outside};
    }
    // The height of the ray's next meeting with the microsurface from height h along w (the
    // ray's side up), or 3 when it leaves it: Heitz et al. 2016, Algorithm 2, with the
    // heights' C1(h) = (h + 1)/2. Rising, it leaves with probability C1(h)^Λ(w) (Smith's G1
    // at height h).
    double next_height(const glm::dvec3& w, double h, double u) const {
        const double c = mean_projection(w), c1 = clamp(0.5 * (h + 1), 0.0, 1.0);
        if (std::fabs(c) < 1e-9) return h;  // (along the mean surface: meets it at once)
        const double lam = lambda(w);
        if (c > 0) {
            if (!(lam > 1e-12)) return 3;         // (nothing above it to meet)
            if (1 - u < std::pow(c1, lam)) return 3;
        }
        return clamp(2 * c1 / std::pow(1 - u, 1 / lam) - 1, -1.0, 1.0);
    }

  private:
    // To and from the frame of the tilted normal n0 = (μ, 1, 0)/|·|: (along the axis, tangent, n0).
    glm::dvec3 to_tilted(const glm::dvec3& v) const {
        const double k = 1 / std::sqrt(1 + mean_a * mean_a);
        return {k * (v.x - mean_a * v.y), v.z, k * (mean_a * v.x + v.y)};
    }
    glm::dvec3 from_tilted(const glm::dvec3& l) const {
        const double k = 1 / std::sqrt(1 + mean_a * mean_a);
        return {k * (l.x + mean_a * l.z), k * (l.z - mean_a * l.x), l.y};
    }
};

// The weighted quartiles of x (pairs of value and weight; reordered here): per quartile the
// smallest x at which the running weight, in increasing x, reaches its share of the total.
// By selection (nth_element halving the range that holds it: linear time), as a sort and a
// scan would give it in n log n.
inline double weighted_quantile(std::vector<std::pair<double, double>>& xw, double share) {
    double need = 0;
    for (const auto& e : xw) need += e.second;
    need *= share;
    std::size_t lo = 0, hi = xw.size();
    if (hi == 0) return 0;
    double before = 0;  // the weight below xw[lo, hi)
    while (hi - lo > 1) {
        const std::size_t mid = lo + (hi - lo) / 2;
        const auto first = xw.begin() + std::ptrdiff_t(lo);
        std::nth_element(first, xw.begin() + std::ptrdiff_t(mid), xw.begin() + std::ptrdiff_t(hi));
        double left = 0;
        for (std::size_t k = lo; k < mid; ++k) left += xw[k].second;
        if (before + left >= need) hi = mid;
        else before += left, lo = mid;
    }
    return xw[lo].first;
}
inline std::array<double, 3> weighted_quartiles(std::vector<std::pair<double, double>>& xw) {
    return {weighted_quantile(xw, 0.25), weighted_quantile(xw, 0.5), weighted_quantile(xw, 0.75)};
}

// R's longitudinal shape as two d'Eon lobes about one centre θc, (1 − w) M(v_c) + w M(v_t):
// the pair closest in L1 to the reflections' histogram over sin θi (pairs of sin θi and
// weight; kBins bins on [−1, 1]), the L1 being what the comparison with the physical fibre
// measures. GGX's slope tail turns the reflections' sin θi by 2a cos θo cos γ (the visible
// normals favour steep facets at grazing incidence): a sharp core with a heavy tail, which one
// lobe fitted to the quartiles (deon_lobe_from_quartiles) makes too wide at its core and too
// light in its tail (docs/fur_breakdown.md). The core v_c is the best of kCores variances over
// [v / span, v · span] about the quartiles' v, the tail v_t one of kV over a log grid from v/4
// to 4 (v_t ≥ v_c), w in steps of 1/kW. Returns {v_t, w, v_c}; w = 0 where one lobe does best.
template <int kBins = 32, int kV = 24, int kW = 32, int kCores = 9>
inline std::array<double, 3> fit_deon_tail(const std::vector<std::pair<double, double>>& xw, double v, double theta_c,
                                           double span = 4) {
    static_assert(kBins <= 64 && kCores <= 16, "the masses' arrays");
    std::array<double, 3> best{v, 0.0, v};
    constexpr std::size_t nb = std::size_t(kBins), nc = std::size_t(kCores);  // array bounds
    double total = 0, hist[nb] = {};
    for (const auto& e : xw) {
        hist[std::min(kBins - 1, std::max(0, int((e.first + 1) * 0.5 * kBins)))] += e.second;
        total += e.second;
    }
    if (!(total > 0)) return best;
    for (double& b : hist) b /= total;
    const double sc = std::sin(theta_c), cc = std::cos(theta_c);
    const auto masses = [&](double vm, double (&m)[nb]) {
        double prev = 0;
        for (int b = 0; b < kBins; ++b) {
            const double next = b + 1 < kBins ? deon_lobe_cdf(-1 + 2.0 * (b + 1) / kBins, vm, sc, cc) : 1.0;
            m[b] = next - prev, prev = next;
        }
    };
    double core_v[nc], core[nc][nb], tail[nb];
    double best_l1 = HUGE_VAL;
    for (int c = 0; c < kCores; ++c) {
        core_v[c] = v * std::pow(span, 2.0 * c / (kCores - 1) - 1);
        masses(core_v[c], core[c]);
        double l1 = 0;
        for (int b = 0; b < kBins; ++b) l1 += std::fabs(hist[b] - core[c][b]);
        if (l1 < best_l1) best_l1 = l1, best = {core_v[c], 0.0, core_v[c]};
    }
    const double lo = std::log(v / 4), hi = std::log(4.0);
    for (int i = 0; i < kV; ++i) {
        const double vt = std::exp(lo + (hi - lo) * i / (kV - 1));
        masses(vt, tail);
        for (int c = 0; c < kCores; ++c) {
            if (vt < core_v[c]) continue;
            for (int k = 1; k <= kW; ++k) {
                const double w = double(k) / kW;
                double l1 = 0;
                for (int b = 0; b < kBins; ++b) l1 += std::fabs(hist[b] - (1 - w) * core[c][b] - w * tail[b]);
                if (l1 < best_l1) best_l1 = l1, best = {vt, w, core_v[c]};
            }
        }
    }
    return best;
}

// One d'Eon lobe (v, θc) closest in L1 to the histogram of xw over sin θi (kBins bins on
// [−1, 1]): from the quartiles' lobe, a 7 × 7 grid over log v (± ln 4) and θc (± 0.4),
// narrowed about the best three times.
template <int kBins = 32>
inline DeonLobeFit fit_deon_lobe_l1(std::vector<std::pair<double, double>>& xw) {
    constexpr std::size_t nb = std::size_t(kBins);
    double total = 0, hist[nb] = {};
    for (const auto& e : xw) {
        hist[std::min(kBins - 1, std::max(0, int((e.first + 1) * 0.5 * kBins)))] += e.second;
        total += e.second;
    }
    const std::array<double, 3> q = weighted_quartiles(xw);
    DeonLobeFit best = deon_lobe_from_quartiles(q[0], q[1], q[2]);
    if (!(total > 0)) return best;
    const auto l1 = [&](double v, double theta_c) {
        const double sc = std::sin(theta_c), cc = std::cos(theta_c);
        double prev = 0, sum = 0;
        for (int b = 0; b < kBins; ++b) {
            const double next = b + 1 < kBins ? deon_lobe_cdf(-1 + 2.0 * (b + 1) / kBins, v, sc, cc) : 1.0;
            sum += std::fabs(hist[b] / total - (next - prev)), prev = next;
        }
        return sum;
    };
    double best_l1 = l1(best.v, best.theta_c), span_v = std::log(4.0), span_c = 0.4;
    for (int level = 0; level < 4; ++level, span_v /= 3, span_c /= 3) {
        const DeonLobeFit at = best;
        for (int i = -3; i <= 3; ++i)
            for (int j = -3; j <= 3; ++j) {
                const double v = at.v * std::exp(span_v * i / 3), c = clamp(at.theta_c + span_c * j / 3, -1.5, 1.5);
                const double d = l1(v, c);
                if (d < best_l1) best_l1 = d, best = {v, c};
            }
    }
    return best;
}

// The rough cortex's walk (RoughCortexTables) for index η, cuticle tilt α and the facets' GGX
// α (0: the one β_m implies, facet_alpha_from_beta): 2,000 walks per node (each share
// within ~1 % at one standard deviation; R's shape, from quartiles, from the reflections of
// two entries per walk, the walk's own and one more), at most 400 chords per walk (the rest counts as
// later; a tail ratio of 0.95, the largest at β 0.3, leaves 1e-9 of it there).
template <typename T>
RoughCortexTables<T> build_rough_cortex(double eta, double alpha, double beta_m, double facet_alpha, double kappa = 0,
                                        glm::dvec3 sigma_a = glm::dvec3(0), double sigma_s = 0,
                                        glm::dvec3 sigma_a_medulla = glm::dvec3(0)) {
    constexpr int kWalks = 2000, kMaxEvents = 400, kShapeDraws = 2;
    const RoughFacets facets = RoughFacets::of(eta, alpha, beta_m, facet_alpha);
    std::vector<std::pair<double, double>> reflections, turns;  // R's sin θi, its turn toward wo; weights
    std::vector<std::pair<double, double>> tt_turns, trt_turns;  // TT's and TRT's exits: the turn from Φ(1, h), Φ(2, h)
    std::vector<std::pair<double, double>> trt_exits, later_exits;  // their sin θi over the row's nodes
    RoughCortexTables<T> tab{};
    FurRng rng(0x0C0A7E5Eull);
    constexpr int kTheta = RoughCortexTables<T>::kTheta, kH = RoughCortexTables<T>::kH;
    for (int i = 0; i < kTheta; ++i) {
        const double theta = (2.0 * i / (kTheta - 1) - 1) * RoughCortexTables<T>::kThetaMax;
        trt_exits.clear();
        later_exits.clear();
        for (int j = 0; j < kH; ++j) {
            const double h = std::min(std::sin(kHalfPi<double> * j / (kH - 1)), 0.999);
            // Toward the light (wo) in the entry point's frame: the normal at offset h is
            // (cos γ, sin γ) in the section, sin γ = h, with wo's section part along (1, 0).
            const glm::dvec3 out(std::sin(theta), std::cos(theta) * std::sqrt(1 - h * h), -std::cos(theta) * h);
            double entered = 0, first = 0, second = 0, later = 0, tail_events = 0, reflected = 0;
            double hits = 0, to_medulla = 0;  // the entered light's first chords that meet the medulla, their 3D paths to it
            glm::dvec3 late_t(0), late_s(0);  // the later orders' light: unscattered at exit, first scattered in the medulla
            reflections.clear();
            turns.clear();
            tt_turns.clear();
            trt_turns.clear();
            // A reflection's azimuth in the section, turned from the mirror's (+γ) toward wo's (−γ).
            const double gamma = std::asin(h);
            const auto turn = [&](const glm::dvec3& r) { return wrap_pi(gamma - std::atan2(r.z, r.y)); };
            // TT's: a chord whose in-plane direction meets the normal at γ' (signed by the
            // tangential part) carries the light round the section by π − 2γ', and the exit
            // leaves at atan2(z, y) from the normal there, so from wo's azimuth (γ from the
            // entry's normal) the exit's is π − 2γ'_1 + atan2(z, y) + γ; the smooth cylinder's
            // is π + 2γ − 2γt (γ'_1 = γt, Bravais: sin γt = h/η'). The turn is the difference.
            const double gamma_t = std::asin(h * std::cos(theta) / std::sqrt(eta * eta - sqr(std::sin(theta))));
            for (int w = 0; w < kWalks; ++w) {
                // The entry is the walk of Heitz et al. 2016 from afar (RoughFacets::walk). Its
                // first facet's reflections that leave at once are counted by their expectation,
                // F times the chance C1(h)^Λ(r) that r rises out of the height h it was met at
                // (no coin's noise); every other way out above (a reflection masked and sent
                // out by a later facet, or light that refracted in and out again) by the walk.
                const double h1 = facets.next_height(-out, 2, rng.uniform());
                const RoughFacets::Event e = facets.event(-out, true, eta, rng);
                const glm::dvec3 r = 2 * glm::dot(out, e.normal) * e.normal - out;  // the first facet's reflection
                const double rises = facets.mean_projection(r) > 0 ? std::pow(clamp(0.5 * (h1 + 1), 0.0, 1.0), facets.lambda(r)) : 0;
                const double kept = e.fresnel * rises;
                reflected += kept;
                reflections.emplace_back(r.x, kept / kShapeDraws);
                turns.emplace_back(turn(r), kept / kShapeDraws);
                for (int k = 1; k < kShapeDraws; ++k) {  // more entries' reflections, for R's shape alone
                    const double hk = facets.next_height(-out, 2, rng.uniform());
                    const RoughFacets::Event ek = facets.event(-out, true, eta, rng);
                    const glm::dvec3 rk = 2 * glm::dot(out, ek.normal) * ek.normal - out;
                    if (facets.mean_projection(rk) > 0) {
                        const double wk = ek.fresnel * std::pow(clamp(0.5 * (hk + 1), 0.0, 1.0), facets.lambda(rk)) / kShapeDraws;
                        reflections.emplace_back(rk.x, wk);
                        turns.emplace_back(turn(rk), wk);
                    }
                    const RoughFacets::Exit xk = facets.walk_from(ek.dir, ek.outside, hk, eta, rng);
                    if (xk.outside && !(ek.outside && xk.events == 0)) {
                        reflections.emplace_back(xk.dir.x, 1.0 / kShapeDraws);
                        turns.emplace_back(turn(xk.dir), 1.0 / kShapeDraws);
                    }
                }
                const RoughFacets::Exit entry = facets.walk_from(e.dir, e.outside, h1, eta, rng);
                if (entry.outside) {
                    if (e.outside && entry.events == 0) continue;  // the first facet's reflection: counted above
                    reflected += 1;
                    reflections.emplace_back(entry.dir.x, 1.0 / kShapeDraws);
                    turns.emplace_back(turn(entry.dir), 1.0 / kShapeDraws);
                    continue;
                }
                entered += 1;
                glm::dvec3 d(entry.dir.x, std::fabs(entry.dir.y), entry.dir.z);  // at the chord's far end
                {
                    // The first chord leaves the entry at γ' to the normal in the section; it
                    // meets the medulla where |sin γ'| < κ, after cos γ' − √(κ² − sin²γ') in
                    // the section, over the chord's in-section share in 3D.
                    const double in_plane = std::max(std::sqrt(d.y * d.y + d.z * d.z), 1e-12), offset = d.z / in_plane;
                    if (std::fabs(offset) < kappa)
                        hits += 1, to_medulla += (d.y / in_plane - std::sqrt(kappa * kappa - offset * offset)) / in_plane;
                }
                const double gamma_1 = std::atan2(d.z, d.y);                   // the first chord's γ'
                double gamma_2 = 0;                                             // the second's
                // The path's light per channel, unscattered and first scattered in the medulla,
                // chord by chord, each chord with its own geometry (medulla_chord's terms): the
                // facets turn the chords of light that stays inside onto the medulla or off it.
                glm::dvec3 path_t(1), path_s(0);
                const auto through = [&](const glm::dvec3& dc) {
                    const double in_plane = std::max(std::sqrt(dc.y * dc.y + dc.z * dc.z), 1e-12), off = dc.z / in_plane;
                    const double l = 2 * dc.y / sqr(in_plane);  // the chord, 2 cos γ' in the section, in 3D
                    const double lm = std::fabs(off) < kappa ? std::min(l, 2 * std::sqrt(kappa * kappa - off * off) / in_plane) : 0.0;
                    for (int c = 0; c < 3; ++c) {
                        const double st = sigma_s + sigma_a_medulla[c], half = std::exp(-0.5 * sigma_a[c] * (l - lm));
                        const double m1 = lm > 0 && st > 0 ? std::expm1(-st * lm) : 0.0;  // e^(−σt ℓ_m) − 1
                        path_s[c] += path_t[c] * half * (st > 0 ? sigma_s / st * -m1 : 0.0);
                        path_t[c] *= half * half * (1 + m1);
                    }
                };
                through(d);
                int order = 1;
                for (; order < kMaxEvents; ++order) {
                    const RoughFacets::Exit x = facets.walk(d, false, eta, rng);
                    if (x.outside) {  // leaves at this order
                        const double beam = std::sqrt(1 - h * h);  // (the nodes are uniform in γ: dh = cos γ dγ)
                        if (order == 2) trt_exits.emplace_back(x.dir.x, beam);
                        if (order >= 3) later_exits.emplace_back(x.dir.x, beam * (path_t[0] + path_t[1] + path_t[2]) / 3);
                        const double exit = std::atan2(x.dir.z, x.dir.y);
                        if (order == 1) tt_turns.emplace_back(wrap_pi(gamma - 2 * gamma_t + 2 * gamma_1 - exit), 1.0);
                        // TRT's: two chords, 2π − 2γ'_1 − 2γ'_2 + exit + γ against the smooth
                        // 2π + 2γ − 4γt.
                        if (order == 2)
                            trt_turns.emplace_back(wrap_pi(gamma - 4 * gamma_t + 2 * gamma_1 + 2 * gamma_2 - exit), 1.0);
                        break;
                    }
                    d = glm::dvec3(x.dir.x, std::fabs(x.dir.y), x.dir.z);  // the next chord's far end
                    if (order == 1) gamma_2 = std::atan2(d.z, d.y);
                    through(d);
                }
                if (order == 1) first += 1;
                else if (order == 2) second += 1;
                else later += 1, tail_events += order - 3, late_t += path_t, late_s += path_s;
            }
            const double inv = entered > 0 ? 1 / entered : 0, mean_tail = later > 0 ? tail_events / later : 0;
            using Tab = RoughCortexTables<T>;
            T* node = tab.share[i][j];
            node[Tab::kTT] = T(first * inv);
            node[Tab::kTRT] = T(second * inv);
            node[Tab::kLater] = T(later * inv);
            node[Tab::kTailRatio] = T(mean_tail / (1 + mean_tail));
            node[Tab::kFr] = T(reflected / kWalks / fur_fresnel(out.y, eta));  // F_r over the smooth F
            const std::array<double, 3> q = weighted_quartiles(reflections);
            const DeonLobeFit lobe = reflected > 0 ? deon_lobe_from_quartiles(q[0], q[1], q[2]) : DeonLobeFit{0, -theta + 2 * alpha};
            // R's core and tail about the quartiles' centre (fit_deon_tail).
            const std::array<double, 3> tail = reflected > 0 ? fit_deon_tail(reflections, lobe.v, lobe.theta_c)
                                                             : std::array<double, 3>{lobe.v, 0.0, lobe.v};
            node[Tab::kVR] = T(tail[2]);
            node[Tab::kQuartileVR] = T(lobe.v);
            node[Tab::kTailR] = T(tail[0]);
            node[Tab::kTailWeightR] = T(tail[1]);
            node[Tab::kDeltaR] = T(theta - 2 * alpha + lobe.theta_c);  // δ_R: θo' = θo − 2α turned to −θc
            node[Tab::kPsiR] = T(reflected > 0 ? weighted_quantile(turns, 0.5) : 0.0);  // ψ_R: the median turn
            node[Tab::kPsiTT] = T(tt_turns.empty() ? 0.0 : weighted_quantile(tt_turns, 0.5));  // ψ_TT: the median turn
            // TT's and TRT's spreads about their median turns: the scale of the logistic with
            // the same mean absolute deviation about the median (a logistic's is 2 s ln 2), the
            // spread in L1 as the median is the centre in L1. (Matched by the quartiles instead,
            // the logistic cut the tails GGX's slopes give the turns: docs/models.md.)
            const auto scale = [](std::vector<std::pair<double, double>>& xw) {
                if (xw.empty()) return 0.0;
                const double med = weighted_quantile(xw, 0.5);
                double dev = 0, total = 0;
                for (const auto& e : xw) dev += e.second * std::fabs(e.first - med), total += e.second;
                return dev / total / (2 * std::log(2.0));
            };
            node[Tab::kScaleTT] = T(scale(tt_turns));
            node[Tab::kPsiTRT] = T(trt_turns.empty() ? 0.0 : weighted_quantile(trt_turns, 0.5));
            node[Tab::kScaleTRT] = T(scale(trt_turns));
            for (int c = 0; c < 3; ++c) {
                node[Tab::kLaterOut + c] = T(late_t[c] * inv);
                node[Tab::kLaterScatter + c] = T(late_s[c] * inv);
            }
            {
                // k: the rough entry's mean path to the medulla over the smooth chord's at h
                // (1 where the smooth chord misses it, or no rough one meets it).
                const double s_t = std::sin(gamma_t), cos_t = std::sqrt(1 - sqr(std::sin(theta)) / (eta * eta));
                const double smooth = s_t < kappa ? (std::cos(gamma_t) - std::sqrt(kappa * kappa - s_t * s_t)) / cos_t : 0.0;
                node[Tab::kEntryPath] = T(smooth > 1e-9 && hits > 0 ? to_medulla / hits / smooth : 1.0);
            }
        }
        // TRT's and the later orders' longitudinal lobes from their exits over the row (beam
        // uniform in h): the d'Eon lobe closest in L1, its conditioning angle as a turn from
        // the material's, θo' = θo + 4α (TRT) and θo (residual): sin δ, δ = θo' + θc.
        using Tab = RoughCortexTables<T>;
        const DeonLobeFit trt = trt_exits.empty() ? DeonLobeFit{4 * longitudinal_variance(beta_m), -theta - 4 * alpha}
                                                  : fit_deon_lobe_l1(trt_exits);
        const DeonLobeFit res = later_exits.empty() ? DeonLobeFit{4 * longitudinal_variance(beta_m), -theta}
                                                    : fit_deon_lobe_l1(later_exits);
        for (int j = 0; j < kH; ++j) {
            T* node = tab.share[i][j];
            node[Tab::kVTRT] = T(trt.v);
            node[Tab::kVRes] = T(res.v);
            node[Tab::kSinDeltaTRT] = T(std::sin(theta + 4 * alpha + trt.theta_c));
            node[Tab::kSinDeltaRes] = T(std::sin(theta + res.theta_c));
        }
    }
    return tab;
}

// One |θo| bin of the tables: light from wo = (sinθo, 0, cosθo) (φo = π/2) enters at offset
// h (only where its refracted chord meets the medulla), is carried unscattered with the
// analytic weights of medulla_chord until it first scatters, then random-walks through the
// medulla and the cortex (Fresnel by choice at the boundary: the smooth one, or with facets
// the rough cortex's, where the light trapped at tilted facets crosses the absorbing cortex
// again before it leaves; the entry stays smooth, its F being the lobes') until it leaves. Per exit: the
// relative azimuth and sin θi, weighted by the exit's energy, the channels' mean (the shape:
// N_S's Fourier series and q's moments), and per channel the weight at exit and at the first
// scattering (the escape fraction).
inline void simulate_medulla_bin(const FurParams<double>& p, double theta_o, int bin, MedullaTables<double>& tab,
                                 const RoughFacets* facets = nullptr) {
    const double eta = p.cortex.eta, sin_o = std::sin(theta_o), cos_o = std::cos(theta_o);
    const double eta_p = std::sqrt(eta * eta - sin_o * sin_o) / cos_o;  // Bravais' η' (docs/theory.md §3.1)
    const double h_max = std::min(1.0, p.kappa * eta_p);
    FurRng rng(static_cast<std::uint64_t>(0x5EEDF00Du) + static_cast<std::uint64_t>(bin));
    double fourier[kFurFourierTerms + 1] = {}, at_exit[3] = {}, at_first[3] = {}, moment[2] = {};
    long long events = 0;
    int paths = 0;
    const glm::dvec3 d_in(-sin_o, 0, -cos_o);
    for (int attempt = 0; paths < kFurPathsPerBin && events < kFurEventsPerBin && attempt < 50 * kFurPathsPerBin; ++attempt) {
        const double h = h_max * rng.uniform();
        const glm::dvec2 p0(h, std::sqrt(1 - h * h));  // (y, z) on the circle, facing the light
        const glm::dvec3 n0(0, p0.x, p0.y);
        const double ci = -glm::dot(d_in, n0);
        double w[3], w0 = 1 - fur_fresnel(ci, eta);
        // Refract into the cortex.
        const double ct = std::sqrt(std::max(0.0, 1 - (1 - ci * ci) / (eta * eta)));
        glm::dvec3 dir = glm::normalize(d_in / eta + (ci / eta - ct) * n0);
        glm::dvec2 pos = p0;
        for (int c = 0; c < 3; ++c) w[c] = w0;
        // Unscattered passes until the first scattering (every pass meets the medulla: a
        // circle keeps the chord's offset).
        bool scattered = false;
        for (int pass = 0; pass < 200 && w0 > 1e-6; ++pass) {
            const double tl = std::sqrt(dir.y * dir.y + dir.z * dir.z);
            const glm::dvec2 t2 = glm::dvec2(dir.y, dir.z) / tl;
            const double b = glm::dot(pos, t2), c2 = glm::dot(pos, pos) - p.kappa * p.kappa, disc = b * b - c2;
            const double s_in = disc > 0 ? -b - std::sqrt(disc) : -1, s_out = disc > 0 ? -b + std::sqrt(disc) : -1;
            if (!(s_in > 0)) break;  // (misses: only for h at h_max, rounding)
            for (int c = 0; c < 3; ++c) w[c] *= std::exp(-p.cortex.sigma_a[c] * s_in / tl);
            const double lm = (s_out - s_in) / tl;
            const double t_free = -std::log(1 - rng.uniform()) / p.sigma_s;
            if (t_free < lm) {
                for (int c = 0; c < 3; ++c) w[c] *= std::exp(-p.sigma_a_medulla[c] * t_free);
                pos += (s_in + t_free * tl) * t2;
                scattered = true;
                break;
            }
            // Through the medulla (the free flight's probability is the sampling itself),
            // on to the boundary, and reflected there with the Fresnel weight.
            for (int c = 0; c < 3; ++c) w[c] *= std::exp(-p.sigma_a_medulla[c] * lm);
            const double s_exit = fur_circle_exit(pos, t2, 1.0);
            for (int c = 0; c < 3; ++c) w[c] *= std::exp(-p.cortex.sigma_a[c] * (s_exit - s_out) / tl);
            pos = glm::normalize(pos + s_exit * t2);
            const glm::dvec3 n(0, pos.x, pos.y);
            const double f = fur_fresnel(glm::dot(dir, n), 1 / eta);
            w0 *= f;
            for (int c = 0; c < 3; ++c) w[c] *= f;
            dir -= 2 * glm::dot(dir, n) * n;
        }
        if (!scattered) continue;
        const double first[3] = {w[0], w[1], w[2]};
        // The walk after the first scattering: weights change by absorption only.
        bool inside_medulla = true, left = false;
        int n_events = 0;
        dir = fur_scatter(dir, p.g, rng.uniform(), rng.uniform());
        while (n_events < kFurEventsPerPath) {
            ++n_events;
            const double tl = std::sqrt(dir.y * dir.y + dir.z * dir.z);
            if (!(tl > 1e-9)) {  // along the axis: the next scattering turns it
                if (!inside_medulla) break;
                dir = fur_scatter(dir, p.g, rng.uniform(), rng.uniform());
                continue;
            }
            const glm::dvec2 t2 = glm::dvec2(dir.y, dir.z) / tl;
            if (inside_medulla) {
                const double s_out = std::max(0.0, fur_circle_exit(pos, t2, p.kappa));
                const double t_free = -std::log(1 - rng.uniform()) / p.sigma_s;
                const double t = std::min(t_free, s_out / tl);
                for (int c = 0; c < 3; ++c) w[c] *= std::exp(-p.sigma_a_medulla[c] * t);
                pos += t * tl * t2;
                if (t_free < s_out / tl) dir = fur_scatter(dir, p.g, rng.uniform(), rng.uniform());
                else inside_medulla = false;
                continue;
            }
            // In the cortex: to the medulla if the line meets it ahead, else to the boundary.
            const double b = glm::dot(pos, t2), c2 = glm::dot(pos, pos) - p.kappa * p.kappa, disc = b * b - c2;
            const double s_in = disc > 0 ? -b - std::sqrt(disc) : -1;
            if (s_in > 1e-12) {
                for (int c = 0; c < 3; ++c) w[c] *= std::exp(-p.cortex.sigma_a[c] * s_in / tl);
                pos += s_in * t2;
                inside_medulla = true;
                continue;
            }
            const double s_exit = std::max(0.0, fur_circle_exit(pos, t2, 1.0));
            for (int c = 0; c < 3; ++c) w[c] *= std::exp(-p.cortex.sigma_a[c] * s_exit / tl);
            pos = glm::normalize(pos + s_exit * t2);
            // The boundary's normal, or with the rough cortex one of its facets as seen from
            // inside (RoughFacets), in the frame (axis, normal, tangent) there; one facet event
            // per meeting (the whole walk would triple the densest medulla's build time).
            const glm::dvec3 n0(0, pos.x, pos.y);
            glm::dvec3 n = n0;
            if (facets) {
                const glm::dvec3 tn(0, -pos.y, pos.x);
                const glm::dvec3 m = facets->sample(glm::dvec3(dir.x, glm::dot(dir, n0), glm::dot(dir, tn)), rng);
                n = glm::normalize(glm::dvec3(m.x, 0, 0) + m.y * n0 + m.z * tn);
            }
            const double cos_i = glm::dot(dir, n);
            if (rng.uniform() < fur_fresnel(cos_i, 1 / eta)) {
                dir -= 2 * cos_i * n;
                const double outward = glm::dot(dir, n0);  // (a facet's reflection may still point out:
                if (outward > 0) dir -= 2 * outward * n0;  // mirrored in, as the walk does)
                continue;
            }
            const double ct_out = std::sqrt(std::max(0.0, 1 - eta * eta * (1 - cos_i * cos_i)));
            glm::dvec3 out = glm::normalize(eta * dir + (ct_out - eta * cos_i) * n);
            const double inward = glm::dot(out, n0);  // (likewise a refraction that points in)
            if (inward < 0) out -= 2 * inward * n0;
            // Left: its azimuth and the moments of sin θi are kept.
            const double phi = std::fabs(wrap_pi(std::atan2(out.z, out.y) - kHalfPi<double>));
            // Weighted by the exit's energy, the mean over the channels (w0 when lossless):
            // absorption favours the light that leaves early, and the shape follows it.
            const double we = (w[0] + w[1] + w[2]) / 3;
            for (int k = 0; k <= kFurFourierTerms; ++k) fourier[k] += we * std::cos(k * phi);
            moment[0] += we * out.x;
            moment[1] += we * out.x * out.x;
            for (int c = 0; c < 3; ++c) {
                at_exit[c] += w[c];
                at_first[c] += first[c];
            }
            left = true;
            break;
        }
        events += n_events;
        if (left) ++paths;
    }
    // The azimuthal density over |φ| as its Fourier series (the noise of a histogram would
    // be larger than the shape's detail), integrated per bin and floored at 0.
    const double width = kPi<double> / MedullaTables<double>::kPhiBins;
    double mass[MedullaTables<double>::kPhiBins], total = 0;
    for (int k = 0; k < MedullaTables<double>::kPhiBins; ++k) {
        const double a = k * width, b = a + width;
        double m = b - a;
        if (fourier[0] > 0)
            for (int j = 1; j <= kFurFourierTerms; ++j) m += 2 * fourier[j] / fourier[0] * (std::sin(j * b) - std::sin(j * a)) / j;
        mass[k] = std::max(0.0, m);
        total += mass[k];
    }
    tab.cdf[bin][0] = 0;
    for (int k = 0; k < MedullaTables<double>::kPhiBins; ++k) {
        tab.density[bin][k] = mass[k] / (total * width);
        // (the running sum can pass 1 by rounding before its last bin: kept within [0, 1])
        tab.cdf[bin][k + 1] =
            k + 1 < MedullaTables<double>::kPhiBins ? std::min(1.0, tab.cdf[bin][k] + mass[k] / total) : 1.0;
    }
    // q(x)'s w and b from E[x²] and E[x] (x = sin θi; sin θo > 0 here): U and C have their
    // own E[x²] (fill_exit_shapes, filled first; 0.317 and 0.239 at η 1.55), and (1 + bx)
    // adds b·E_sym[x²] to E[x].
    const double m_u = exit_second_moment(tab, 0), m_c = exit_second_moment(tab, 1);
    const double e1 = fourier[0] > 0 ? moment[0] / fourier[0] : 0, e2 = fourier[0] > 0 ? moment[1] / fourier[0] : m_c;
    const double w_once = m_u > m_c ? clamp((e2 - m_c) / (m_u - m_c), 0.0, 1.0) : 0.0;
    tab.longitudinal[bin][0] = w_once;
    tab.longitudinal[bin][1] = clamp(e1 / (w_once * m_u + (1 - w_once) * m_c), -1.0, 1.0);
    for (int c = 0; c < 3; ++c) {
        const bool lossless = p.cortex.sigma_a[c] == 0 && p.sigma_a_medulla[c] == 0;  // exactly 1 by construction
        tab.escape[bin][c] = lossless || !(at_first[c] > 0) ? 1.0 : std::min(1.0, at_exit[c] / at_first[c]);
    }
}

// The tables of a material (host): uniform and lossless where the medulla does not scatter.
// With the rough cortex they depend on α and the facets too (β_m where facet_alpha is 0).
template <typename T> MedullaTables<T> build_medulla_tables(const FurParams<T>& params) {
    FurParams<double> p;
    p.cortex.eta = double(params.cortex.eta);
    p.cortex.sigma_a = glm::dvec3(params.cortex.sigma_a);
    p.kappa = double(params.kappa);
    p.sigma_s = double(params.sigma_s);
    p.sigma_a_medulla = glm::dvec3(params.sigma_a_medulla);
    p.g = double(params.g);
    MedullaTables<double> d;
    fill_exit_shapes(d, p.cortex.eta);  // (before the simulation: its moment fit reads them)
    const bool scatters = p.kappa > 0 && p.sigma_s > 0;
    const RoughFacets facets = scatters && params.rough_cortex ? RoughFacets::of(p.cortex.eta, double(params.cortex.alpha),
                                                                                 double(params.cortex.beta_m),
                                                                                 double(params.facet_alpha))
                                                               : RoughFacets{};
    constexpr int kTheta = MedullaTables<T>::kThetaBins, kPhi = MedullaTables<T>::kPhiBins;
    for (int t = 0; t < kTheta; ++t) {
        if (scatters) {
            simulate_medulla_bin(p, (t + 0.5) * kHalfPi<double> / kTheta, t, d, params.rough_cortex ? &facets : nullptr);
            continue;
        }
        for (int k = 0; k < kPhi; ++k) {
            d.density[t][k] = kInvPi<double>;
            d.cdf[t][k] = double(k) / kPhi;
        }
        d.cdf[t][kPhi] = 1;
        for (int c = 0; c < 3; ++c) d.escape[t][c] = 1;
        d.longitudinal[t][0] = 0;  // (no scattered light: the cos θi law, as before tables had a shape)
        d.longitudinal[t][1] = 0;
    }
    MedullaTables<T> r;
    fill_exit_shapes(r, p.cortex.eta);
    for (int t = 0; t < kTheta; ++t) {
        for (int k = 0; k < kPhi; ++k) r.density[t][k] = T(d.density[t][k]);
        for (int k = 0; k <= kPhi; ++k) r.cdf[t][k] = T(d.cdf[t][k]);
        for (int c = 0; c < 3; ++c) r.escape[t][c] = T(d.escape[t][c]);
        for (int k = 0; k < 2; ++k) r.longitudinal[t][k] = T(d.longitudinal[t][k]);
    }
    fill_exit_mix(r);
    return r;
}

}  // namespace detail

// Everything that depends only on the fur parameters and the lobe controls, computed once
// per material on the host (validated: the constructor throws std::invalid_argument naming
// the bad parameter; docs/models.md gives the medulla tables' build time). Trivially
// copyable. Its d'Eon ingredients (longitudinal(p), tilt()) are DeonLobes', with the
// controls' per-lobe tilts, as ChiangMaterial's.
template <typename T> class FurMaterial : public DeonLobes<T> {
  public:
    static constexpr int kLobes = DeonLobes<T>::kLobes;

    explicit FurMaterial(const FurParams<T>& params, const FurControls<T>& controls = FurControls<T>())
        : FurMaterial(params, validated(controls), detail::build_medulla_tables(validated(params))) {}

    HAIRSCATTER_HD const FurParams<T>& params() const { return params_; }
    HAIRSCATTER_HD const FurControls<T>& controls() const { return controls_; }
    // Lobe p's factor on its energy: gain × tint of R, TT, TRT, the residual (p < 4) and S
    // (p = 4); 1 without controls, and then the fiber skips the products.
    HAIRSCATTER_HD glm::vec<3, T> lobe_weight(int p) const { return p < 4 ? weights_[p] : weight_s_; }
    HAIRSCATTER_HD bool has_lobe_weights() const { return any_weight_; }
    HAIRSCATTER_HD const TrimmedLogistic<T>& azimuthal() const { return n_; }
    HAIRSCATTER_HD const MedullaTables<T>& medulla() const { return tables_; }
    // The rough cortex's shares of the orders (FurParams::rough_cortex; zero otherwise).
    HAIRSCATTER_HD const detail::RoughCortexTables<T>& rough_cortex() const { return rough_; }
    // The offset |h| at which the refracted chord grazes the medulla, sinγt = κ, i.e.
    // h = κ η' (Bravais' η'); 1 where the medulla meets every chord. The chord's share
    // √(κ² − sin²γt) has a square-root edge there, which a quadrature over h must split at
    // (the dual-scattering tables do).
    HAIRSCATTER_HD T h_break(T sin_o) const {
        const FiberRefraction<T> r(sin_o, cos_from_sin(sin_o), params_.cortex.eta);
        return params_.kappa < r.gamma_t_scale ? params_.kappa / r.gamma_t_scale : T(1);
    }

    // The medulla tables in a small versioned binary file, to skip their simulation next
    // time: "HSFT", the version, the tables' sizes, the parameters they depend on (η and
    // σa^c of the cortex, κ, σs^m, σa^m, g, whether the cortex is rough, and its α, β_m, β_n
    // and facet α), the tables as doubles and an FNV-1a checksum of everything before it. A
    // float material's tables come back bit for bit. (Version 6: in version 5 q's w mixed a
    // uniform and a semicircle in sin θi, not MedullaTables' U and C. In version 4 a facet α of 0
    // meant Gaussian facets; version 3 had no facet α; version 2 neither the rough flag nor α
    // and β, on which the rough cortex's tables depend.)
    static constexpr std::uint32_t kFileVersion = 6;
    void save(const std::string& path) const {
        std::vector<unsigned char> buf;
        detail::put_bytes(buf, "HSFT", 4);
        for (std::uint32_t u : {kFileVersion, std::uint32_t(MedullaTables<T>::kThetaBins),
                                std::uint32_t(MedullaTables<T>::kPhiBins)})
            detail::put_bytes(buf, &u, 4);
        for (double d : table_parameters(params_)) detail::put_bytes(buf, &d, 8);
        for_each_value(tables_, [&](const T& v, double, double, const char*) {
            const double d = double(v);
            detail::put_bytes(buf, &d, 8);
        });
        detail::write_table_file(path, std::move(buf), "fur medulla tables");
    }

    // The material of params with the tables of a file written by save() (no simulation of
    // the medulla; the rough cortex's walk, which the file does not hold, is still run when
    // params.rough_cortex is set).
    // Throws std::invalid_argument for bad params (as the constructor), std::runtime_error
    // naming the file for a wrong magic, version, table size, file size or checksum, a
    // value outside what the simulation produces, or tables built for other parameters
    // (those the tables depend on must agree to 1e-6 relative; with the smooth cortex β_m,
    // β_n, α and the facet α may differ).
    static FurMaterial load(const FurParams<T>& params, const std::string& path,
                            const FurControls<T>& controls = FurControls<T>()) {
        require_valid(params);
        require_valid(controls);
        auto fail = [&](const std::string& why) {
            return std::runtime_error("hairscatter: '" + path + "' is not a valid fur medulla table file: " + why);
        };
        std::ifstream f(path, std::ios::binary);
        if (!f) HAIRSCATTER_THROW(std::runtime_error("hairscatter: cannot open fur medulla tables '" + path + "'"));
        constexpr int kTheta = MedullaTables<T>::kThetaBins, kPhi = MedullaTables<T>::kPhiBins;
        constexpr std::size_t kParams = 15, kValues = std::size_t(kTheta) * (2 * kPhi + 1 + 3 + 2);
        constexpr std::size_t kExpected = 4 + 3 * 4 + (kParams + kValues) * 8 + 8;
        // One byte more than a valid file holds: a longer file (or pipe) is seen as such.
        std::vector<unsigned char> buf(kExpected + 1);
        f.read(reinterpret_cast<char*>(buf.data()), std::streamsize(buf.size()));
        buf.resize(std::size_t(f.gcount()));
        if (buf.size() < 16 || std::memcmp(buf.data(), "HSFT", 4) != 0) HAIRSCATTER_THROW(fail("bad magic or too short"));
        std::size_t at = 4;
        const std::uint32_t version = detail::get_bytes<std::uint32_t>(buf, at);
        if (version != kFileVersion)
            HAIRSCATTER_THROW(fail("version " + std::to_string(version) + ", this library reads version " +
                                   std::to_string(kFileVersion)));
        const std::uint32_t theta = detail::get_bytes<std::uint32_t>(buf, at), phi = detail::get_bytes<std::uint32_t>(buf, at);
        if (theta != std::uint32_t(kTheta) || phi != std::uint32_t(kPhi))
            HAIRSCATTER_THROW(fail("tables of " + std::to_string(theta) + " x " + std::to_string(phi) +
                                   " bins, this library's are " + std::to_string(kTheta) + " x " + std::to_string(kPhi)));
        if (buf.size() != kExpected)
            HAIRSCATTER_THROW(fail(buf.size() < kExpected ? "size " + std::to_string(buf.size()) + " bytes, expected " +
                                                                std::to_string(kExpected) + " (truncated?)"
                                                          : "longer than the " + std::to_string(kExpected) + " bytes expected"));
        std::size_t end = kExpected - 8;
        if (detail::get_bytes<std::uint64_t>(buf, end) != detail::fnv1a(buf.data(), kExpected - 8))
            HAIRSCATTER_THROW(fail("checksum mismatch (corrupt file)"));
        static const char* kName[kParams] = {"eta", "sigma_a.r", "sigma_a.g", "sigma_a.b", "kappa",
                                             "sigma_s", "sigma_a_medulla.r", "sigma_a_medulla.g", "sigma_a_medulla.b", "g",
                                             "rough_cortex", "alpha", "beta_m", "beta_n", "facet_alpha"};
        const auto given = table_parameters(params);
        for (std::size_t k = 0; k < kParams; ++k) {
            const double in_file = detail::get_bytes<double>(buf, at), want = given[k];
            if (k > 10 && !params.rough_cortex) continue;  // (the smooth cortex's tables serve every α and β)
            if (!(std::fabs(in_file - want) <= 1e-6 * std::fmax(std::fabs(in_file), std::fabs(want))))
                HAIRSCATTER_THROW(fail(std::string("built for other fur parameters: ") + kName[k] + " " +
                                       std::to_string(in_file) + " in the file, " + std::to_string(want) + " given"));
        }
        MedullaTables<T> tables;
        detail::fill_exit_shapes(tables, double(params.cortex.eta));  // (from η: not in the file)
        for_each_value(tables, [&](T& v, double lo, double hi, const char* what) {
            v = T(detail::get_bytes<double>(buf, at));  // checked in T (1e300 is a double, not a float)
            // Within rounding of the range (a sum that passed 1 by an ulp in a file an earlier
            // build wrote) is brought into it; beyond that the file is refused.
            const double slack = 1e-9 * std::fmax(1.0, std::fmax(std::fabs(lo), std::fabs(hi)));
            if (!(std::isfinite(double(v)) && double(v) >= lo - slack && double(v) <= hi + slack))
                HAIRSCATTER_THROW(fail(std::string(what) + " = " + std::to_string(double(v)) + " outside [" +
                                       std::to_string(lo) + ", " + std::to_string(hi) + "]"));
            v = clamp(v, T(lo), T(hi));
        });
        for (int t = 0; t < kTheta; ++t) {
            if (tables.cdf[t][0] != T(0) || tables.cdf[t][kPhi] != T(1)) HAIRSCATTER_THROW(fail("a cdf not from 0 to 1"));
            for (int k = 0; k < kPhi; ++k)
                if (tables.cdf[t][k + 1] < tables.cdf[t][k]) HAIRSCATTER_THROW(fail("a decreasing cdf"));
        }
        detail::fill_exit_mix(tables);  // (from U, C and the loaded w)
        return FurMaterial(params, controls, tables);
    }

  private:
    // (params and controls validated by the caller.)
    FurMaterial(const FurParams<T>& params, const FurControls<T>& controls, const MedullaTables<T>& tables)
        : DeonLobes<T>(params.cortex.beta_m, controls.lobes, params.cortex.alpha), params_(params),
          controls_(controls), weights_(controls.lobes), weight_s_(controls.weight_s()),
          any_weight_(weights_.any() || weight_s_ != glm::vec<3, T>(T(1))), n_(logistic_scale(params.cortex.beta_n)),
          tables_(tables) {
        if (params.rough_cortex)
            rough_ = detail::build_rough_cortex<T>(double(params.cortex.eta), double(params.cortex.alpha),
                                                   double(params.cortex.beta_m), double(params.facet_alpha), double(params.kappa),
                                                   glm::dvec3(params.cortex.sigma_a), double(params.sigma_s),
                                                   glm::dvec3(params.sigma_a_medulla));
    }

    // What the tables depend on, in the file's order: with the rough cortex also the cuticle
    // tilt α and its facets' β_m and facet α (RoughFacets), which load() compares only then;
    // β_n, which the facets used to depend on, is recorded and compared with them.
    static std::array<double, 15> table_parameters(const FurParams<T>& p) {
        return {double(p.cortex.eta), double(p.cortex.sigma_a[0]), double(p.cortex.sigma_a[1]),
                double(p.cortex.sigma_a[2]), double(p.kappa), double(p.sigma_s), double(p.sigma_a_medulla[0]),
                double(p.sigma_a_medulla[1]), double(p.sigma_a_medulla[2]), double(p.g), p.rough_cortex ? 1.0 : 0.0,
                double(p.cortex.alpha), double(p.cortex.beta_m), double(p.cortex.beta_n), double(p.facet_alpha)};
    }
    // f(value, lo, hi, name) over every value of the tables in the file's order, with the
    // range the simulation keeps it in (a density is at most 1/width when all its mass is
    // in one bin).
    template <class Tables, class F> static void for_each_value(Tables& tab, F&& f) {
        constexpr int kTheta = MedullaTables<T>::kThetaBins, kPhi = MedullaTables<T>::kPhiBins;
        const double max_density = double(kPhi) / kPi<double> * 1.001;
        for (int t = 0; t < kTheta; ++t) {
            for (int k = 0; k < kPhi; ++k) f(tab.density[t][k], 0.0, max_density, "a density value");
            for (int k = 0; k <= kPhi; ++k) f(tab.cdf[t][k], 0.0, 1.0, "a cdf value");
            for (int c = 0; c < 3; ++c) f(tab.escape[t][c], 0.0, 1.0, "an escape fraction");
            f(tab.longitudinal[t][0], 0.0, 1.0, "a longitudinal mix");
            f(tab.longitudinal[t][1], -1.0, 1.0, "a longitudinal skew");
        }
    }

    FurParams<T> params_;
    FurControls<T> controls_;
    LobeWeights<T> weights_;
    glm::vec<3, T> weight_s_;
    bool any_weight_;
    TrimmedLogistic<T> n_;
    MedullaTables<T> tables_;
    detail::RoughCortexTables<T> rough_{};
};

// One fur fibre hit at offset h ∈ [-1, 1], behind the contract (models/contract.hpp), with
// ChiangFiber's conventions. Lobes: R, TT, TRT and the residual (Chiang et al. 2016 with the
// medulla's extinction in every chord), and S, the light scattered in the medulla:
//   f_S = E_S(wo, h) · q(sinθi; θo) · N_S(φ; θo)
// with E_S = (1 − F) first / (1 − T F) · a_esc: every pass's light that first scatters in the
// medulla, times the fraction that then leaves (MedullaTables). For σa^c = σa^m = 0,
// Σ_p A_p + E_S = 1 exactly (the extinction removes from the unscattered lobes what S
// gains). q, per unit sinθi, mixes the uniform exit of singly scattered light with the cos θi
// law of diffused light, skewed for g ≠ 0 (MedullaTables). sample: u.x picks the lobe ∝ its
// energy (channel sum), S is drawn exactly: sinθi from q (u.y, u.z and u.x's leftover), φ
// from its table (u.w).
// kLobes is 3: lobe_split and sample report S together with the residual.
template <typename T> class FurFiber : public FiberModel<FurFiber<T>, T> {
  public:
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    using Material = FurMaterial<T>;
    static constexpr int kLobes = Material::kLobes;
    using LobeSplit = hairscatter::LobeSplit<T, kLobes>;

    // Cheap, device-callable: h is clamped into [-1, 1] (clamped_offset).
    HAIRSCATTER_HD FurFiber(const Material& material, T h) : mat_(&material), h_(clamped_offset(h)) {
        gamma_o_ = elem::asin(h_);
        cos_gamma_o_ = cos_from_sin(h_);
    }
    FurFiber(const Material&&, T) = delete;

    // Host: the fibre at h, which must lie in [-1, 1] (throws std::invalid_argument).
    static FurFiber checked(const Material& material, T h) { return FurFiber(material, checked_offset(h)); }

    HAIRSCATTER_HD T h() const { return h_; }
    HAIRSCATTER_HD const Material& material() const { return *mat_; }

    // Per lobe, A_p(wo) and the share of it in |φ − centre| < π/2 (ChiangFiber's); the
    // scattered lobe is added to the residual's entry, its share from its table.
    HAIRSCATTER_HD LobeSplit lobe_split(V3 wo, T centre = T(0)) const {
        if (!unit_direction(wo)) return empty_lobe_split<T, kLobes>();
        const Outgoing o = outgoing<false>(wo);
        LobeSplit r;
        for (int p = 0; p < kLobes; ++p) {
            r.a[p] = V3(o.a[p][0], o.a[p][1], o.a[p][2]);
            r.backward[p] = o.lobe_n[p].arc_mass(centre - kHalfPi<T> - o.phi_p[p], kPi<T>);
        }
        const V3 res(o.a[kLobes][0], o.a[kLobes][1], o.a[kLobes][2]), s(o.a[kS][0], o.a[kS][1], o.a[kS][2]);
        r.a[kLobes] = res + s;
        const T wr = res.x + res.y + res.z, ws = s.x + s.y + s.z;
        const T bs = mat_->medulla().arc_mass(o.theta_bin, centre);
        r.backward[kLobes] = wr + ws > T(0) ? (T(0.5) * wr + bs * ws) / (wr + ws) : T(0.5);
        return r;
    }

    // Σ_p A_p + E_S: exact, every lobe's angular factor being normalised.
    HAIRSCATTER_HD V3 albedo(V3 wo) const {
        if (!unit_direction(wo)) return V3(T(0));
        return albedo_from(outgoing<false>(wo));
    }

    // The medulla-scattered lobe alone, f_S(wo, wi) (eval less Chiang's lobes): for studies
    // and for the tests against the physical reference's scattered light.
    HAIRSCATTER_HD V3 eval_scattered(V3 wo, V3 wi) const {
        if (!unit_directions(wo, wi)) return V3(T(0));
        const Outgoing o = outgoing<false>(wo);
        const T sin_i = clamp(wi.x, T(-1), T(1));
        return scattered_density(o, sin_i, cos_from_sin(sin_i), relative_azimuth(wo, wi)) * V3(o.a[kS][0], o.a[kS][1], o.a[kS][2]);
    }

  private:
    friend class FiberModel<FurFiber, T>;
    friend class BoundFiber<FurFiber>;

    static constexpr int kS = kLobes + 1;  // the scattered lobe's index here

    struct Outgoing {
        T a[std::size_t(kS + 1)][3];           // A_0 … A_3 and E_S per channel
        T w[std::size_t(kS + 1)];              // selection weights (channel sums)
        T w_total, inv_w_total;
        DeonLanes<T, kLobes + 1> m;            // M_p conditioned on the tilted θo', lane p lobe p
        T phi_p[std::size_t(kLobes + 1)];      // Φ(p, h), wrapped (0 for the residual)
        int theta_bin;
        T sin_o;
        DeonLongitudinal<T> r_lobe;            // R's M_p (the rough cortex's width at h)
        DeonLongitudinal<T> trt_lobe, res_lobe;  // TRT's and the residual's M_p
        TrimmedLogistic<T> lobe_n[std::size_t(kLobes)];  // N_p's trimmed logistic per lobe
        LaneLogistics<T, kLobes + 1> n;        // their constants as lanes (lane kLobes: the residual's, uniform)
        DeonLongitudinal<T> r_tail;            // R's tail and its weight w (the rough cortex's; w 0 without)
        T r_w;
        DeonLanes<T, 1> tail;                  // R's tail conditioned on R's θo', its norm times w
    };

    HAIRSCATTER_HD V3 albedo_from(const Outgoing& o) const {
        V3 a(T(0));
        for (int p = 0; p <= kS; ++p) a += V3(o.a[p][0], o.a[p][1], o.a[p][2]);
        return a;
    }

    template <bool kW> HAIRSCATTER_HD Outgoing outgoing(const V3& wo) const {
        const FurParams<T>& prm = mat_->params();
        Outgoing o;
        const T sin_o = clamp(wo.x, T(-1), T(1));
        const T cos_o = cos_from_sin(sin_o);
        const T fresnel = fresnel_dielectric(cos_o * cos_gamma_o_, prm.cortex.eta);
        const FiberRefraction<T> refraction(sin_o, cos_o, prm.cortex.eta);
        const typename FiberRefraction<T>::Path path = refraction.path(h_);
        // The rough cortex's walk at (θo, γ) (RoughCortexTables; read once, here, because its
        // entry also lengthens the chord's path through the cortex by k).
        using Tab = detail::RoughCortexTables<T>;
        T e[Tab::kEvalValues];  // (read only with the rough cortex)
        if (prm.rough_cortex) mat_->rough_cortex().at(elem::asin(sin_o), gamma_o_, e);
        const detail::MedullaChord<T> chord = detail::medulla_chord(prm, path.sin_gamma_t, path.chord, refraction.chord_scale,
                                                                    prm.rough_cortex ? e[Tab::kEntryPath] : T(1));
        const T gamma_t = elem::asin(path.sin_gamma_t);
        T att[std::size_t(kLobes + 1)][3];
        // S's first scattering over the light that entered, per channel: first Σ_k Q_k T^(k−1),
        // the light that passes k chords unscattered, with Q_k the share of the entered light
        // still inside at the k-th chord (smooth: Q_k = F^(k−1), the sum 1 / (1 − T F)); with
        // the rough cortex the later orders' part is the walk's own (S_c, below).
        T scatter[3];
        T entry_reflect = fresnel;  // R's share at entry: the smooth F, or the rough boundary's F_r
        for (int p = 0; p < kLobes; ++p) o.lobe_n[p] = mat_->azimuthal();
        for (int p = 0; p < kLobes; ++p) o.n.set(p, mat_->azimuthal());
        o.n.minus_inv_s[kLobes] = T(-0.0), o.n.scale[kLobes] = kInvTwoPi<T>;  // the residual: uniform
        if (prm.rough_cortex) {
            // The rough cortex's walk (RoughCortexTables): the facets reflect F_r at entry; of
            // the light that entered (1 − F_r), e1 leaves after one chord, e2 after two, each
            // chord attenuated by the chord at h, T; the later orders' light, L_c unscattered
            // and S_c first scattered in the medulla, is the walk's own, every chord with its
            // geometry (the facets turn trapped light's chords onto the medulla or off it):
            //   A_0 = F_r,  A_1 = (1 − F_r) e1 T,  A_2 = (1 − F_r) e2 T²,  A_res = (1 − F_r) L_c,
            //   E_S = (1 − F_r) (first (e1 + e2 (1 + T)) + S_c) a_esc.
            // Lossless every path's light leaves unscattered or scatters (L_c + S_c = e3, and
            // first = 1 − T): Σ_p A_p + E_S = 1 as before.
            entry_reflect = clamp(e[Tab::kFr] * fresnel, T(0), T(1));
            for (int c = 0; c < 3; ++c) {
                const T t = chord.transmittance[c], in = T(1) - entry_reflect;
                att[0][c] = entry_reflect;
                att[1][c] = in * e[Tab::kTT] * t;
                att[2][c] = in * e[Tab::kTRT] * t * t;
                att[3][c] = in * e[Tab::kLaterOut + c];
                scatter[c] = chord.first_scatter[c] * (e[Tab::kTT] + e[Tab::kTRT] * (T(1) + t)) + e[Tab::kLaterScatter + c];
            }
        } else {
            attenuation_channels<T, kLobes, 3>(fresnel, fresnel, chord.transmittance, att);
            for (int c = 0; c < 3; ++c) {
                // (the floor as in attenuation_channels: 1 − T F = 0 only where 1 − F = 0)
                const T denom = T(1) - chord.transmittance[c] * fresnel;
                scatter[c] = chord.first_scatter[c] / (denom > kMinNormal<T> ? denom : kMinNormal<T>);
            }
        }
        for (int p = 0; p <= kLobes; ++p)
            for (int c = 0; c < 3; ++c) o.a[p][c] = att[p][c];
        o.theta_bin = MedullaTables<T>::theta_bin(abs_value(sin_o));
        o.sin_o = sin_o;
        for (int c = 0; c < 3; ++c)  // (1 − F) first Σ_k Q_k T^(k−1): first scattering on any pass
            o.a[kS][c] = (T(1) - entry_reflect) * scatter[c] * mat_->medulla().escape[o.theta_bin][c];
        // The lobe controls, in this one place: f, the selection weights, albedo and lobe_split
        // all read the scaled energies (the per-lobe tilts are in the material's DeonLobes).
        if (mat_->has_lobe_weights())
            for (int p = 0; p <= kS; ++p) {
                const V3 weight = mat_->lobe_weight(p);
                for (int c = 0; c < 3; ++c) o.a[p][c] *= weight[c];
            }
        if (prm.rough_cortex) mat_->template condition<LobeSet::kAll, kLobes + 1, false>(o.m, sin_o, cos_o);  // (roots below)
        else mat_->template condition<LobeSet::kAll>(o.m, sin_o, cos_o);
        for (int p = 0; p <= kLobes; ++p) o.phi_p[p] = p < kLobes ? exit_azimuth_wrapped(p, gamma_o_, gamma_t) : T(0);
        o.r_lobe = mat_->longitudinal(0);
        o.trt_lobe = mat_->longitudinal(2);
        o.res_lobe = mat_->longitudinal(3);
        o.r_w = T(0);
        o.tail.sin_o[0] = o.tail.cos_o[0] = o.tail.a_scale[0] = o.tail.sqrt_a_scale[0] = o.tail.half_inv_v[0] = o.tail.norm[0] = T(0);
        if (prm.rough_cortex) {
            // R's azimuth turned by ψ_R toward wo's (Φ = −2γ toward 0; ψ_R is 0 at h = 0), TT's
            // by ψ_TT from Φ(1, h) (both 0 at h = 0).
            const T sign = h_ < T(0) ? T(-1) : T(1);
            o.phi_p[0] = wrap_pi_once(o.phi_p[0] + sign * e[Tab::kPsiR]);
            o.phi_p[1] = wrap_pi_once(o.phi_p[1] + sign * e[Tab::kPsiTT]);
            // TRT's by ψ_TRT from Φ(2, h), and TT's and TRT's N_p of the widths their facets
            // give them at h (s_TT, s_TRT; floored at the narrowest logistic the parameters
            // allow), in place of β_n's: R's stays β_n's.
            o.phi_p[2] = wrap_pi_once(o.phi_p[2] + sign * e[Tab::kPsiTRT]);
            // R's shape at h from the same facets (RoughCortexTables): the lobe of variance v_R
            // (floored at the narrowest lobe the parameters allow), its conditioning angle
            // turned by −δ_R from the tilt's (the controls' R tilt still acts on top).
            // Its constants and the two logistics' as one vector each in float (a division, an
            // exp, an expm1): R's e^(−2/v_R), TT's and TRT's e^(−π/s) − 1, and R's tail's
            // e^(−2/v_t) (fit_deon_tail: R's M_p the mixture (1 − w) M(v_R) + w M(v_t)).
            const T v_floor = longitudinal_variance(kMinRoughness<T>), s_floor = logistic_scale(kMinRoughness<T>);
            constexpr std::size_t kN = 8;
            // (the widths one run of the table, so one vector load and max: built lane by lane,
            // the vector's load waited on the lanes' stores; lanes 6 and 7 unused)
            const T floors[kN] = {v_floor, s_floor, s_floor, v_floor, v_floor, v_floor, v_floor, v_floor};
            T width[kN], inv[kN], x[kN], m[kN];
            for (std::size_t k = 0; k < kN; ++k) width[k] = e[Tab::kVR + k] > floors[k] ? e[Tab::kVR + k] : floors[k];
            o.r_w = e[Tab::kTailWeightR];
            for (std::size_t k = 0; k < kN; ++k) inv[k] = T(1) / width[k];
            for (std::size_t k = 0; k < kN; ++k) x[k] = m[k] = inv[k] * (k == 1 || k == 2 ? -kPi<T> : T(-2));
            if constexpr (std::is_same<T, float>::value) {
                elem::exp_each_nonpositive(x);
                elem::expm1_each_given_exp(m, x);
            } else {  // (one libm call per value: the logistics need only their expm1; lanes 6 and 7 unused)
                for (std::size_t k = 0; k < 6; ++k)
                    if (k != 1 && k != 2) x[k] = elem::exp(x[k]);
                for (std::size_t k = 0; k < 4; ++k) m[k] = elem::expm1(m[k]);
                // (TRT's and the residual's e^(−2/v) − 1 from the exp, an expm1 call less each: their
                // v is at most 4 v(β 1) ≈ 110, e^(−2/v) < 0.99, so under 1e-14 relative)
                m[4] = x[4] - T(1);
                m[5] = x[5] - T(1);
            }
            o.r_lobe = DeonLongitudinal<T>(width[0], inv[0], x[0], m[0]);
            o.r_tail = DeonLongitudinal<T>(width[3], inv[3], x[3], m[3]);
            o.trt_lobe = DeonLongitudinal<T>(width[4], inv[4], x[4], m[4]);
            o.res_lobe = DeonLongitudinal<T>(width[5], inv[5], x[5], m[5]);
            for (int k = 1; k < 3; ++k) {
                o.lobe_n[k] = TrimmedLogistic<T>(width[k], inv[k], m[k]);
                o.n.set(k, o.lobe_n[k]);
            }
            T sd, cd;
            elem::sincos(e[Tab::kDeltaR], sd, cd);
            const T s0 = o.m.sin_o[0], c0 = o.m.cos_o[0];
            o.r_lobe.condition(o.m, 0, s0 * cd - c0 * sd, abs_value(c0 * cd + s0 * sd));
            // TRT's and the residual's lobes from the walk's exits, turned by δ likewise.
            for (int p = 2; p <= kLobes; ++p) {
                using std::sqrt;
                const T sp = e[Tab::kSinDeltaTRT + p - 2], cp = sqrt(T(1) - sp * sp);
                const T s = o.m.sin_o[p], c = o.m.cos_o[p];
                (p == 2 ? o.trt_lobe : o.res_lobe).condition(o.m, p, s * cp - c * sp, abs_value(c * cp + s * sp));
            }
            o.m.take_roots();
            // R's tail about the same θo'; the weights go into the norms, so the densities add
            // the two: M_R = (1 − w) M(v_R) + w M(v_t).
            o.r_tail.condition(o.tail, 0, o.m.sin_o[0], o.m.cos_o[0]);
            o.tail.take_roots();
            o.m.norm[0] *= T(1) - o.r_w;
            o.tail.norm[0] *= o.r_w;
        }
        if constexpr (kW) {
            T total = T(0);
            for (int p = 0; p <= kS; ++p) total += (o.w[p] = o.a[p][0] + o.a[p][1] + o.a[p][2]);
            o.w_total = total;
            o.inv_w_total = total > T(0) ? T(1) / total : T(0);
        }
        return o;
    }

    // Each lobe's angular density M_p N_p at (θi, φ): the products f and pdf weigh. The
    // unscattered lobes as Chiang's, side by side (as deon_logistic_densities), then S. R's
    // tail takes the exp lane that the residual's N (uniform: 1/2π) leaves free there: the
    // three N exponents, the tail's and the four M exponents are one vector of eight exps in
    // float.
    HAIRSCATTER_HD void densities(const Outgoing& o, T sin_i, T cos_i, T phi, T (&mn)[std::size_t(kS + 1)]) const {
        using std::sqrt;
        constexpr int kM = kLobes + 1;  // where the M_p exponents start in e (e[kLobes]: R's tail)
        T e[std::size_t(kM + kLobes + 1)], m_factor[std::size_t(kLobes + 1)];
        const T sqrt_cos_i = sqrt(cos_i);
        // R's tail only where it has weight (e^(−0) = 1 times 0 else), and by the series alone
        // where a ≤ 6 for every θi (its fitted tails are mostly that wide).
        T tail_exponent = T(-0.0), tail_factor = T(0);
        if (o.r_w > T(0)) {
            if (o.tail.a_scale[0] <= T(detail::kI0SmallSplit)) o.tail.terms_small(0, sin_i, cos_i, tail_exponent, tail_factor);
            else o.tail.terms(0, sin_i, cos_i, sqrt_cos_i, tail_exponent, tail_factor);
        }
        // (every lane as one vector: lane kLobes's N, the residual's, is uniform, and the lane
        // holds the tail's exponent; a select rather than the lane written over after, whose
        // store the vector's load would wait on)
        for (int k = 0; k <= kLobes; ++k)
            e[k] = select(k < kLobes, TrimmedLogistic<T>::exponent_of_difference(phi - o.phi_p[k], o.n.minus_inv_scale(k)),
                          tail_exponent);
        for (int k = 0; k <= kLobes; ++k) o.m.terms(k, sin_i, cos_i, sqrt_cos_i, e[kM + k], m_factor[k]);
        elem::exp_each_nonpositive(e);  // (every exponent ≤ 0)
        // R's tail added to R's M, and the residual's N (lane kLobes) 1/2π, its scale, through
        // the same arithmetic as the others' (e 1, the denominator 1): one vector, selects
        // rather than lanes written over (a store into a vector's lane stalls its load), into
        // an array of its own (mn might alias o, which keeps the loop from vectorising).
        const T tail = tail_factor * e[kLobes];
        T lanes[std::size_t(kLobes + 1)];
        for (int k = 0; k <= kLobes; ++k) {
            const T en = select(k < kLobes, e[k], T(1)), onto = select(k < kLobes, T(1), T(0));
            lanes[k] = (m_factor[k] * e[kM + k] + select(k == 0, tail, T(0))) * (en * o.n.numerator(k)) / sqr(T(1) + en * onto);
        }
        for (int p = 0; p <= kLobes; ++p) mn[p] = lanes[p];
        mn[kS] = scattered_density(o, sin_i, cos_i, phi);
    }
    // S's density per steradian: q(sin θi) per unit sin θi times N_S(φ).
    HAIRSCATTER_HD T scattered_density(const Outgoing& o, T sin_i, T cos_i, T phi) const {
        const MedullaTables<T>& m = mat_->medulla();
        return m.longitudinal_pdf(o.theta_bin, o.sin_o, sin_i, cos_i) * m.azimuthal_pdf(o.theta_bin, phi);
    }

    template <bool kF, bool kPdf>
    HAIRSCATTER_HD HairEvalPdf<T> query(const Outgoing& o, const V3& wo, const V3& wi) const {
        const T sin_i = clamp(wi.x, T(-1), T(1));
        return combine<kF, kPdf>(o, sin_i, cos_from_sin(sin_i), relative_azimuth(wo, wi));
    }

    template <bool kF, bool kPdf>
    HAIRSCATTER_HD HairEvalPdf<T> combine(const Outgoing& o, T sin_i, T cos_i, T phi) const {
        T mn[std::size_t(kS + 1)];
        densities(o, sin_i, cos_i, phi, mn);
        HairEvalPdf<T> r;
        if constexpr (kF)
            for (int p = 0; p <= kS; ++p) r.f += mn[p] * V3(o.a[p][0], o.a[p][1], o.a[p][2]);
        if constexpr (kPdf) {
            T sum = T(0);
            for (int p = 0; p <= kS; ++p) sum += mn[p] * o.w[p];
            r.pdf = sum * o.inv_w_total;
        }
        return r;
    }

    HAIRSCATTER_HD HairSample<T> sample_from(const Outgoing& o, const V3& wo, const V4& u) const {
        const DiscreteChoice<T> choice = sample_discrete(o.w, kS + 1, u.x, o.w_total);
        const int p = choice.index;
        T sin_i, phi;
        if (p == kS) {
            // q(sin θi) from u.y, u.z and the lobe choice's leftover, φ from its table (u.w).
            sin_i = mat_->medulla().sample_longitudinal(o.theta_bin, o.sin_o, u.y, u.z, choice.rescaled);
            phi = mat_->medulla().sample_azimuth(o.theta_bin, u.w);
        } else {
            // R: its tail with probability w (the lobe choice's leftover), else its core.
            const bool tail = p == 0 && choice.rescaled < o.r_w;
            sin_i = (p == 0 ? (tail ? o.r_tail : o.r_lobe) : p == 2 ? o.trt_lobe : p == 3 ? o.res_lobe : mat_->longitudinal(p))
                        .sample_sin_theta(o.m.sin_o[p], o.m.cos_o[p], u.y, u.z);
            phi = p < kLobes ? o.phi_p[p] + o.lobe_n[p].sample(u.w) : kTwoPi<T> * u.w - kPi<T>;
        }
        phi = wrap_pi(phi);
        const T cos_i = cos_from_sin(sin_i);
        const V3 wi = direction_from_azimuth(wo, sin_i, phi);
        return make_sample(wi, lobe_tag(p < kS ? p : kLobes),
                           combine<true, true>(o, sin_i, cos_i, queried_azimuth(wo, wi, cos_i, phi)));
    }

    const Material* mat_;
    T h_ = T(0), gamma_o_ = T(0), cos_gamma_o_ = T(1);
};

static_assert(is_fiber_model_v<FurFiber<float>> && is_fiber_model_v<FurFiber<double>>);

}  // namespace hairscatter
