// Reference values for the Python module's tests (tests/python/test_reference.py): every model
// of the contract, in float and double, evaluated by plain C++ calls on fixed inputs, inputs
// and results printed as hexadecimal floats (%a) so that the test can feed the same inputs to
// the module and compare the results bit for bit.
//
// Each line: <case> <call> <values…>, where the values are the call's inputs, then its
// results:
//   eval    wo(3) wi(3) h   → eval(3) pdf
//   sample  wo(3) u(4) h    → wi(3) weight(3) pdf lobe
//   albedo  wo(3) h         → albedo(3)
//   split   wo(3) h centre  → a(4 × 3) backward(4)
//   dual    wo(3) wi(3) h   → eval(3) pdf      (the dual BCSDF, light state fixed below)
// The parameters of each case are written out below and in test_reference.py's CASES; the
// models take them as doubles rounded to T, as the module does.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <type_traits>

#include <hairscatter/dual.hpp>
#include <hairscatter/hairscatter.hpp>

namespace hs = hairscatter;

namespace {

constexpr int kRows = 48;

// A fixed sequence of uniform numbers in [0, 1) (64-bit LCG, top 53 bits).
struct Sequence {
    std::uint64_t state = 0x9E3779B97F4A7C15ull;
    double next() {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) * (1.0 / 9007199254740992.0);
    }
};

template <typename T> glm::vec<3, T> random_direction(Sequence& s) {
    const double z = 2 * s.next() - 1, phi = 2 * 3.141592653589793 * s.next(), r = std::sqrt(1 - z * z);
    return glm::vec<3, T>(T(z), T(r * std::cos(phi)), T(r * std::sin(phi)));
}

void put(double v) { std::printf(" %a", v); }
template <typename T> void put(const glm::vec<3, T>& v) {
    for (int k = 0; k < 3; ++k) put(double(v[k]));
}
template <typename T> void put(const glm::vec<4, T>& v) {
    for (int k = 0; k < 4; ++k) put(double(v[k]));
}

template <typename Fiber, typename Material> Fiber fiber_at(const Material& m, typename Fiber::Real h) {
    if constexpr (std::is_constructible_v<Fiber, const Material&, typename Fiber::Real>)
        return Fiber(m, h);
    else
        return Fiber(m);
}

template <typename Fiber, typename Material> void print_model(const char* name, const Material& material, bool dual) {
    using T = typename Fiber::Real;
    constexpr bool kNear = std::is_constructible_v<Fiber, const Material&, T>;
    Sequence s;
    for (int i = 0; i < kRows; ++i) {
        glm::vec<3, T> wo = random_direction<T>(s), wi = random_direction<T>(s);
        if (i == kRows - 1) wi = glm::vec<3, T>(std::numeric_limits<T>::infinity(), T(0), T(0));  // the contract's 0
        if (i == kRows - 2) wi = glm::vec<3, T>(T(0));
        const T h = kNear ? T(2 * s.next() - 1) : T(0);
        const glm::vec<4, T> u(T(s.next()), T(s.next()), T(s.next()), T(s.next()));
        const T centre = T(3.141592653589793 * s.next());
        const Fiber fiber = fiber_at<Fiber>(material, h);

        std::printf("%s eval", name);
        put(wo), put(wi), put(double(h));
        const glm::vec<3, T> f = fiber.eval(wo, wi);
        put(f), put(double(fiber.pdf(wo, wi)));
        std::printf("\n%s sample", name);
        put(wo), put(u), put(double(h));
        const hs::HairSample<T> smp = fiber.sample(wo, u);
        put(smp.wi), put(smp.weight), put(double(smp.pdf)), put(double(hs::lobe_index(smp.lobe)));
        std::printf("\n%s albedo", name);
        put(wo), put(double(h)), put(fiber.albedo(wo));
        std::printf("\n");
        if constexpr (hs::has_lobe_split_v<Fiber>) {
            if (i % 8 == 0) {  // Huang's lobe_split is a cubature of ~4·10³ evaluations
                std::printf("%s split", name);
                put(wo), put(double(h)), put(double(centre));
                const auto split = fiber.lobe_split(wo, centre);
                for (int p = 0; p < 4; ++p) put(split.a[p]);
                for (int p = 0; p < 4; ++p) put(double(split.backward[p]));
                std::printf("\n");
            }
        }
    }
    if constexpr (hs::has_lobe_split_v<Fiber>) {
        if (!dual) return;
        // Small tables (as test_reference.py builds them) and a partly shadowed point.
        hs::DualTableOptions<T> opt;
        opt.theta_samples = 16;
        opt.psi_samples = 9;
        opt.h_nodes = 8;
        const auto tables = hs::DualScatteringTables<T>::template build<Fiber>(material, opt);
        hs::DualScatteringLight<T> light;
        light.direct_fraction = T(0.25);
        light.n = T(2);
        light.beyond = T(3);
        Sequence d;
        for (int i = 0; i < kRows; ++i) {
            const glm::vec<3, T> wo = random_direction<T>(d), wi = random_direction<T>(d);
            const T h = kNear ? T(2 * d.next() - 1) : T(0);
            const hs::DualScatteringBcsdf<Fiber> bcsdf(fiber_at<Fiber>(material, h), tables);
            std::printf("%s dual", name);
            put(wo), put(wi), put(double(h)), put(bcsdf.eval(wo, wi, light)), put(double(bcsdf.pdf(wo, wi)));
            std::printf("\n");
        }
    }
}

template <typename T> hs::FiberParams<T> params(double eta, double beta_m, double beta_n, double alpha, glm::dvec3 sigma_a) {
    hs::FiberParams<T> p;
    p.eta = T(eta), p.beta_m = T(beta_m), p.beta_n = T(beta_n), p.alpha = T(alpha);
    p.sigma_a = glm::vec<3, T>(sigma_a);
    return p;
}

template <typename T> void print_all(const std::string& suffix) {
    const glm::dvec3 brown(0.6, 0.9, 1.6);
    const double alpha = 0.035;
    auto name = [&](const char* n) { return std::string(n) + suffix; };

    const hs::ChiangMaterial<T> chiang(params<T>(1.55, 0.3, 0.25, alpha, brown));
    print_model<hs::ChiangFiber<T>>(name("chiang").c_str(), chiang, true);
    print_model<hs::BasicChiangFiber<T, hs::LobeSet::kR | hs::LobeSet::kTT>>(name("chiang_r_tt").c_str(), chiang, false);

    hs::LobeControls<T> controls;
    controls.gain[0] = T(2);
    controls.tint[1] = glm::vec<3, T>(glm::dvec3(1.0, 0.55, 0.3));
    controls.override_alpha(2, T(0.05));
    const hs::DeonFarFieldMaterial<T> deon(params<T>(1.55, 0.35, 0.3, alpha, brown), 0, controls);
    print_model<hs::DeonFarFieldFiber<T>>(name("deon").c_str(), deon, true);

    const hs::TabulatedMaterial<T> tabulated(params<T>(1.55, 0.3, 0.3, alpha, brown), hs::TabulatedOptions::coarse());
    print_model<hs::TabulatedFiber<T>>(name("tabulated").c_str(), tabulated, false);

    hs::MarschnerParams<T> mp;
    mp.eta = T(1.55), mp.sigma_a = glm::vec<3, T>(brown), mp.alpha_r = T(-0.12), mp.beta_r = T(0.13);
    mp.beta_n = T(0.3), mp.eccentricity = T(0.9), mp.caustic_width = T(0.26), mp.caustic_gain = T(0.5);
    mp.caustic_fade = T(0.3), mp.caustic_dh_max = T(0.5);
    const hs::MarschnerMaterial<T> marschner(mp);
    print_model<hs::MarschnerFiber<T>>(name("marschner").c_str(), marschner, false);

    hs::HuangParams<T> hp;
    hp.eta = T(1.55), hp.roughness = T(0.3), hp.alpha = T(alpha), hp.sigma_a = glm::vec<3, T>(brown);
    hp.aspect_ratio = T(0.7), hp.orientation = T(0.4);
    hs::HuangQuadrature q;
    q.offset_nodes = 16, q.tt_points = 32, q.trt_per_tt = 2;
    const hs::HuangMaterial<T> huang(hp, q);
    print_model<hs::HuangFiber<T>>(name("huang").c_str(), huang, false);
}

}  // namespace

int main() {
    print_all<float>("_f32");
    print_all<double>("_f64");
    return 0;
}
