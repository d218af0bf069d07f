// How light crosses a slab of explicit parallel fibers, against the 1D stack that dual
// scattering's two-stream estimator uses (docs/theory.md §5.7, "What it approximates").
//
// A beam at normal incidence (perpendicular to the fibers and to the slab) enters a laterally
// periodic slab of non-overlapping fibers (tests/support/fiber_slab.hpp, packing fraction
// about 0.2) and is path-traced with the Chiang fiber at the true h of every hit until it
// leaves; the power leaving through the far face is the slab's transmittance T, through the
// near face its reflectance R. Printed beside them: the 1D stack's T_N and R_N (the adding
// formula of dual/tables.hpp with the tables' a_f and a_b at θ = 0) at the mean count N of
// the beam's straight rays, the same averaged over a Poisson distribution of counts, and the
// forward lobe's azimuthal variance about straight ahead (what spreads the beam in the plane
// of the section). Last, the longitudinal spread of the reflected light: the power-weighted
// variance of the angle its exit direction makes with the fibers' normal plane (the beam
// arrives at θ = 0, so this is how far multiple scattering spreads it in θ), beside the
// variance the two-stream estimator gives its back kernel for the same stack (dual_streams'
// spread_b at N fibers along the arrival and none behind, dual/two_stream.hpp) and the
// reflected light's mean number of events, split into forward (|φ| > π/2) and backward ones.
//
//     slab_transmission_tool [--melanin M] [--paths P] [--seed S]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>

#include "../support/fiber_slab.hpp"

namespace {

namespace hs = hairscatter;
using slab::dvec3;
constexpr double kPi = 3.14159265358979323846;

struct Options {
    double melanin = 0.3;  // eumelanin concentration (the study's blond)
    int paths = 20000;
    unsigned seed = 11;
};

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const char* v = i + 1 < argc ? argv[i + 1] : nullptr;
        if (a == "--melanin" && v) o.melanin = std::atof(v), ++i;
        else if (a == "--paths" && v) o.paths = std::atoi(v), ++i;
        else if (a == "--seed" && v) o.seed = unsigned(std::atoi(v)), ++i;
        else {
            std::fprintf(stderr, "usage: slab_transmission_tool [--melanin M >= 0] [--paths P > 0] [--seed S]\n");
            std::exit(2);
        }
    }
    if (!(o.melanin >= 0) || !(o.paths > 0)) {
        std::fprintf(stderr, "slab_transmission_tool: --melanin must be >= 0 and --paths > 0\n");
        std::exit(2);
    }
    return o;
}

// The forward half's azimuthal variance about straight through (φ = π), and the backward
// half's about φ = 0, per unit of weight, red channel: sampled over h and the fiber's sampler.
void azimuthal_variances(const hs::ChiangMaterial<double>& mat, double& var_f, double& var_b) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> U;
    double wf = 0, wb = 0;
    var_f = var_b = 0;
    const dvec3 wo(0, 0, 1);  // in the normal plane
    for (int k = 0; k < 200000; ++k) {
        const hs::ChiangFiber<double> fiber(mat, 2 * U(rng) - 1);
        const auto smp = fiber.sample(wo, slab::draw4(U, rng));
        if (!(smp.pdf > 0)) continue;
        const double phi = std::atan2(smp.wi.z, smp.wi.y) - std::atan2(wo.z, wo.y);
        const double through = std::remainder(phi - kPi, 2 * kPi), back = std::remainder(phi, 2 * kPi);
        if (std::abs(through) < 0.5 * kPi) var_f += smp.weight.x * through * through, wf += smp.weight.x;
        else var_b += smp.weight.x * back * back, wb += smp.weight.x;
    }
    var_f = wf > 0 ? var_f / wf : 0;
    var_b = wb > 0 ? var_b / wb : 0;
}

}  // namespace

int main(int argc, char** argv) {
    const Options opt = parse(argc, argv);
    hs::FiberParams<double> p;
    p.sigma_a = hs::sigma_a_from_concentrations(opt.melanin, 0.0);
    const hs::ChiangMaterial<double> mat(p);
    const auto tables = hs::DualScatteringTables<double>::build<hs::ChiangFiber<double>>(mat, hs::DualTableOptions<double>{});
    const auto e = tables.view().lookup(0.0);
    double var_f, var_b;
    azimuthal_variances(mat, var_f, var_b);
    std::printf("melanin %g: a_f %.3f %.3f %.3f, a_b %.3f %.3f %.3f (θ = 0); azimuthal variance per event (red): "
                "forward %.3f rad² (σ %.2f), backward %.3f rad²\n",
                opt.melanin, e.a_f.x, e.a_f.y, e.a_f.z, e.a_b.x, e.a_b.y, e.a_b.z, var_f, std::sqrt(var_f), var_b);
    std::printf("| N | slab T (R, G, B) | 1D T_N | 1D, Poisson counts | slab R | 1D R_N | events of transmitted light "
                "| reflected light's θ variance: slab, back kernel (rad²) | its events, forward + backward |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|\n");
    for (const double tau : {1.0, 2.0, 5.0, 10.0, 20.0}) {
        const slab::FiberSlab s(400.0, 8.0 * tau + 2.0, tau, 7);
        std::mt19937_64 rng(opt.seed);
        std::uniform_real_distribution<double> U;
        dvec3 T(0), R(0);
        double count = 0, events = 0, events_w = 0;
        double r_w = 0, r_theta2 = 0, r_fwd = 0, r_back = 0;  // the reflected light's θ spread and events
        for (int k = 0; k < opt.paths; ++k) {
            dvec3 o(0, U(rng) * s.width(), -0.5), d(0, 0, 1), beta(1);
            count += s.count(o, d);
            int skip = -1, ev = 0, fwd = 0, back = 0;
            for (int depth = 0; depth < 100000; ++depth) {
                const slab::Hit h = s.intersect(o, d, skip);
                if (h.fiber < 0) {
                    if (d.z > 0) T += beta, events += ev * slab::mean(beta), events_w += slab::mean(beta);
                    else {
                        R += beta;
                        const double w = slab::mean(beta), th = std::asin(std::clamp(d.x, -1.0, 1.0));
                        r_w += w, r_theta2 += w * th * th, r_fwd += w * fwd, r_back += w * back;
                    }
                    break;
                }
                ++ev;
                const hs::FiberFrame<double> fr(dvec3(1, 0, 0), -d);
                const hs::ChiangFiber<double> fiber(mat, glm::dot(h.p - h.axis, fr.y));
                const auto smp = fiber.sample(fr.to_local(-d), slab::draw4(U, rng));
                if (!(smp.pdf > 0)) break;
                beta *= smp.weight;
                const dvec3 d_next = glm::normalize(fr.to_world(smp.wi));
                // Forward: the travel keeps its side in the plane of the section.
                (d_next.y * d.y + d_next.z * d.z > 0 ? fwd : back) += 1;
                d = d_next;
                o = h.p;
                skip = h.fiber;
                if (depth > 3) {  // Russian roulette
                    const double q = std::min(0.99, std::max({beta.x, beta.y, beta.z}));
                    if (U(rng) >= q) break;
                    beta /= q;
                }
            }
        }
        T /= double(opt.paths), R /= double(opt.paths);
        const double n = count / opt.paths;
        dvec3 T1, R1, TP(0);
        for (int c = 0; c < 3; ++c) {
            const auto st = hs::layered_stack(e.a_f[c], e.a_b[c], n);
            T1[c] = st.T_, R1[c] = st.R;
        }
        double pk = std::exp(-n);
        for (int k = 0; k < 400; ++k, pk *= n / k)
            for (int c = 0; c < 3; ++c) TP[c] += pk * hs::layered_stack(e.a_f[c], e.a_b[c], double(k)).T_;
        const double spread_b = hs::dual_streams(e, n, 0.0).spread_b;
        std::printf("| %.2f | %.3g, %.3g, %.3g | %.3g, %.3g, %.3g | %.3g, %.3g, %.3g | %.3f, %.3f, %.3f | %.3f, %.3f, %.3f | %.1f "
                    "| %.3f, %.3f | %.1f + %.1f |\n",
                    n, T.x, T.y, T.z, T1.x, T1.y, T1.z, TP.x, TP.y, TP.z, R.x, R.y, R.z, R1.x, R1.y, R1.z,
                    events_w > 0 ? events / events_w : 0.0, r_w > 0 ? r_theta2 / r_w : 0.0, spread_b,
                    r_w > 0 ? r_fwd / r_w : 0.0, r_w > 0 ? r_back / r_w : 0.0);
    }
    return 0;
}
