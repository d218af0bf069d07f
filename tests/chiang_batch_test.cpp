// ChiangBatch (models/chiang_batch.hpp): every result of a batch equals the one-hit call's,
// ChiangFiber<T>(material, h).eval(wo, wi) and so on: to the last bit where the compilers
// cannot contract products into FMAs, else within the relative bound kMaxRelative (the
// sampled lobe the same), over random hits with the extremes (h = ±1, grazing and axial
// directions, unnormalised lengths, u at and beyond 0 and 1), batch sizes around the block
// width, float and double, with and without lobe controls; and hostile input gives zeros or
// the empty sample where the one-hit calls do, and never NaN or Inf.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtx/string_cast.hpp>

#include <hairscatter/hairscatter.hpp>

namespace hs = hairscatter;

namespace {

// The bound the batch keeps against the one-hit calls, per component. Without FMA (x86-64
// up to v2) both are the same operations in the same order: equal to the last bit. Where
// the compilers may contract a product and a sum into an FMA (x86-64-v3, -march=native,
// ARM), they do so differently in the batch's loops across hits and in the one-hit code,
// and the last bit of an exponent's argument differs; an exponential multiplies that by
// the exponent: a sharp lobe (β_m = 0.02, 1/2v ≈ 2300) turns the one-ulp difference of
// d² (about 1e-7 of cos²) into a relative 3e-4 of M. There the bound is relative: 2e-3 in
// float, 1e-8 in double (a grazing h = 1 - 2^-53 measured 3e-9).
#if defined(__FMA__) || defined(__FP_FAST_FMAF) || defined(__aarch64__)
constexpr bool kContracts = true;
#else
constexpr bool kContracts = false;
#endif
template <typename T> constexpr double kMaxRelative = !kContracts ? 0.0 : sizeof(T) == 4 ? 2e-3 : 1e-8;

// Distance in units in the last place: the difference of the values' positions in the
// ordered sequence of representable numbers (0 and -0 are one position).
template <typename T> std::int64_t ulp_distance(T a, T b) {
    using Bits = std::conditional_t<sizeof(T) == 4, std::int32_t, std::int64_t>;
    auto ordered = [](T x) {
        Bits i;
        std::memcpy(&i, &x, sizeof i);
        return i < 0 ? std::int64_t(std::numeric_limits<Bits>::min()) - std::int64_t(i) : std::int64_t(i);
    };
    if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b) ? 0 : std::numeric_limits<std::int64_t>::max();
    const std::int64_t d = ordered(a) - ordered(b);
    return d < 0 ? -d : d;
}

template <typename T> struct Hits {
    std::vector<T> h, wo[3], wi[3], u[4];
    std::size_t size() const { return h.size(); }
    void add(T hh, glm::vec<3, T> o, glm::vec<3, T> i, glm::vec<4, T> uu) {
        h.push_back(hh);
        for (int c = 0; c < 3; ++c) wo[c].push_back(o[c]), wi[c].push_back(i[c]);
        for (int c = 0; c < 4; ++c) u[c].push_back(uu[c]);
    }
    glm::vec<3, T> wo_at(std::size_t k) const { return {wo[0][k], wo[1][k], wo[2][k]}; }
    glm::vec<3, T> wi_at(std::size_t k) const { return {wi[0][k], wi[1][k], wi[2][k]}; }
    glm::vec<4, T> u_at(std::size_t k) const { return {u[0][k], u[1][k], u[2][k], u[3][k]}; }
    hs::ChiangBatchQuery<T> query(std::size_t n) const {
        hs::ChiangBatchQuery<T> q;
        q.n = n;
        q.h = h.data();
        q.wo = {wo[0].data(), wo[1].data(), wo[2].data()};
        q.wi = {wi[0].data(), wi[1].data(), wi[2].data()};
        return q;
    }
    hs::ChiangBatchSampleQuery<T> sample_query(std::size_t n) const {
        hs::ChiangBatchSampleQuery<T> q;
        q.n = n;
        q.h = h.data();
        q.wo = {wo[0].data(), wo[1].data(), wo[2].data()};
        for (int c = 0; c < 4; ++c) q.u[c] = u[c].data();
        return q;
    }
};

template <typename T> glm::vec<3, T> sphere(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double z = 2.0 * u(rng) - 1.0, a = 6.283185307179586 * u(rng), r = std::sqrt(1.0 - z * z);
    return glm::vec<3, T>(T(z), T(r * std::cos(a)), T(r * std::sin(a)));
}

// Random hits, one in four with an extreme in h, wo, wi or u.
template <typename T> Hits<T> random_hits(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const T edge_h[] = {T(-1), T(1), T(0), T(-0.0), T(1.0001), T(-1.5), std::nextafter(T(1), T(0))};
    const glm::vec<3, T> edge_w[] = {{T(1), T(0), T(0)},        {T(-1), T(0), T(0)},
                                     {T(0.99999), T(0.004), T(0)}, {T(0), T(1), T(0)},
                                     {T(0), T(0), T(-1)},       {T(3), T(-4), T(12)},
                                     {T(1e-3), T(2e-3), T(0)},  {T(-0.9999999), T(0), T(1e-4)}};
    const T edge_u[] = {T(0), T(1), T(-0.25), T(1.5), std::nextafter(T(1), T(0)), T(1e-30)};
    Hits<T> hits;
    for (std::size_t k = 0; k < n; ++k) {
        T hh = T(2.0 * u(rng) - 1.0);
        glm::vec<3, T> wo = sphere<T>(rng), wi = sphere<T>(rng);
        glm::vec<4, T> uu(T(u(rng)), T(u(rng)), T(u(rng)), T(u(rng)));
        switch (rng() % 8) {
            case 0: hh = edge_h[rng() % 7]; break;
            case 1: wo = edge_w[rng() % 8]; break;
            case 2: wi = edge_w[rng() % 8]; break;
            case 3: uu[int(rng() % 4)] = edge_u[rng() % 6]; break;
            default: break;
        }
        hits.add(hh, wo, wi, uu);
    }
    return hits;
}

template <typename T> std::vector<hs::ChiangMaterial<T>> materials() {
    std::vector<hs::ChiangMaterial<T>> m;
    hs::FiberParams<T> p;
    p.eta = T(1.55), p.beta_m = T(0.3), p.beta_n = T(0.3), p.alpha = T(0.035);
    p.sigma_a = hs::sigma_a_from_concentrations(T(1.3), T(0.2));
    m.emplace_back(p);
    p.beta_m = T(0.02), p.beta_n = T(0.05), p.alpha = T(-0.1), p.sigma_a = glm::vec<3, T>(T(0));  // sharp, clear
    m.emplace_back(p);
    p.eta = T(1.0001), p.beta_m = T(1), p.beta_n = T(1), p.alpha = T(0.39), p.sigma_a = glm::vec<3, T>(T(40), T(0), T(3));
    m.emplace_back(p);
    hs::LobeControls<T> controls;  // gains and tints: the weighted path
    controls.gain[0] = T(2), controls.gain[2] = T(0);
    controls.tint[1] = glm::vec<3, T>(T(0.5), T(1), T(3));
    p.eta = T(1.55), p.beta_m = T(0.25), p.beta_n = T(0.4), p.alpha = T(0.05);
    p.sigma_a = hs::sigma_a_from_concentrations(T(0.4), T(0.8));
    m.emplace_back(p, controls);
    return m;
}

// The largest difference seen: in ulps where the values are equal up to the last bit,
// else relative.
template <typename T> struct Worst {
    double relative = 0.0;
    std::int64_t ulp = 0;
    const char* what = "";
    std::size_t differing = 0, compared = 0;
    void add(T batch, T one, const char* label = "eval_pdf_at") {
        const std::int64_t d = ulp_distance(batch, one);
        const double scale = std::fabs(double(one)) > 0.0 ? std::fabs(double(one)) : 1.0;
        const double r = d == 0 ? 0.0 : std::isfinite(double(batch)) ? std::fabs(double(batch) - double(one)) / scale : 1e300;
        if (d > ulp) ulp = d;
        if (r > relative) relative = r, what = label;
        differing += d != 0;
        ++compared;
    }
    bool ok() const { return relative <= kMaxRelative<T>; }
};

// Everything a batch computes for n hits, each array one longer than n and filled with a
// canary first (the batch must not write past n).
template <typename T> struct Results {
    static constexpr T kCanary = T(-7);
    std::vector<T> f[3], f2[3], pdf, pdf2, swi[3], sweight[3], spdf;
    std::vector<hs::SampledLobe> lobe;
    Results(const hs::ChiangBatch<T>& batch, const Hits<T>& hits, std::size_t n)
        : pdf(n + 1, kCanary), pdf2(n + 1, kCanary), spdf(n + 1, kCanary), lobe(n + 1, hs::SampledLobe::kUniform) {
        for (int c = 0; c < 3; ++c) {
            f[c].assign(n + 1, kCanary), f2[c].assign(n + 1, kCanary);
            swi[c].assign(n + 1, kCanary), sweight[c].assign(n + 1, kCanary);
        }
        batch.eval(hits.query(n), {f[0].data(), f[1].data(), f[2].data()});
        batch.pdf(hits.query(n), pdf.data());
        batch.eval_pdf(hits.query(n), {f2[0].data(), f2[1].data(), f2[2].data()}, pdf2.data());
        hs::ChiangBatchSamples<T> out;
        out.wi = {swi[0].data(), swi[1].data(), swi[2].data()};
        out.weight = {sweight[0].data(), sweight[1].data(), sweight[2].data()};
        out.pdf = spdf.data();
        out.lobe = lobe.data();
        batch.sample(hits.sample_query(n), out);
    }
};

template <typename T> void expect_batch_matches_one_hit(std::size_t n, unsigned seed) {
    const Hits<T> hits = random_hits<T>(n + 1, seed);
    Worst<T> worst;
    for (const hs::ChiangMaterial<T>& mat : materials<T>()) {
        const hs::ChiangBatch<T> batch(mat);
        const Results<T> r(batch, hits, n);
        const auto& [f, f2, pdf, pdf2, swi, sweight, spdf, lobe] = r;
        const T canary = Results<T>::kCanary;
        for (std::size_t k = 0; k < n; ++k) {
            const hs::ChiangFiber<T> fiber(mat, hits.h[k]);
            const glm::vec<3, T> e = fiber.eval(hits.wo_at(k), hits.wi_at(k));
            const T p = fiber.pdf(hits.wo_at(k), hits.wi_at(k));
            const hs::HairEvalPdf<T> ep = fiber.eval_pdf(hits.wo_at(k), hits.wi_at(k));
            const hs::HairSample<T> s = fiber.sample(hits.wo_at(k), hits.u_at(k));
            for (int c = 0; c < 3; ++c) {
                worst.add(f[c][k], e[c], "eval");
                worst.add(f2[c][k], ep.f[c], "eval_pdf f");
                worst.add(swi[c][k], s.wi[c], "sample wi");
                worst.add(sweight[c][k], s.weight[c], "sample weight");
            }
            worst.add(pdf[k], p, "pdf");
            worst.add(pdf2[k], ep.pdf, "eval_pdf pdf");
            worst.add(spdf[k], s.pdf, "sample pdf");
            ASSERT_EQ(int(lobe[k]), int(s.lobe)) << "hit " << k << " of " << n;
            ASSERT_TRUE(worst.ok()) << "hit " << k << " of " << n << ", h " << hits.h[k] << ": " << worst.what
                                    << " differs by " << worst.relative << " relative";
        }
        // Nothing written past n.
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(f[c][n], canary);
            EXPECT_EQ(swi[c][n], canary);
        }
        EXPECT_EQ(pdf[n], canary);
        EXPECT_EQ(spdf[n], canary);
        EXPECT_EQ(int(lobe[n]), int(hs::SampledLobe::kUniform));

        // One hit at a time (a GPU thread's call) gives the block's results.
        std::vector<T> g[3], q(n);
        for (int c = 0; c < 3; ++c) g[c].resize(n);
        for (std::size_t k = 0; k < n; ++k)
            batch.eval_pdf_at(hits.query(n), k, {g[0].data(), g[1].data(), g[2].data()}, q.data());
        for (std::size_t k = 0; k < n; ++k) {
            for (int c = 0; c < 3; ++c) worst.add(g[c][k], f2[c][k]);
            worst.add(q[k], pdf2[k]);
        }
        ASSERT_TRUE(worst.ok()) << worst.what << " differs by " << worst.relative << " relative";
    }
    ::testing::Test::RecordProperty("max_ulp", int(worst.ulp));
    ::testing::Test::RecordProperty("max_relative", std::to_string(worst.relative));
    ::testing::Test::RecordProperty("differing", int(worst.differing));
    ::testing::Test::RecordProperty("compared", int(worst.compared));
}

template <typename T> void expect_hostile_input_is_zero() {
    const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
    const T big = std::numeric_limits<T>::max(), tiny = std::numeric_limits<T>::denorm_min();
    const T values[] = {nan, inf, -inf, T(0), big, -big, tiny, T(1), T(-1), T(0.5)};
    std::mt19937 rng(7);
    Hits<T> hits;
    for (int k = 0; k < 2000; ++k) {
        auto pick = [&] { return values[rng() % 10]; };
        hits.add(pick(), {pick(), pick(), pick()}, {pick(), pick(), pick()}, {pick(), pick(), pick(), pick()});
    }
    const std::size_t n = hits.size();
    for (const hs::ChiangMaterial<T>& mat : materials<T>()) {
        const Results<T> r(hs::ChiangBatch<T>(mat), hits, n);
        const auto& [f, f2, pdf, pdf2, swi, sweight, spdf, lobe] = r;
        (void)f2, (void)pdf2;
        Worst<T> worst;
        for (std::size_t k = 0; k < n; ++k) {
            const hs::ChiangFiber<T> fiber(mat, hits.h[k]);
            const hs::HairEvalPdf<T> ep = fiber.eval_pdf(hits.wo_at(k), hits.wi_at(k));
            const hs::HairSample<T> s = fiber.sample(hits.wo_at(k), hits.u_at(k));
            for (int c = 0; c < 3; ++c) {
                ASSERT_TRUE(std::isfinite(f[c][k]) && std::isfinite(swi[c][k]) && std::isfinite(sweight[c][k])) << k;
                worst.add(f[c][k], ep.f[c], "eval_pdf f");
                worst.add(swi[c][k], s.wi[c], "sample wi");
                worst.add(sweight[c][k], s.weight[c], "sample weight");
            }
            ASSERT_TRUE(std::isfinite(pdf[k]) && std::isfinite(spdf[k])) << k;
            worst.add(pdf[k], ep.pdf, "eval_pdf pdf");
            worst.add(spdf[k], s.pdf, "sample pdf");
            // The invalid hits: zeros and the empty sample, in every build.
            glm::vec<3, T> wo = hits.wo_at(k), wi = hits.wi_at(k);
            glm::vec<4, T> u = hits.u_at(k);
            if (!hs::unit_directions(wo, wi)) {
                ASSERT_TRUE(pdf[k] == T(0) && f[0][k] == T(0) && f[1][k] == T(0) && f[2][k] == T(0)) << k;
            }
            wo = hits.wo_at(k);
            const bool sample_valid = hs::unit_direction_and_numbers(wo, u);
            ASSERT_EQ(sample_valid, lobe[k] != hs::SampledLobe::kNone) << k;
            if (!sample_valid) {
                for (int c = 0; c < 3; ++c) ASSERT_TRUE(swi[c][k] == T(0) && sweight[c][k] == T(0)) << k;
                ASSERT_EQ(spdf[k], T(0)) << k;
            }
            // Where the compilers contract, a direction at a pole (a component 1/FLT_MAX beside
            // ±1 here) has an azimuth that the sign of a zero product decides, and an FMA
            // keeps a sign that two roundings lose: the batch and the one-hit code may then
            // read azimuths a quarter turn apart. Without contraction they are equal.
            if (kContracts) continue;
            ASSERT_TRUE(worst.ok()) << "hit " << k << ": " << worst.what << " differs by " << worst.relative << " h "
                                    << hits.h[k] << " wo " << glm::to_string(hits.wo_at(k)) << " wi "
                                    << glm::to_string(hits.wi_at(k)) << " u " << glm::to_string(hits.u_at(k)) << " f "
                                    << f[0][k] << " " << ep.f[0] << " pdf " << pdf[k] << " " << ep.pdf;
            ASSERT_EQ(int(lobe[k]), int(s.lobe)) << k;
        }
    }
}

}  // namespace

TEST(ChiangBatch, MatchesOneHitCallsFloat) {
    // N = 0, 1, around the block widths (32 and 8 in float, 16 and 4 in double), a long batch.
    for (const std::size_t n : std::vector<std::size_t>{0, 1, 3, 4, 5, 7, 8, 9, 16, 17, 31, 32, 33, 45, 4099})
        expect_batch_matches_one_hit<float>(n, unsigned(n) + 1u);
}
TEST(ChiangBatch, MatchesOneHitCallsDouble) {
    for (const std::size_t n : std::vector<std::size_t>{0, 1, 3, 4, 5, 7, 8, 9, 16, 17, 31, 32, 33, 45, 4099})
        expect_batch_matches_one_hit<double>(n, unsigned(n) + 2u);
}
TEST(ChiangBatch, HostileInputGivesTheOneHitZerosFloat) { expect_hostile_input_is_zero<float>(); }
TEST(ChiangBatch, HostileInputGivesTheOneHitZerosDouble) { expect_hostile_input_is_zero<double>(); }
