// libFuzzer target: parameters → material → eval / pdf / sample for every model, float and
// double. The bytes choose the model, the precision, the parameters (raw floats: any value,
// NaN and Inf included), the lobe controls (raw floats, or mapped
// into [0, 3) and ±π/8 so that valid ones are common), wo, wi and u. Checked:
//   - validate() never throws, and a material is built exactly when it returns "" for the
//     parameters and the controls (Marschner: and no residual gain or tint);
//   - for valid parameters, unit wo and wi and u in [0, 1]: eval, pdf and the sample are
//     finite and non-negative and the sample's direction is finite;
//   - a non-finite component of wo or wi gives eval = 0 and pdf = 0, and of wo or u the
//     empty sample.
// A violation aborts (libFuzzer reports it with the input).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include <hairscatter/hairscatter.hpp>

namespace hs = hairscatter;

namespace {

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
};

void check(bool ok) {
    if (!ok) std::abort();
}

template <typename T, typename Fiber> void exercise(const Fiber& fiber, Reader& r) {
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    for (int k = 0; k < 4; ++k) {
        V3 wo(T(r.next()), T(r.next()), T(r.next())), wi(T(r.next()), T(r.next()), T(r.next()));
        V4 u(T(r.next()), T(r.next()), T(r.next()), T(r.next()));
        const bool finite = hs::is_finite(wo) && hs::is_finite(wi) && hs::is_finite(u);
        // Finite raw values become unit vectors and numbers in [0, 1] (when they can).
        bool proper = false;
        if (finite) {
            const T lo = glm::length(wo), li = glm::length(wi);
            if (lo > T(1e-3) && lo < T(1e3) && li > T(1e-3) && li < T(1e3)) {
                wo /= lo;
                wi /= li;
                for (int c = 0; c < 4; ++c) u[c] = u[c] - std::floor(u[c]);
                proper = hs::is_finite(u);
            }
        }
        const hs::HairEvalPdf<T> e = fiber.eval_pdf(wo, wi);
        const V3 f = fiber.eval(wo, wi);
        const T pdf = fiber.pdf(wo, wi);
        const hs::HairSample<T> s = fiber.sample(wo, u);
        if (!finite) {
            // eval and pdf need wo and wi; sample needs wo and u.
            if (!(hs::is_finite(wo) && hs::is_finite(wi))) check(f == V3(T(0)) && pdf == T(0) && e.pdf == T(0));
            if (!(hs::is_finite(wo) && hs::is_finite(u))) check(s.pdf == T(0) && s.weight == V3(T(0)));
        } else if (proper) {
            check(hs::is_finite(f) && f.x >= T(0) && f.y >= T(0) && f.z >= T(0));
            check(hs::is_finite(pdf) && pdf >= T(0) && hs::is_finite(e.pdf));
            check(hs::is_finite(s.pdf) && s.pdf >= T(0) && hs::is_finite(s.weight) && hs::is_finite(s.wi));
            check(s.weight.x >= T(0) && s.weight.y >= T(0) && s.weight.z >= T(0));
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
    auto value = [&](T scale) {
        const T x = T(r.next());
        if (raw || !hs::is_finite(x)) return raw ? x : T(1);
        return scale * (x - std::floor(x));
    };
    const int lobes = keep_residual && !raw ? 3 : 4;
    for (int p = 0; p < lobes; ++p) c.gain[p] = value(T(3));
    for (int p = 0; p < lobes; ++p)
        for (int ch = 0; ch < 3; ++ch) c.tint[p][ch] = value(T(3));
    for (int p = 0; p < 3; ++p) {
        const T a = value(T(2) * hs::kMaxCuticleTilt<T>);
        c.alpha[p] = raw ? a : a - hs::kMaxCuticleTilt<T>;
    }
    c.alpha_override = raw ? unsigned(r.byte()) : unsigned(r.byte() & 7u);
    return c;
}

template <typename T> void run(int model, Reader& r, std::uint8_t control_mode) {
    if (model < 4) {
        hs::FiberParams<T> p;
        p.eta = T(r.next());
        p.beta_m = T(r.next());
        p.beta_n = T(r.next());
        p.alpha = T(r.next());
        p.sigma_a = glm::vec<3, T>(T(r.next()), T(r.next()), T(r.next()));
        const hs::LobeControls<T> c = read_controls<T>(r, control_mode);
        const bool valid = hs::validate(p).empty() && hs::validate(c).empty();
        try {
            if (model == 0) {
                const hs::ChiangMaterial<T> m(p, c);
                check(valid);
                T h = T(r.next());
                h = hs::is_finite(h) ? h - T(2) * std::floor(T(0.5) * h) - T(1) : T(0);  // into [-1, 1)
                exercise<T>(hs::ChiangFiber<T>(m, h), r);
            } else if (model == 1) {
                const hs::DeonFarFieldMaterial<T> m(p, 16, c);  // a fixed, small node count: speed
                check(valid);
                exercise<T>(hs::DeonFarFieldFiber<T>(m), r);
            } else {
                hs::TabulatedOptions o = model == 2 ? hs::TabulatedOptions::coarse() : hs::TabulatedOptions::fast();
                o.h_nodes = 8;
                o.phi_samples = 32;
                o.theta_samples = 8;
                o.m_rows = 16;
                o.m_nodes = 48;
                const hs::TabulatedMaterial<T> m(p, o, c);
                check(valid);
                exercise<T>(hs::TabulatedFiber<T>(m), r);
            }
        } catch (const std::invalid_argument&) {
            check(!valid);
        }
        return;
    }
    hs::MarschnerParams<T> p;
    p.eta = T(r.next());
    p.sigma_a = glm::vec<3, T>(T(r.next()), T(r.next()), T(r.next()));
    p.alpha_r = T(r.next());
    p.beta_r = T(r.next());
    p.beta_n = T(r.next());
    p.eccentricity = T(r.next());
    const hs::LobeControls<T> c = read_controls<T>(r, control_mode);
    const bool valid = hs::validate(p).empty() && hs::validate(c).empty() && !c.weighted(3);
    try {
        const hs::MarschnerMaterial<T> m(p, 3, c);
        check(valid);
        exercise<T>(hs::MarschnerFiber<T>(m), r);
    } catch (const std::invalid_argument&) {
        check(!valid);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    Reader r{data, size};
    const std::uint8_t sel = r.byte();
    const int model = (sel >> 1) % 5;
    const std::uint8_t control_mode = r.byte();
    if (sel & 1)
        run<double>(model, r, control_mode);
    else
        run<float>(model, r, control_mode);
    return 0;
}
