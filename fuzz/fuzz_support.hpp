// What the model fuzz targets share: a reader of raw floats and bytes from libFuzzer's input,
// the check that aborts (libFuzzer then reports the input), lobe controls from the bytes, and
// the calls of a fiber's contract with their checks:
//   - for unit wo and wi and u in [0, 1]: eval, pdf and the sample are finite and
//     non-negative and the sample's direction is finite;
//   - a non-finite component of wo or wi gives eval = 0 and pdf = 0, and of wo or u the
//     empty sample.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include <hairscatter/hairscatter.hpp>

namespace fuzz {

namespace hs = hairscatter;

struct Reader {
    const std::uint8_t* p;
    std::size_t n;
    float next() {
        float f = 0.0f;
        if (n >= 4) {
            std::memcpy(&f, p, 4);
            p += 4;
            n -= 4;
        }
        return f;
    }
    std::uint8_t byte() {
        if (n == 0) return 0;
        --n;
        return *p++;
    }
    // A raw float's fractional part in [0, 1) (0 for a non-finite one).
    template <typename T> T unit() {
        const T x = T(next());
        return hs::is_finite(x) ? x - std::floor(x) : T(0);
    }
    // A parameter: the raw float (any value), or mapped into [lo, hi) by its fractional part.
    template <typename T> T parameter(T lo, T hi, bool mapped) { return mapped ? lo + (hi - lo) * unit<T>() : T(next()); }
    // A fiber offset h in [-1, 1) from a raw float (0 for a non-finite one).
    template <typename T> T offset() {
        const T h = T(next());
        return hs::is_finite(h) ? h - T(2) * std::floor(T(0.5) * h) - T(1) : T(0);
    }
};

inline void check(bool ok) {
    if (!ok) std::abort();
}

template <typename T> bool non_negative(const glm::vec<3, T>& v) {
    return hs::is_finite(v) && v.x >= T(0) && v.y >= T(0) && v.z >= T(0);
}

// Finite raw values become unit vectors and numbers in [0, 1] (when they can): true then.
template <typename T> bool make_proper(glm::vec<3, T>& wo, glm::vec<3, T>& wi, glm::vec<4, T>& u) {
    if (!(hs::is_finite(wo) && hs::is_finite(wi) && hs::is_finite(u))) return false;
    const T lo = glm::length(wo), li = glm::length(wi);
    if (!(lo > T(1e-3) && lo < T(1e3) && li > T(1e-3) && li < T(1e3))) return false;
    wo /= lo;
    wi /= li;
    for (int c = 0; c < 4; ++c) u[c] = u[c] - std::floor(u[c]);
    return hs::is_finite(u);
}

// Four (wo, wi, u) triples from the bytes through every call of a fiber's contract.
template <typename T, typename Fiber> void exercise(const Fiber& fiber, Reader& r) {
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    for (int k = 0; k < 4; ++k) {
        V3 wo(T(r.next()), T(r.next()), T(r.next())), wi(T(r.next()), T(r.next()), T(r.next()));
        V4 u(T(r.next()), T(r.next()), T(r.next()), T(r.next()));
        const bool finite = hs::is_finite(wo) && hs::is_finite(wi) && hs::is_finite(u);
        const bool proper = make_proper(wo, wi, u);
        const hs::HairEvalPdf<T> e = fiber.eval_pdf(wo, wi);
        const V3 f = fiber.eval(wo, wi);
        const T pdf = fiber.pdf(wo, wi);
        const hs::HairSample<T> s = fiber.sample(wo, u);
        if (!finite) {
            // eval and pdf need wo and wi; sample needs wo and u.
            if (!(hs::is_finite(wo) && hs::is_finite(wi))) check(f == V3(T(0)) && pdf == T(0) && e.pdf == T(0));
            if (!(hs::is_finite(wo) && hs::is_finite(u))) check(s.pdf == T(0) && s.weight == V3(T(0)));
        } else if (proper) {
            check(non_negative(f) && non_negative(e.f));
            check(hs::is_finite(pdf) && pdf >= T(0) && hs::is_finite(e.pdf) && e.pdf >= T(0));
            check(hs::is_finite(s.pdf) && s.pdf >= T(0) && non_negative(s.weight) && hs::is_finite(s.wi));
        }
    }
}

// Lobe controls from the bytes: none, or gains, tints, tilts and override bits either raw
// (any float) or mapped into [0, 3) (gains, tints) and [-π/8, π/8] (tilts), with the
// residual's left at 1 on half of the mapped sets (Marschner refuses any other).
template <typename T> hs::LobeControls<T> read_controls(Reader& r, std::uint8_t mode) {
    hs::LobeControls<T> c;
    if ((mode & 1u) == 0u) return c;
    const bool raw = (mode & 2u) != 0u, keep_residual = (mode & 4u) != 0u;
    // Mode bit 16: gains and tints anywhere up to kMaxLobeGain (log-uniform), where the
    // multiple-scattering sums of a dual-scattering fiber would diverge.
    const bool large = (mode & 16u) != 0u;
    auto value = [&](T scale) {
        if (large && !raw) {
            const T x = T(r.next());
            return hs::is_finite(x) ? std::pow(T(10), T(6) * (x - std::floor(x))) : T(1);
        }
        const T x = T(r.next());
        if (raw || !hs::is_finite(x)) return raw ? x : T(1);
        return scale * (x - std::floor(x));
    };
    const int lobes = keep_residual && !raw ? 3 : 4;
    for (int p = 0; p < lobes; ++p) c.gain[p] = value(T(3));
    for (int p = 0; p < lobes; ++p)
        for (int ch = 0; ch < 3; ++ch) c.tint[p][ch] = value(T(3));
    for (int p = 0; p < 3; ++p) {
        const T x = T(r.next());
        const T a = raw || !hs::is_finite(x) ? (raw ? x : T(1)) : T(2) * hs::kMaxCuticleTilt<T> * (x - std::floor(x));
        c.alpha[p] = raw ? a : a - hs::kMaxCuticleTilt<T>;
    }
    c.alpha_override = raw ? unsigned(r.byte()) : unsigned(r.byte() & 7u);
    return c;
}

}  // namespace fuzz
