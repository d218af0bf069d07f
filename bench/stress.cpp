// stress — random and adversarial calls of every model in float and double (not CI; run by
// scripts/stress.sh, which writes docs/stress.md). Per model and precision it cycles over
// materials at the documented parameter limits and in between, and per call draws:
//   wo, wi: uniform on the sphere (most calls), or an edge direction — along the fiber axis
//           (±x exactly), within 1e-6 of it, grazing (x = 0), with a 1e-7 azimuthal part;
//   h (Chiang): uniform in [-1, 1], or exactly ±1 or 0;
//   u: uniform, or components at 0, 1 and 1 - ulp, and one call in 32 a component outside
//      [0, 1] (which every model clamps);
//   1 call in 64: one non-finite component (NaN, ±Inf) in wo, wi or u; 1 in 64 a finite
//      direction of another length (up to the largest float; the models normalise it).
// Chiang and the dual BCSDF also cycle through lobe gains far above 1 (up to 1e6).
// Counted: calls (each eval, pdf, eval_pdf and sample), NaN, Inf and negative values among
// f, pdf and the sample's weight, pdf and direction, non-finite inputs that do not give the
// zero result (contract), and sample/pdf/eval mismatches: a sample with pdf > 0 whose
// direction's pdf(wo, wi), or eval(wo, wi) against weight · pdf, differs by more than
// kRelTolerance (below); samples exactly on the fiber axis are counted (and compared like
// any other), and differences that moving wi by 4 ulps explains are counted apart as
// rounding (within_rounding).
//
//   stress [--calls N] [--slow-calls N] [--dual-calls N] [--only MODEL] [--seed S] [--out FILE]
//
// N (default 1e8) is the number of calls per fast model (Chiang, tabulated, tabulated fast())
// and precision; the far field and Marschner, 10–50× slower per call, get --slow-calls
// (default N / 10); the dual-scattering BCSDF over the Chiang fiber gets --dual-calls
// (default N). --only runs the models whose name contains MODEL. Prints one Markdown table
// row per (model, precision) and writes the table.
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <hairscatter/dual.hpp>
#include <hairscatter/hairscatter.hpp>

namespace hs = hairscatter;

namespace {

// xoshiro128+-style generator, cheap enough not to dominate a 100 ns model call.
struct Rng {
    std::uint64_t s;
    std::uint64_t next() {
        s += 0x9e3779b97f4a7c15ull;
        std::uint64_t z = s;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
    int below(int n) { return int(next() % std::uint64_t(n)); }
};

struct Counts {
    std::uint64_t calls = 0, nan = 0, inf = 0, negative = 0, mismatch = 0, contract = 0, pole = 0, ulp = 0;
    double max_rel_mismatch = 0;  // among the mismatches
};

// A sample's pdf and pdf(wo, its wi) (and its weight · pdf and eval(wo, wi)) agree when
// |Δ| ≤ 1e-4 · max, with an absolute floor far below any density a renderer could use. At
// the edges of a lobe's support and on steep narrow lobes the rounding of wi (float: 6e-8)
// moves them more; within_rounding counts that apart.
constexpr double kRelTolerance = 1e-4, kAbsTolerance = 1e-30;

template <typename T> void tally(Counts& c, T x) {
    if (x != x) {
        ++c.nan;
    } else if (!hs::is_finite(x)) {
        ++c.inf;
    } else if (x < T(0)) {
        ++c.negative;
    }
}
template <typename T> void tally(Counts& c, const glm::vec<3, T>& v) {
    for (int i = 0; i < 3; ++i) tally(c, v[i]);
}
// A direction may be negative; only NaN / Inf count.
template <typename T> void tally_dir(Counts& c, const glm::vec<3, T>& v) {
    for (int i = 0; i < 3; ++i) {
        if (v[i] != v[i])
            ++c.nan;
        else if (!hs::is_finite(v[i]))
            ++c.inf;
    }
}

template <typename T> glm::vec<3, T> sphere(Rng& r) {
    const double z = 2 * r.uniform() - 1, phi = 6.283185307179586 * r.uniform();
    const double s = std::sqrt(std::fmax(0.0, 1 - z * z));
    return glm::vec<3, T>(T(z), T(s * std::cos(phi)), T(s * std::sin(phi)));
}

template <typename T> glm::vec<3, T> direction(Rng& r) {
    const int k = r.below(16);
    if (k >= 6) return sphere<T>(r);
    const double sign = r.uniform() < 0.5 ? -1.0 : 1.0, phi = 6.283185307179586 * r.uniform();
    switch (k) {
        case 0: return glm::vec<3, T>(T(sign), T(0), T(0));  // along the axis
        case 1: {                                             // within 1e-6 of it
            const double e = 1e-6 * r.uniform();
            return glm::vec<3, T>(T(sign * std::sqrt(1 - e * e)), T(e * std::cos(phi)), T(e * std::sin(phi)));
        }
        case 2: return glm::vec<3, T>(T(0), T(std::cos(phi)), T(std::sin(phi)));  // grazing
        case 3: return glm::vec<3, T>(T(sign), T(1e-7), T(0));                     // unnormalised by 1e-14
        case 4: return glm::vec<3, T>(T(0), T(sign), T(0));
        default: return glm::vec<3, T>(T(0), T(0), T(sign));
    }
}

template <typename T> T unit_number(Rng& r) {
    switch (r.below(12)) {
        case 0: return T(0);
        case 1: return T(1);
        case 2: return T(1) - std::numeric_limits<T>::epsilon() / T(2);  // 1 - ulp
        default: return T(r.uniform());
    }
}

template <typename T> T poison(Rng& r) {
    switch (r.below(3)) {
        case 0: return std::numeric_limits<T>::quiet_NaN();
        case 1: return std::numeric_limits<T>::infinity();
        default: return -std::numeric_limits<T>::infinity();
    }
}

// The sample's values (pdf, and f = weight · pdf where known) lie within the tolerance of
// the range that eval_pdf takes when wi moves by up to 4 ulps of 1 along each axis: where the
// density is steep (the edge of a narrow lobe's support, φ = ±π with β_n = 1e-3: 100 per
// radian), the rounding of the sampled angles into wi moves them by more than the
// tolerance; that is rounding, not a mismatch.
template <typename T> struct Back {
    double v[4];  // pdf, then f's three channels (has_f)
    bool has_f;
};
template <typename T, typename BackAt>
bool within_rounding(const BackAt& back_at, const glm::vec<3, T>& wi, const Back<T>& want) {
    using V3 = glm::vec<3, T>;
    const T e = T(4) * std::numeric_limits<T>::epsilon();
    double lo[4], hi[4];
    for (int k = 0; k < 4; ++k) lo[k] = std::numeric_limits<double>::max(), hi[k] = -lo[k];
    auto probe = [&](const V3& w) {
        const Back<T> b = back_at(glm::normalize(w));
        for (int k = 0; k < 4; ++k) lo[k] = std::fmin(lo[k], b.v[k]), hi[k] = std::fmax(hi[k], b.v[k]);
    };
    for (int axis = 0; axis < 3; ++axis)
        for (T sign : {T(-1), T(1)}) {
            V3 w = wi;
            w[axis] += sign * e;
            probe(w);
        }
    // Between those corners too, in the fiber's inclination (x) and azimuth (a rotation
    // about x by up to the angle 4 ulps subtend): the sampler's exact value can sit on a
    // lobe's peak, which no corner of the box reaches.
    const double rho = std::sqrt(double(wi.y) * double(wi.y) + double(wi.z) * double(wi.z));
    for (int j = -8; j <= 8; ++j) {
        const double t = double(j) / 8.0;
        V3 w = wi;
        w.x += T(t) * e;
        probe(w);
        if (rho > 0) {
            const double a = t * double(e) / rho, c = std::cos(a), sn = std::sin(a);
            probe(V3(wi.x, T(c * double(wi.y) - sn * double(wi.z)), T(sn * double(wi.y) + c * double(wi.z))));
        }
    }
    for (int k = 0; k < (want.has_f ? 4 : 1); ++k)
        if (!(want.v[k] >= lo[k] * (1 - kRelTolerance) - kAbsTolerance && want.v[k] <= hi[k] * (1 + kRelTolerance) + kAbsTolerance))
            return false;
    return true;
}

// The inputs of one round: wo, wi, u, and in 1 call of 64 one non-finite component.
template <typename T> struct Inputs {
    glm::vec<3, T> wo, wi;
    glm::vec<4, T> u;
    bool bad;
};
template <typename T> Inputs<T> inputs(Rng& r) {
    Inputs<T> in{direction<T>(r), direction<T>(r), {}, false};
    for (int k = 0; k < 4; ++k) in.u[k] = unit_number<T>(r);
    if (r.below(32) == 0) in.u[r.below(4)] = r.below(2) ? T(2) : T(-1);  // outside [0, 1]: clamped
    if (r.below(64) == 0) {  // another length, finite: normalised
        const T scales[4] = {std::numeric_limits<T>::max(), T(3), T(1e-3), T(1e-30)};
        const T s = scales[r.below(4)];
        glm::vec<3, T>& w = r.below(2) ? in.wo : in.wi;
        const T m = std::fmax(std::fabs(w.x), std::fmax(std::fabs(w.y), std::fabs(w.z)));
        w *= s / m;
    }
    in.bad = r.below(64) == 0;
    if (in.bad) {
        const int which = r.below(10);
        if (which < 3)
            in.wo[which] = poison<T>(r);
        else if (which < 6)
            in.wi[which - 3] = poison<T>(r);
        else
            in.u[which - 6] = poison<T>(r);
    }
    return in;
}

// A sample's direction, pdf and (has_f) f = weight · pdf: NaN, Inf and negative values
// counted; a sample exactly on the fiber axis (u.y at 0 or 1 puts sinθi at ±1) is counted
// in `pole` and compared like any other (its azimuth is the one pdf(wo, wi) reads there);
// its values are compared with back_at(wi). within_rounding() is asked only when they
// differ (it costs six more calls).
template <typename T, typename BackAt>
void check_sample(Counts& c, const glm::vec<3, T>& wi, T pdf, const glm::vec<3, T>& weight, bool has_f, const BackAt& back_at) {
    tally(c, pdf);
    tally_dir(c, wi);
    if (wi.y == T(0) && wi.z == T(0)) ++c.pole;
    if (!(pdf > T(0) && hs::is_finite(pdf) && hs::is_finite(wi))) return;
    ++c.calls;
    const Back<T> b = back_at(wi);
    Back<T> want{{double(pdf), double(weight.x) * double(pdf), double(weight.y) * double(pdf), double(weight.z) * double(pdf)}, has_f};
    double worst = 0;
    for (int k = 0; k < (has_f ? 4 : 1); ++k) {
        const double diff = std::fabs(b.v[k] - want.v[k]), scale = std::fmax(std::fabs(b.v[k]), std::fabs(want.v[k]));
        if (diff > kRelTolerance * scale + kAbsTolerance) worst = std::fmax(worst, diff / scale);
    }
    if (worst == 0) return;
    if (within_rounding(back_at, wi, want)) {
        ++c.ulp;
    } else {
        ++c.mismatch;
        if (worst > c.max_rel_mismatch) c.max_rel_mismatch = worst;
    }
}

// One round of calls on one fiber: eval_pdf, eval, pdf, sample and the pdf of the sample.
template <typename T, typename Fiber> void round(const Fiber& fiber, Rng& r, Counts& c) {
    using V3 = glm::vec<3, T>;
    const Inputs<T> in = inputs<T>(r);
    const V3 &wo = in.wo, &wi = in.wi;
    const glm::vec<4, T>& u = in.u;
    const bool bad = in.bad;
    const hs::HairEvalPdf<T> e = fiber.eval_pdf(wo, wi);
    const V3 f = fiber.eval(wo, wi);
    const T pdf = fiber.pdf(wo, wi);
    const hs::HairSample<T> s = fiber.sample(wo, u);
    c.calls += 4;
    if (bad) {
        const bool wi_bad = !hs::is_finite(wi), uo_bad = !hs::is_finite(wo) || !hs::is_finite(u);
        bool ok = true;
        if (wi_bad || !hs::is_finite(wo)) ok = ok && e.f == V3(T(0)) && e.pdf == T(0) && f == V3(T(0)) && pdf == T(0);
        if (uo_bad) ok = ok && s.pdf == T(0) && s.weight == V3(T(0));
        if (!ok) ++c.contract;
        return;
    }
    tally(c, e.f);
    tally(c, e.pdf);
    tally(c, f);
    tally(c, pdf);
    tally(c, s.weight);
    check_sample(c, s.wi, s.pdf, s.weight, true, [&](const V3& w) {
        const hs::HairEvalPdf<T> ep = fiber.eval_pdf(wo, w);
        return Back<T>{{double(ep.pdf), double(ep.f.x), double(ep.f.y), double(ep.f.z)}, true};
    });
}

// A light state for the dual-scattering BCSDF: documented values (direct fraction in
// [0, 1], counts from 0 to far beyond any hair, kUnbounded, a renderer's own T_f and σ̄²_f)
// and, one call in 16, a NaN, negative or infinite field, which must still give a finite,
// non-negative value (dual/settings.hpp: the BCSDF clamps what a density source reports).
template <typename T> hs::DualScatteringLight<T> light_state(Rng& r) {
    hs::DualScatteringLight<T> l;
    const T df[4] = {T(0), T(1), T(0.5), T(r.uniform())};
    l.direct_fraction = df[r.below(4)];
    const T counts[6] = {T(0), T(20 * r.uniform()), T(1e-9), T(1e7), T(1e30), hs::kUnbounded<T>};
    l.n = counts[r.below(6)];
    l.beyond = counts[r.below(6)];
    if (r.below(4) == 0) {
        l.use_transmittance = true;
        l.T_f = glm::vec<3, T>(T(r.uniform()), T(0), T(1));
        l.sigma2_f = counts[r.below(5)];
    }
    if (r.below(16) == 0) {
        const T bad[4] = {std::numeric_limits<T>::quiet_NaN(), T(-1), -hs::kUnbounded<T>, hs::kUnbounded<T>};
        const T v = bad[r.below(4)];
        switch (r.below(6)) {
            case 0: l.direct_fraction = v; break;
            case 1: l.n = v; break;
            case 2: l.beyond = v; break;
            case 3: l.T_f.y = v; break;
            case 4: l.sigma2_f = v; break;
            default: l.use_transmittance = true, l.T_f = glm::vec<3, T>(v); break;
        }
    }
    return l;
}

// One round of calls on the dual-scattering BCSDF: eval under a light state, pdf, sample
// through at(wo, spread) with a spread hint, and the pdf of the sample at the same hint.
template <typename T, typename Dual> void dual_round(const Dual& dual, Rng& r, Counts& c) {
    using V3 = glm::vec<3, T>;
    const auto [wo, wi, u, bad] = inputs<T>(r);
    const hs::DualScatteringLight<T> light = light_state<T>(r);
    const T hints[6] = {T(0), T(0), T(0.05 * r.uniform()), T(1), T(1e6), hs::kUnbounded<T>};
    T spread = hints[r.below(6)];
    if (r.below(64) == 0) spread = poison<T>(r);  // a broken hint: still a valid density
    const V3 f = dual.eval(wo, wi, light);
    const T pdf = dual.pdf(wo, wi);
    const auto at = dual.at(wo, spread);
    const hs::DualSample<T> s = at.sample(u);
    c.calls += 3;
    if (bad) {
        bool ok = true;
        if (!hs::is_finite(wi) || !hs::is_finite(wo)) ok = ok && f == V3(T(0)) && pdf == T(0);
        if (!hs::is_finite(wo) || !hs::is_finite(u)) ok = ok && s.pdf == T(0);
        if (!ok) ++c.contract;
        return;
    }
    tally(c, f);
    tally(c, pdf);
    // The sampler's pdf is at.pdf of its direction by construction; the comparison checks
    // that this holds on every path. (Its value needs a light state: not compared.)
    check_sample(c, s.wi, s.pdf, V3(T(0)), false,
                 [&](const V3& w) { return Back<T>{{double(at.pdf(w)), 0.0, 0.0, 0.0}, false}; });
}

// The parameter sets every model cycles through: defaults, both roughnesses at the lower
// limit, at 1, one at each end, the extreme tilts, no and strong absorption, η near 1 and 3.
template <typename T> std::vector<hs::FiberParams<T>> fiber_params() {
    const T lo = hs::kMinRoughness<T>;
    std::vector<hs::FiberParams<T>> v;
    auto add = [&](T bm, T bn, T alpha, T sigma, T eta) {
        hs::FiberParams<T> p;
        p.beta_m = bm;
        p.beta_n = bn;
        p.alpha = alpha;
        p.sigma_a = glm::vec<3, T>(sigma, T(0.5) * sigma, T(2) * sigma);
        p.eta = eta;
        v.push_back(p);
    };
    const T tilt = hs::kMaxCuticleTilt<T>;
    add(T(0.3), T(0.3), hs::radians(T(2)), T(0.5), T(1.55));
    add(lo, lo, hs::radians(T(2)), T(0.5), T(1.55));
    add(T(1), T(1), T(0), T(0), T(1.55));
    add(lo, T(1), tilt, T(0.2), T(1.55));
    add(T(1), lo, -tilt, T(2), T(1.55));
    add(T(0.05), T(0.1), tilt, T(0), T(1.0001));
    add(T(0.3), T(0.05), T(0), T(50), T(3));
    add(T(0.7), T(0.9), -tilt, T(1e-3), T(1.2));
    return v;
}

template <typename T> std::vector<hs::MarschnerParams<T>> marschner_params() {
    const T lo = hs::kMinRoughness<T>;
    std::vector<hs::MarschnerParams<T>> v;
    hs::MarschnerParams<T> p;
    p.sigma_a = glm::vec<3, T>(T(0.5), T(0.3), T(0.2));
    v.push_back(p);
    p.beta_r = hs::kMinMarschnerWidth<T>;
    p.beta_n = lo;
    v.push_back(p);
    p.beta_r = hs::kMaxMarschnerWidth<T>;
    p.beta_n = T(1);
    p.alpha_r = hs::kMaxMarschnerShift<T>;
    v.push_back(p);
    p = hs::MarschnerParams<T>();
    p.eccentricity = T(0.85);
    p.caustic_gain = T(5);
    p.alpha_r = -hs::kMaxMarschnerShift<T>;
    v.push_back(p);
    p.eta = T(1.0001);
    p.sigma_a = glm::vec<3, T>(T(40));
    v.push_back(p);
    return v;
}

struct Row {
    std::string model, precision;
    Counts c;
    double seconds;
    int materials;
};

// --only: run just the models whose name contains this text (timing a model alone).
std::string g_only;

template <typename T, typename MakeRound>
Row run(const char* model, std::uint64_t calls, int materials, std::uint64_t seed, const MakeRound& per_material) {
    Row row{model, sizeof(T) == 4 ? "float" : "double", {}, 0, materials};
    if (std::string(model).find(g_only) == std::string::npos) return row;
    Rng r{seed};
    const auto t0 = std::chrono::steady_clock::now();
    for (int m = 0; m < materials; ++m) {
        const std::uint64_t target = calls * std::uint64_t(m + 1) / std::uint64_t(materials);
        per_material(m, [&](auto&& one_round) {
            while (row.c.calls < target) one_round(r, row.c);
        });
    }
    row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::fprintf(stderr, "%-18s %-6s %12" PRIu64 " calls  %6.1f s\n", model, row.precision.c_str(), row.c.calls,
                 row.seconds);
    return row;
}

// Lobe gains far above 1 (docs/controls.md: the multiple-scattering sums cap them), on
// the extra materials of Chiang and the dual BCSDF: k = 0 every gain at the limit 1e6, 1 a
// TT gain of 100 with R off and TRT at 10, both over fiber_params' lossless set (index 2).
template <typename T> hs::LobeControls<T> large_gains(int k) {
    hs::LobeControls<T> c;
    if (k == 0) {
        for (T& g : c.gain) g = hs::kMaxLobeGain<T>;
    } else {
        c.gain[0] = T(0);
        c.gain[1] = T(100);
        c.gain[2] = T(10);
    }
    return c;
}
constexpr int kGainSets = 2;

template <typename T>
void models(std::vector<Row>& rows, std::uint64_t calls, std::uint64_t slow, std::uint64_t dual, std::uint64_t seed) {
    const auto fp = fiber_params<T>();
    const int nf = int(fp.size());
    // (m ≥ nf: the large gains over the lossless parameters.)
    auto chiang = [&](int m) {
        return m < nf ? hs::ChiangMaterial<T>(fp[std::size_t(m)]) : hs::ChiangMaterial<T>(fp[2], large_gains<T>(m - nf));
    };
    rows.push_back(run<T>("Chiang", calls, nf + kGainSets, seed + 1, [&](int m, auto&& loop) {
        const hs::ChiangMaterial<T> mat = chiang(m);
        loop([&](Rng& r, Counts& c) {
            const int k = r.below(8);
            const T h = k == 0 ? T(1) : k == 1 ? T(-1) : k == 2 ? T(0) : T(2 * r.uniform() - 1);
            round<T>(hs::ChiangFiber<T>(mat, h), r, c);
        });
    }));
    rows.push_back(run<T>("tabulated", calls, nf, seed + 2, [&](int m, auto&& loop) {
        const hs::TabulatedMaterial<T> mat(fp[std::size_t(m)]);
        const hs::TabulatedFiber<T> fiber(mat);
        loop([&](Rng& r, Counts& c) { round<T>(fiber, r, c); });
    }));
    rows.push_back(run<T>("tabulated fast()", calls, nf, seed + 3, [&](int m, auto&& loop) {
        const hs::TabulatedMaterial<T> mat(fp[std::size_t(m)], hs::TabulatedOptions::fast());
        const hs::TabulatedFiber<T> fiber(mat);
        loop([&](Rng& r, Counts& c) { round<T>(fiber, r, c); });
    }));
    rows.push_back(run<T>("far field", slow, nf, seed + 4, [&](int m, auto&& loop) {
        const hs::DeonFarFieldMaterial<T> mat(fp[std::size_t(m)]);
        const hs::DeonFarFieldFiber<T> fiber(mat);
        loop([&](Rng& r, Counts& c) { round<T>(fiber, r, c); });
    }));
    // Dual scattering over the Chiang fiber (h as above), the tables of each material, the
    // improved formulation on even materials and Zinke 2008's on odd ones.
    rows.push_back(run<T>("dual (Chiang)", dual, nf + kGainSets, seed + 6, [&](int m, auto&& loop) {
        const hs::ChiangMaterial<T> mat = chiang(m);
        hs::DualTableOptions<T> o;
        o.settings = m % 2 ? hs::DualScatteringSettings<T>::zinke2008() : hs::DualScatteringSettings<T>::improved();
        const auto tables = hs::DualScatteringTables<T>::template build<hs::ChiangFiber<T>>(mat, o);
        loop([&](Rng& r, Counts& c) {
            const int k = r.below(8);
            const T h = k == 0 ? T(1) : k == 1 ? T(-1) : k == 2 ? T(0) : T(2 * r.uniform() - 1);
            dual_round<T>(hs::DualScatteringBcsdf<hs::ChiangFiber<T>>(hs::ChiangFiber<T>(mat, h), tables), r, c);
        });
    }));
    const auto mp = marschner_params<T>();
    rows.push_back(run<T>("Marschner", slow, int(mp.size()), seed + 5, [&](int m, auto&& loop) {
        const hs::MarschnerMaterial<T> mat(mp[std::size_t(m)]);
        const hs::MarschnerFiber<T> fiber(mat);
        loop([&](Rng& r, Counts& c) { round<T>(fiber, r, c); });
    }));
}

}  // namespace

int main(int argc, char** argv) {
    std::uint64_t calls = 100000000, slow = 0, dual = 0, seed = 1;
    std::string out;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> const char* {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "stress: %s needs a value\n", a.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--calls")
            calls = std::uint64_t(std::atof(value()));
        else if (a == "--slow-calls")
            slow = std::uint64_t(std::atof(value()));
        else if (a == "--dual-calls")
            dual = std::uint64_t(std::atof(value()));
        else if (a == "--only")
            g_only = value();
        else if (a == "--seed")
            seed = std::uint64_t(std::atoll(value()));
        else if (a == "--out")
            out = value();
        else {
            std::fprintf(stderr, "usage: stress [--calls N] [--slow-calls N] [--dual-calls N] [--only MODEL] [--seed S] "
                                 "[--out FILE]\n");
            return 2;
        }
    }
    if (slow == 0) slow = calls / 10;
    if (dual == 0) dual = calls;
    std::vector<Row> all, rows;
    models<float>(all, calls, slow, dual, seed);
    models<double>(all, calls, slow, dual, seed + 100);
    for (const Row& w : all)
        if (w.c.calls > 0) rows.push_back(w);

    std::string table =
        "| model | precision | materials | calls | NaN | Inf | negative | non-finite input not 0 | sample/pdf "
        "mismatch | largest mismatch (relative) | within 4 ulps of wi | samples on the axis | seconds |\n"
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    std::uint64_t failures = 0;
    for (const Row& w : rows) {
        char line[512];
        std::snprintf(line, sizeof line,
                      "| %s | %s | %d | %" PRIu64 " | %" PRIu64 " | %" PRIu64 " | %" PRIu64 " | %" PRIu64 " | %" PRIu64
                      " | %.2g | %" PRIu64 " | %" PRIu64 " | %.1f |\n",
                      w.model.c_str(), w.precision.c_str(), w.materials, w.c.calls, w.c.nan, w.c.inf, w.c.negative,
                      w.c.contract, w.c.mismatch, w.c.max_rel_mismatch, w.c.ulp, w.c.pole, w.seconds);
        table += line;
        failures += w.c.nan + w.c.inf + w.c.negative + w.c.contract + w.c.mismatch;
    }
    std::fputs(table.c_str(), stdout);
    if (!out.empty()) {
        std::FILE* f = std::fopen(out.c_str(), "w");
        if (!f || std::fputs(table.c_str(), f) < 0 || std::fclose(f) != 0) {
            std::fprintf(stderr, "stress: cannot write %s\n", out.c_str());
            return 2;
        }
    }
    std::printf("stress: %" PRIu64 " failures\n", failures);
    return failures == 0 ? 0 : 1;
}
