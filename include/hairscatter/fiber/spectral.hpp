// hairscatter — spectral rendering's inputs: N values per path (one per sampled wavelength),
// the wavelengths a renderer samples, and the absorption σa of eumelanin and pheomelanin at
// any visible wavelength, from the published absorption spectra (docs/spectral.md).
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "../config.hpp"
#include "../math/functions.hpp"
#include "params.hpp"
#include "pigments.hpp"

namespace hairscatter {

// N values, one per channel (a sampled wavelength, or a colour channel). Plain and
// trivially copyable: a renderer copies its own sampled spectrum in and out.
template <typename T, int N> struct SpectralValues {
    static_assert(N >= 1, "at least one channel");
    static constexpr int kChannels = N;
    T v[std::size_t(N)];

    HAIRSCATTER_HD T& operator[](int c) { return v[c]; }
    HAIRSCATTER_HD const T& operator[](int c) const { return v[c]; }
    // Every channel x.
    HAIRSCATTER_HD static SpectralValues filled(T x) {
        SpectralValues r;
        for (int c = 0; c < N; ++c) r.v[c] = x;
        return r;
    }
};

// The wavelengths, in nm, at which the melanin spectra below are used: 360–830 nm, the
// range pbrt-v4 (Lambda_min, Lambda_max) and Mitsuba 3 (its CIE range) sample.
template <typename T> inline constexpr T kMinWavelength = T(360);
template <typename T> inline constexpr T kMaxWavelength = T(830);

namespace detail {
// The two power laws from ln λ, which they share: e^(ln k - m ln λ) (pow's float overload is
// not on every device compiler's list, and k λ^-m stays well inside the float range this way).
template <typename T> HAIRSCATTER_HD T eumelanin_absorption_from_log(T ln_lambda) {
    using std::exp;
    return exp(T(24.912920578972837) - T(3.33) * ln_lambda);  // ln 6.6·10¹⁰
}
template <typename T> HAIRSCATTER_HD T pheomelanin_absorption_from_log(T ln_lambda) {
    using std::exp;
    return exp(T(33.300902038909065) - T(4.75) * ln_lambda);  // ln 2.9·10¹⁴
}
}  // namespace detail

// The absorption coefficients of the two melanins in mm⁻¹ at wavelength λ in nm: Jacques'
// power-law fits for melanosomes, 6.6·10¹¹ λ^-3.33 and 2.9·10¹⁵ λ^-4.75 per cm, as Donner &
// Jensen 2006 ("A Spectral BSSRDF for Shading Human Skin") use them:
//   σa,e(λ) = 6.6·10¹⁰ λ^-3.33 mm⁻¹ (eumelanin),  σa,p(λ) = 2.9·10¹⁴ λ^-4.75 mm⁻¹ (pheomelanin).
// Only their ratio enters σa (sigma_a_from_concentrations_at fits its length to the RGB
// coefficients), so a text that prints the same numbers per mm changes nothing there.
// No range check (wavelength_in_range / validate_wavelengths are the checks).
template <typename T> HAIRSCATTER_HD T eumelanin_absorption_per_mm(T lambda_nm) {
    using std::log;
    return detail::eumelanin_absorption_from_log(log(lambda_nm));
}
template <typename T> HAIRSCATTER_HD T pheomelanin_absorption_per_mm(T lambda_nm) {
    using std::log;
    return detail::pheomelanin_absorption_from_log(log(lambda_nm));
}

// The library's concentrations (sigma_a_from_concentrations: σa per unit fiber radius,
// pbrt-v4's and Chiang et al. 2016's) in the spectra's units: a concentration of 1 is a
// pigment whose absorption times this length, in mm, is σa per unit radius,
//   σa(λ) = kMelaninUnitLength · (ce σa,e(λ) + cp σa,p(λ)).
// Fitted (least squares in log σa, one length for both pigments) together with the three
// reference wavelengths below so that σa at those wavelengths reproduces the RGB
// coefficients ce (0.419, 0.697, 1.37) + cp (0.187, 0.4, 1.05): every coefficient within
// 1.1 % (docs/spectral.md has the fit; tests/spectral_test.cpp checks the bound).
template <typename T> inline constexpr T kMelaninUnitLength = T(0.0139094);

// The wavelengths, in nm, at which the RGB coefficients above are the spectra's values
// (the fit above): R 640.36, G 546.95, B 446.42. "RGB σa agrees with spectral σa" means
// sigma_a_from_concentrations(ce, cp)[c] = sigma_a_from_concentrations_at(ce, cp,
// rgb_reference_wavelength(c)) within 1.1 % relative, for every ce, cp ≥ 0.
template <typename T> HAIRSCATTER_HD constexpr T rgb_reference_wavelength(int c) {
    return c == 0 ? T(640.364) : (c == 1 ? T(546.946) : T(446.417));
}

// Whether λ (nm) lies in [kMinWavelength, kMaxWavelength] (NaN does not).
template <typename T> HAIRSCATTER_HD bool wavelength_in_range(T lambda_nm) {
    return detail::in_range(lambda_nm, kMinWavelength<T>, kMaxWavelength<T>);
}

// σa per unit fiber radius at wavelength λ (nm) of eumelanin and pheomelanin concentrations
// ce, cp ≥ 0 (the units of sigma_a_from_concentrations): unchecked and device-callable; the
// caller keeps λ in range and the concentrations non-negative (clamped_spectral_sigma_a
// does it per hit, spectral_sigma_a checks on the host).
template <typename T> HAIRSCATTER_HD T sigma_a_from_concentrations_at(T eumelanin, T pheomelanin, T lambda_nm) {
    using std::log;
    const T ln_lambda = log(lambda_nm);  // (one log for both pigments)
    return kMelaninUnitLength<T> * (eumelanin * detail::eumelanin_absorption_from_log(ln_lambda) +
                                    pheomelanin * detail::pheomelanin_absorption_from_log(ln_lambda));
}

// Empty when every wavelength lies in [360, 830] nm, else a message naming each bad one.
template <typename T, int N> std::string validate_wavelengths(const SpectralValues<T, N>& lambda_nm) {
    detail::Complaints bad;
    for (int c = 0; c < N; ++c)
        if (!wavelength_in_range(lambda_nm[c]))
            bad.add("wavelength[" + std::to_string(c) + "] (nm)", double(lambda_nm[c]), "[360, 830]");
    return bad.str();
}

// Empty when both concentrations are finite and non-negative, else a message naming each bad one.
template <typename T> std::string validate(const MelaninConcentrations<T>& c) {
    detail::Complaints bad;
    if (!detail::in_range(c.eumelanin, T(0), kMaxFinite<T>)) bad.add("eumelanin", double(c.eumelanin), "[0, inf) (finite)");
    if (!detail::in_range(c.pheomelanin, T(0), kMaxFinite<T>))
        bad.add("pheomelanin", double(c.pheomelanin), "[0, inf) (finite)");
    return bad.str();
}

// Host: σa per unit radius at each of N wavelengths (nm) of melanin concentrations, checked:
// throws std::invalid_argument naming a negative or non-finite concentration or a
// wavelength outside [360, 830] nm (without exceptions: prints it and aborts).
template <typename T, int N>
SpectralValues<T, N> spectral_sigma_a(const MelaninConcentrations<T>& c, const SpectralValues<T, N>& lambda_nm) {
    std::string bad = validate(c);
    const std::string wavelengths = validate_wavelengths(lambda_nm);
    if (!wavelengths.empty()) bad += (bad.empty() ? "" : "; ") + wavelengths;
    detail::throw_if_invalid(bad, "spectral absorption");
    SpectralValues<T, N> r;
    for (int k = 0; k < N; ++k) r[k] = sigma_a_from_concentrations_at(c.eumelanin, c.pheomelanin, lambda_nm[k]);
    return r;
}

// Per hit, on the host or the device (textured concentrations, a renderer's sampled
// wavelengths): no checks and no exceptions. Concentrations are clamped to [0, max] and
// wavelengths into [360, 830] nm, NaN and ±Inf to the lower end (as clamped_params does).
template <typename T, int N>
HAIRSCATTER_HD SpectralValues<T, N> clamped_spectral_sigma_a(const MelaninConcentrations<T>& c,
                                                              const SpectralValues<T, N>& lambda_nm) {
    // (NaN and ±Inf, read from the bits so that -ffast-math keeps the rule, → lo)
    auto into = [](T x, T lo, T hi) { return is_finite(x) ? (x > hi ? hi : (x >= lo ? x : lo)) : lo; };
    const T ce = into(c.eumelanin, T(0), kMaxFinite<T>), cp = into(c.pheomelanin, T(0), kMaxFinite<T>);
    SpectralValues<T, N> r;
    for (int k = 0; k < N; ++k)
        r[k] = sigma_a_from_concentrations_at(ce, cp, into(lambda_nm[k], kMinWavelength<T>, kMaxWavelength<T>));
    return r;
}

// N wavelengths from one uniform number u ∈ [0, 1): the first at 360 + 470 u nm, the others
// at equal steps of 470/N nm after it, wrapped into the range (pbrt-v4's
// SampledWavelengths::SampleUniform, the "hero wavelength" scheme of Wilkie et al. 2014).
// Each is uniform on [360, 830] nm: its density is uniform_wavelength_pdf.
template <typename T, int N> HAIRSCATTER_HD SpectralValues<T, N> sample_uniform_wavelengths(T u) {
    constexpr T kSpan = kMaxWavelength<T> - kMinWavelength<T>;
    SpectralValues<T, N> r;
    T x = kMinWavelength<T> + kSpan * clamp(u, T(0), T(1));
    for (int k = 0; k < N; ++k) {
        r[k] = x > kMaxWavelength<T> ? x - kSpan : x;
        x += kSpan / T(N);
    }
    return r;
}
template <typename T> HAIRSCATTER_HD constexpr T uniform_wavelength_pdf() {
    return T(1) / (kMaxWavelength<T> - kMinWavelength<T>);
}

}  // namespace hairscatter
