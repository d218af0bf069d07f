// hairscatter — dual-scattering tables per wavelength, for spectral rendering with the Chiang
// model and melanin (docs/spectral.md). A renderer that samples wavelengths per path needs
// a_f, a_b, ᾱ, β̄² at any wavelength: they are built once at K wavelengths evenly spaced
// over [360, 830] nm, three wavelengths per DualScatteringTables (one per channel: the
// tables' channels are independent), and read at a path's wavelengths by linear
// interpolation in λ.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "../fiber/spectral.hpp"
#include "../models/chiang.hpp"
#include "tables.hpp"

namespace hairscatter {

template <typename T> class SpectralDualTables {
  public:
    using Entry = DualScatteringEntry<T>;
    static constexpr int kMinWavelengths = 2;

    SpectralDualTables() = default;

    // The tables of Chiang fibers with the material's geometry and lobe controls (its own σa
    // is replaced) and the melanin concentrations' σa (fiber/spectral.hpp) at `wavelengths`
    // wavelengths from 360 to 830 nm. Host only; throws std::invalid_argument naming a bad
    // concentration or a count below 2 (the table options are DualScatteringTables').
    static SpectralDualTables build(const ChiangMaterial<T>& material, const MelaninConcentrations<T>& melanin,
                                    int wavelengths = 48, const DualTableOptions<T>& opt = {}) {
        std::string bad = validate(melanin);
        if (wavelengths < kMinWavelengths)
            bad += (bad.empty() ? "" : "; ") + std::string("wavelengths = ") + std::to_string(wavelengths) +
                   " is outside its range [2, inf)";
        detail::throw_if_invalid(bad, "spectral dual-scattering tables");
        SpectralDualTables t;
        t.count_ = wavelengths;
        for (int j = 0; 3 * j < wavelengths; ++j) {
            FiberParams<T> p = material.params();
            for (int c = 0; c < 3; ++c) {
                const int k = 3 * j + c < wavelengths ? 3 * j + c : wavelengths - 1;  // (the last group: padded)
                p.sigma_a[c] = sigma_a_from_concentrations_at(melanin.eumelanin, melanin.pheomelanin, t.wavelength(k));
            }
            const ChiangMaterial<T> m(p, material.controls());
            t.tables_.push_back(DualScatteringTables<T>::template build<ChiangFiber<T>>(m, opt));
        }
        return t;
    }

    int wavelengths() const { return count_; }
    // Wavelength k of the grid, in nm: 360 + 470 k / (K - 1).
    T wavelength(int k) const {
        return kMinWavelength<T> + (kMaxWavelength<T> - kMinWavelength<T>) * T(k) / T(count_ - 1);
    }
    // The RGB tables that hold wavelength k, in channel k % 3 (for the dual BCSDF's RGB
    // machinery: its three channels are three of the grid's wavelengths).
    const DualScatteringTables<T>& tables_of(int k) const { return tables_[std::size_t(k / 3)]; }
    int channel_of(int k) const { return k % 3; }

    // The entry at the light's inclination θ whose channel c is wavelength lambda[c] (nm,
    // clamped into [360, 830]): a_f, a_b, ᾱ, β̄², μ_f and μ_b interpolated linearly in λ between the two
    // nearest grid wavelengths (each read at θ as DualScatteringTables::lookup reads it), the
    // backscattering terms A_b, Δ_b, σ_b² derived from them (Zinke et al. 2008 eqs. 13–15).
    // A path with four wavelengths reads two entries.
    Entry lookup(T theta, const glm::vec<3, T>& lambda) const {
        Entry e;
        for (int c = 0; c < 3; ++c) {
            const T x = (clamp(lambda[c], kMinWavelength<T>, kMaxWavelength<T>) - kMinWavelength<T>) /
                        (kMaxWavelength<T> - kMinWavelength<T>) * T(count_ - 1);
            const int k0 = x >= T(count_ - 1) ? count_ - 2 : int(x);
            const T t = x - T(k0);
            const Entry e0 = tables_of(k0).lookup(theta), e1 = tables_of(k0 + 1).lookup(theta);
            const int c0 = channel_of(k0), c1 = channel_of(k0 + 1);
            for (int f = 0; f < Entry::kFields; ++f)
                if (f < Entry::kFieldA_b || f >= Entry::kFieldMu_f)  // A_b, Δ_b, σ_b² are derived below
                    e.fields()[f][c] = e0.fields()[f][c0] + t * (e1.fields()[f][c1] - e0.fields()[f][c0]);
        }
        derive_backscattering(e, tables_.front().settings().d_b);
        return e;
    }

  private:
    int count_ = 0;
    std::vector<DualScatteringTables<T>> tables_;
};

}  // namespace hairscatter
