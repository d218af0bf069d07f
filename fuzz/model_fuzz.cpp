// libFuzzer target: parameters → material → eval / pdf / sample for the Chiang, far-field,
// tabulated and Marschner models, float and double (Huang's and the dual BCSDF's are
// bcsdf_fuzz.cpp). The bytes choose the model, the precision, the parameters (raw floats:
// any value, NaN and Inf included), the lobe controls (raw floats, or mapped into [0, 3) and
// ±π/8 so that valid ones are common), wo, wi and u. Checked: validate() never throws, and a
// material is built exactly when it returns "" for the parameters and the controls
// (Marschner: and no residual gain or tint); then the contract's calls and their checks
// (fuzz_support.hpp). A violation aborts (libFuzzer reports it with the input).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include <hairscatter/hairscatter.hpp>

#include "fuzz_support.hpp"

namespace hs = hairscatter;

namespace {

using fuzz::check;
using fuzz::exercise;
using fuzz::read_controls;
using fuzz::Reader;

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
                exercise<T>(hs::ChiangFiber<T>(m, r.offset<T>()), r);
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
