// hairscatter — the per-fiber tables of dual scattering (Zinke et al. 2008 §4.1, theory.md
// §5.1): forward and backward albedos a_f, a_b, their albedo-weighted lobe shifts ᾱ and
// variances β̄², and from them the local backscattering A_b, Δ_b, σ_b; plus the
// azimuthally averaged forward lobes of the widened global term. Built once per fiber
// parameter set on the host, looked up by the light's inclination.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/constants.hpp"
#include "../math/quadrature.hpp"

namespace hairscatter {

// Conventions. θ is the inclination of the direction light arrives from (tables are
// built with wo at θ and integrated over wi, read through the fiber's reciprocity; the
// lookups use θi, as Sadeghi & Tamstorf note Zinke's θd really is). Shifts and variances
// are in θi + θo (d'Eon's corrected 2θh): lobe p peaks at θi = α_p - θo with variance
// β_p² = v_p, so Δ_b below is a shift of θi + θo too. Everything is per RGB channel.
template <typename T> struct DualScatteringEntry {
    using V3 = glm::vec<3, T>;
    static constexpr int kLobes = 4;  // R, TT, TRT, residual; models with fewer leave zeros

    V3 a_f{T(0)}, a_b{T(0)};            // ∫ f over the forward (|φ| > π/2) / backward half
    V3 alpha_f{T(0)}, alpha_b{T(0)};    // ᾱ_f, ᾱ_b
    V3 beta2_f{T(0)}, beta2_b{T(0)};    // β̄²_f, β̄²_b
    V3 A_b{T(0)}, delta_b{T(0)}, sigma2_b{T(0)};  // A_1 + A_3, Δ_b, σ_b²
    V3 global[kLobes] = {V3(T(0)), V3(T(0)), V3(T(0)), V3(T(0))};  // h-mean of A_p N^G_p

    static constexpr int kFields = 9 + kLobes;  // V3 fields, in the order of fields()
    V3* fields() { return &a_f; }
    const V3* fields() const { return &a_f; }
};
static_assert(sizeof(DualScatteringEntry<float>) == DualScatteringEntry<float>::kFields * 3 * sizeof(float),
              "DualScatteringEntry must be a flat array of vec3 for fields() and the file format");

// Zinke et al. 2008 eqs. 13–15 (theory.md §5.1), the derived backscattering quantities from
// a_f, a_b, ᾱ and β̄² of one θ. d_b enters σ_b. Denominators are floored: 1 - a_f² → 0 only
// for a lossless fiber that scatters everything forward, where A_b → 0 anyway.
template <typename T> void derive_backscattering(DualScatteringEntry<T>& e, T d_b) {
    for (int c = 0; c < 3; ++c) {
        const T af = e.a_f[c], ab = e.a_b[c];
        const T af2 = af * af, ab2 = ab * ab, ab3 = ab2 * ab;
        const T one = std::max(T(1) - af2, T(1e-6));
        const T one2 = one * one, one3 = one2 * one;
        const T A1 = ab * af2 / one;
        const T A3 = ab3 * af2 / one3;
        e.A_b[c] = A1 + A3;
        e.delta_b[c] = e.alpha_b[c] * (T(1) - T(2) * ab2 / one2) +
                       e.alpha_f[c] * (T(2) * one2 + T(4) * af2 * ab2) / one3;
        const T bf2 = e.beta2_f[c], bb2 = e.beta2_b[c];
        const T bf = std::sqrt(bf2), bb = std::sqrt(bb2);
        const T num = ab * std::sqrt(T(2) * bf2 + bb2) + ab3 * std::sqrt(T(2) * bf2 + T(3) * bb2);
        const T den = ab + ab3 * (T(2) * bf + T(3) * bb);
        const T sigma_b = den > T(0) ? (T(1) + d_b * af2) * num / den : T(0);
        e.sigma2_b[c] = sigma_b * sigma_b;
    }
}

template <typename T> struct DualTableOptions {
    int theta_samples = 64;  // table entries over θ ∈ [-π/2, π/2]
    int h_nodes = 32;        // Gauss–Legendre nodes averaging near-field models over h = sin γ
    T d_b = T(0.7);          // backscattering density factor (enters σ_b)
};

template <typename T> class DualScatteringTables {
  public:
    using Entry = DualScatteringEntry<T>;
    static constexpr std::uint32_t kFileVersion = 1;

    DualScatteringTables() = default;
    DualScatteringTables(std::vector<Entry> entries, T d_b, int h_nodes) : entries_(std::move(entries)), d_b_(d_b), h_nodes_(h_nodes) {
        if (entries_.size() < 2) HAIRSCATTER_THROW(std::invalid_argument("hairscatter: dual-scattering tables need ≥ 2 θ samples"));
    }

    // Builds the tables of a single-fiber model. Material is a model's per-material
    // object and Fiber(material, h) its per-hit fiber, which must provide kLobes,
    // lobe_split(wo) (per lobe A_p and the backward fraction of N_p), and the material
    // lobe_shift(p) and lobe_variance(p). Near-field models are averaged over h by
    // Gauss–Legendre quadrature in γ = asin h: ½∫ f(h) dh = ½∫ f(sin γ) cos γ dγ removes the
    // square-root behaviour of γ (and of Fresnel) at h = ±1, where a rule in h converges
    // slowly (32 nodes in h: 2e-3 relative error in a lobe's forward albedo; in γ: 1e-7).
    template <template <typename> class Fiber, typename Material>
    static DualScatteringTables build(const Material& material, const DualTableOptions<T>& opt = {}) {
        if (opt.theta_samples < 2 || opt.h_nodes < 1)
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DualTableOptions needs theta_samples ≥ 2 and h_nodes ≥ 1"));
        if (!(opt.d_b >= T(0) && opt.d_b <= T(1)))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DualTableOptions d_b must lie in [0, 1]"));
        using V3 = glm::vec<3, T>;
        constexpr int L = Fiber<T>::kLobes + 1;
        static_assert(L <= Entry::kLobes, "the model has more lobes than the tables hold");
        const GaussLegendre<T> gl(opt.h_nodes);
        std::vector<Fiber<T>> fibers;
        std::vector<T> h_weight;
        for (int k = 0; k < opt.h_nodes; ++k) {
            const T gamma = kHalfPi<T> * gl.nodes[std::size_t(k)];
            fibers.emplace_back(material, std::sin(gamma));
            h_weight.push_back(T(0.5) * kHalfPi<T> * gl.weights[std::size_t(k)] * std::cos(gamma));
        }

        std::vector<Entry> entries(std::size_t(opt.theta_samples));
        for (int i = 0; i < opt.theta_samples; ++i) {
            const T theta = node_theta(i, opt.theta_samples);
            const V3 wo(std::sin(theta), std::cos(theta), T(0));
            V3 af[L], ab[L];
            for (int p = 0; p < L; ++p) af[p] = ab[p] = V3(T(0));
            Entry& e = entries[std::size_t(i)];
            for (int k = 0; k < opt.h_nodes; ++k) {
                const auto split = fibers[std::size_t(k)].lobe_split(wo);
                const T w = h_weight[std::size_t(k)];  // mean over h ∈ [-1, 1]
                for (int p = 0; p < L; ++p) {
                    af[p] += w * split.a[p] * (T(1) - split.backward[p]);
                    ab[p] += w * split.a[p] * split.backward[p];
                }
            }
            for (int p = 0; p < L; ++p) {
                const T alpha = material.lobe_shift(p), v = material.lobe_variance(p);
                e.a_f += af[p];
                e.a_b += ab[p];
                e.alpha_f += alpha * af[p];
                e.alpha_b += alpha * ab[p];
                e.beta2_f += v * af[p];
                e.beta2_b += v * ab[p];
                // N^G_p: N_p's mean over the forward half (width π), times A_p, over h.
                e.global[p] = af[p] * kInvPi<T>;
            }
            for (int c = 0; c < 3; ++c) {
                const T f = e.a_f[c], b = e.a_b[c];
                e.alpha_f[c] = f > T(0) ? e.alpha_f[c] / f : T(0);
                e.beta2_f[c] = f > T(0) ? e.beta2_f[c] / f : T(0);
                e.alpha_b[c] = b > T(0) ? e.alpha_b[c] / b : T(0);
                e.beta2_b[c] = b > T(0) ? e.beta2_b[c] / b : T(0);
            }
            derive_backscattering(e, opt.d_b);
        }
        return DualScatteringTables(std::move(entries), opt.d_b, opt.h_nodes);
    }

    int size() const { return int(entries_.size()); }
    T d_b() const { return d_b_; }
    int h_nodes() const { return h_nodes_; }
    const Entry& entry(int i) const { return entries_[std::size_t(i)]; }
    T theta_of(int i) const { return node_theta(i, size()); }

    // Linear interpolation between the nodes (θ clamped to [-π/2, π/2]).
    Entry lookup(T theta) const {
        const T s = std::clamp(theta * (T(2) * kInvPi<T>), T(-1), T(1));
        const T x = (std::asin(s) * (T(2) * kInvPi<T>) + T(1)) * T(0.5) * T(size() - 1);
        const int i = std::min(int(x), size() - 2);
        const T t = x - T(i);
        Entry r;
        const auto* a = entries_[std::size_t(i)].fields();
        const auto* b = entries_[std::size_t(i + 1)].fields();
        auto* o = r.fields();
        for (int k = 0; k < Entry::kFields; ++k) o[k] = a[k] + t * (b[k] - a[k]);
        return r;
    }

    // A small versioned binary file: "HSDT", version, θ samples, h nodes, d_b, the entries
    // as doubles, and an FNV-1a checksum of everything before it.
    void save(const std::string& path) const {
        std::vector<unsigned char> buf;
        put(buf, "HSDT", 4);
        put_u32(buf, kFileVersion);
        put_u32(buf, std::uint32_t(size()));
        put_u32(buf, std::uint32_t(Entry::kFields));
        put_u32(buf, std::uint32_t(h_nodes_));
        put_f64(buf, double(d_b_));
        for (const Entry& e : entries_)
            for (int k = 0; k < Entry::kFields; ++k)
                for (int c = 0; c < 3; ++c) put_f64(buf, double(e.fields()[k][c]));
        const std::uint64_t sum = fnv1a(buf.data(), buf.size());
        put(buf, &sum, 8);
        std::ofstream f(path, std::ios::binary);
        if (!f) HAIRSCATTER_THROW(std::runtime_error("hairscatter: cannot write dual-scattering tables to '" + path + "'"));
        f.write(reinterpret_cast<const char*>(buf.data()), std::streamsize(buf.size()));
        if (!f) HAIRSCATTER_THROW(std::runtime_error("hairscatter: failed writing dual-scattering tables to '" + path + "'"));
    }

    static DualScatteringTables load(const std::string& path) {
        std::ifstream f(path, std::ios::binary);
        if (!f) HAIRSCATTER_THROW(std::runtime_error("hairscatter: cannot open dual-scattering tables '" + path + "'"));
        const std::vector<unsigned char> buf((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
        auto fail = [&](const std::string& why) {
            return std::runtime_error("hairscatter: '" + path + "' is not a valid dual-scattering table file: " + why);
        };
        const std::size_t header = 4 + 4 * 4 + 8;
        if (buf.size() < header + 8 || std::memcmp(buf.data(), "HSDT", 4) != 0) HAIRSCATTER_THROW(fail("bad magic or too short"));
        std::size_t at = 4;
        const std::uint32_t version = get_u32(buf, at), n = get_u32(buf, at), fields = get_u32(buf, at),
                            h_nodes = get_u32(buf, at);
        const double d_b = get_f64(buf, at);
        if (version != kFileVersion)
            HAIRSCATTER_THROW(fail("version " + std::to_string(version) + ", this library reads version " + std::to_string(kFileVersion)));
        if (fields != std::uint32_t(Entry::kFields)) HAIRSCATTER_THROW(fail("unexpected number of fields per entry"));
        if (n < 2 || n > 1000000) HAIRSCATTER_THROW(fail("implausible number of θ samples"));
        const std::size_t expected = header + std::size_t(n) * fields * 3 * 8 + 8;
        if (buf.size() != expected)
            HAIRSCATTER_THROW(fail("size " + std::to_string(buf.size()) + " bytes, expected " + std::to_string(expected) + " (truncated?)"));
        std::uint64_t sum;
        std::memcpy(&sum, buf.data() + expected - 8, 8);
        if (sum != fnv1a(buf.data(), expected - 8)) HAIRSCATTER_THROW(fail("checksum mismatch (corrupt file)"));
        std::vector<Entry> entries(n);
        for (Entry& e : entries)
            for (int k = 0; k < Entry::kFields; ++k)
                for (int c = 0; c < 3; ++c) {
                    const double v = get_f64(buf, at);
                    if (!std::isfinite(v)) HAIRSCATTER_THROW(fail("non-finite value"));
                    e.fields()[k][c] = T(v);
                }
        if (!(d_b >= 0 && d_b <= 1)) HAIRSCATTER_THROW(fail("d_b outside [0, 1]"));
        return DualScatteringTables(std::move(entries), T(d_b), int(h_nodes));
    }

  private:
    // Nodes θ_i = (π/2) sin(π x_i / 2) for x_i uniform in [-1, 1]: uniform near θ = 0 and
    // denser toward the poles, where the albedos and A_b change fastest (a uniform θ grid of
    // 64 samples leaves 12 % of A_b's range as interpolation error within 3° of grazing).
    static T node_theta(int i, int n) {
        const T x = T(-1) + T(2) * T(i) / T(n - 1);
        return kHalfPi<T> * std::sin(kHalfPi<T> * x);
    }

    static std::uint64_t fnv1a(const unsigned char* p, std::size_t n) {
        std::uint64_t h = 1469598103934665603ull;
        for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
        return h;
    }
    static void put(std::vector<unsigned char>& b, const void* p, std::size_t n) {
        const auto* c = static_cast<const unsigned char*>(p);
        b.insert(b.end(), c, c + n);
    }
    static void put_u32(std::vector<unsigned char>& b, std::uint32_t v) { put(b, &v, 4); }
    static void put_f64(std::vector<unsigned char>& b, double v) { put(b, &v, 8); }
    static std::uint32_t get_u32(const std::vector<unsigned char>& b, std::size_t& at) {
        std::uint32_t v;
        std::memcpy(&v, b.data() + at, 4);
        at += 4;
        return v;
    }
    static double get_f64(const std::vector<unsigned char>& b, std::size_t& at) {
        double v;
        std::memcpy(&v, b.data() + at, 8);
        at += 8;
        return v;
    }

    std::vector<Entry> entries_;
    T d_b_ = T(0.7);
    int h_nodes_ = 0;
};

}  // namespace hairscatter
