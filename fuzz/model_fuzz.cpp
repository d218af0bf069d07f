// libFuzzer target: parameters → material → eval / pdf / sample for every model, float and
// double. The bytes choose the model, the precision, the parameters (raw floats: any value,
// NaN and Inf included), wo, wi and u. Checked:
//   - validate() never throws, and a material is built exactly when it returns "";
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

template <typename T> void run(int model, Reader& r) {
    if (model < 4) {
        hs::FiberParams<T> p;
        p.eta = T(r.next());
        p.beta_m = T(r.next());
        p.beta_n = T(r.next());
        p.alpha = T(r.next());
        p.sigma_a = glm::vec<3, T>(T(r.next()), T(r.next()), T(r.next()));
        const bool valid = hs::validate(p).empty();
        try {
            if (model == 0) {
                const hs::ChiangMaterial<T> m(p);
                check(valid);
                T h = T(r.next());
                h = hs::is_finite(h) ? h - T(2) * std::floor(T(0.5) * h) - T(1) : T(0);  // into [-1, 1)
                exercise<T>(hs::ChiangFiber<T>(m, h), r);
            } else if (model == 1) {
                const hs::DeonFarFieldMaterial<T> m(p, 16);  // a fixed, small node count: speed
                check(valid);
                exercise<T>(hs::DeonFarFieldFiber<T>(m), r);
            } else {
                hs::TabulatedOptions o = model == 2 ? hs::TabulatedOptions::coarse() : hs::TabulatedOptions::fast();
                o.h_nodes = 8;
                o.phi_samples = 32;
                o.theta_samples = 8;
                o.m_rows = 16;
                o.m_nodes = 48;
                const hs::TabulatedMaterial<T> m(p, o);
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
    const bool valid = hs::validate(p).empty();
    try {
        const hs::MarschnerMaterial<T> m(p, 3);
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
    if (sel & 1)
        run<double>(model, r);
    else
        run<float>(model, r);
    return 0;
}
