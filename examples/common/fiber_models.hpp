// hairscatter examples — every fiber model the library ships behind one switch, shared by
// the renderer and the lobe explorer: --model chiang|farfield|tabulated|marschner|huang|fur, the
// Chiang lobe subsets (--lobes R,TT,TRT,residual), the materials, and per-hit fibers
// bound to their wo.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <hairscatter/hairscatter.hpp>

namespace hairscatter_examples {

enum class FiberModel { kChiang, kFarField, kTabulated, kMarschner, kHuang, kFur };

const char* to_string(FiberModel m);
// "chiang" | "farfield" | "tabulated" | "marschner" | "huang" | "fur"; throws std::invalid_argument naming --model.
FiberModel parse_model(const std::string& name);

// The examples' lobe sets: bit p keeps lobe p (0 R, 1 TT, 2 TRT, 3 residual). Only
// with_chiang_lobes below turns one into the library's lobe-set type.
struct LobeBits {
    static constexpr unsigned kR = 1u, kTT = 2u, kTRT = 4u, kResidual = 8u;
    static constexpr unsigned kPrimary = kR | kTT | kTRT, kAll = kPrimary | kResidual;
};
constexpr bool keeps_lobe(unsigned bits, int p) { return ((bits >> p) & 1u) != 0u; }

// A lobe list "R,TT,TRT,residual" (any subset, any order, case-insensitive), or "all",
// "primary" (R,TT,TRT), as LobeBits; throws naming --lobes.
unsigned parse_lobes(const std::string& list);
std::string lobes_to_string(unsigned lobes);  // "R,TT,TRT,residual"
std::vector<unsigned> each_lobe(unsigned lobes);  // the set's lobes one by one

// THE place where a lobe set chosen at run time becomes the template argument of
// BasicChiangFiber: calls f(std::integral_constant<L, kLobes>{}) with L the library's
// lobe-set type and kLobes the set (use it as BasicChiangFiber<T, decltype(arg)::value>).
// Nothing else in the examples names the library's lobe-set type, so a change of that
// type is a change of this function only.
template <unsigned kBits = 1u, class F> decltype(auto) with_chiang_lobes(unsigned bits, F&& f) {
    using Set = hairscatter::LobeSet;  // the library's lobe-set type
    if constexpr (kBits > LobeBits::kAll) {
        throw std::invalid_argument("--lobes: empty or unknown lobe set " + std::to_string(bits));
        return f(std::integral_constant<Set, Set::kAll>{});  // the return type
    } else {
        static_assert(unsigned(Set::kR) == LobeBits::kR && unsigned(Set::kTT) == LobeBits::kTT &&
                      unsigned(Set::kTRT) == LobeBits::kTRT && unsigned(Set::kResidual) == LobeBits::kResidual);
        if (bits == kBits) return f(std::integral_constant<Set, Set(kBits)>{});
        return with_chiang_lobes<kBits + 1u>(bits, std::forward<F>(f));
    }
}

// Marschner's parameters for a Chiang parameter set: the same η, σa and βn; the R lobe's
// shift α_R = −2α (the scale tilt shifts R by twice its angle, Marschner et al. 2003 §4.1)
// and width β_R = √v(βm), Chiang's longitudinal standard deviation (Chiang et al. 2016
// eq. 7); TT and TRT follow Marschner's Table 1.
template <typename T> hairscatter::MarschnerParams<T> marschner_params(const hairscatter::FiberParams<T>& p) {
    hairscatter::MarschnerParams<T> m;
    m.eta = p.eta;
    m.sigma_a = p.sigma_a;
    m.beta_n = p.beta_n;
    m.alpha_r = T(-2) * p.alpha;
    m.beta_r = std::sqrt(hairscatter::longitudinal_variance(p.beta_m));
    return m;
}

// The cross-section of --model huang (--aspect, --orientation in degrees): Huang et al.
// 2022's minor-over-major axis ratio and the major axis' angle about the fiber.
struct SectionShape {
    double aspect = 1.0, orientation_deg = 0.0;
};

// Huang's parameters for a Chiang parameter set: the same η, α and σa, βm as the
// microfacet roughness, and the section shape.
template <typename T>
hairscatter::HuangParams<T> huang_params(const hairscatter::FiberParams<T>& p, const SectionShape& shape) {
    hairscatter::HuangParams<T> h;
    h.eta = p.eta;
    h.roughness = p.beta_m;
    h.alpha = p.alpha;
    h.sigma_a = p.sigma_a;
    h.aspect_ratio = T(shape.aspect);
    h.orientation = hairscatter::radians(T(shape.orientation_deg));
    return h;
}

// The medulla of --model fur (--kappa, --medulla-sigma-s, --medulla-sigma-a, --medulla-g):
// its radius over the fiber's, its scattering and absorption per unit fiber radius and its
// Henyey–Greenstein anisotropy (models/fur.hpp). The default has none: the fur fiber is then
// Chiang's.
struct MedullaShape {
    double kappa = 0.0, sigma_s = 0.0, g = 0.0;
    double sigma_a[3] = {0.0, 0.0, 0.0};
    bool rough_cortex = false;  // --rough-cortex: FurParams::rough_cortex
    double facet_alpha = 0.0;   // --facet-alpha: FurParams::facet_alpha
};

// The fur fiber's parameters for a Chiang parameter set: the set is the cortex.
template <typename T>
hairscatter::FurParams<T> fur_params(const hairscatter::FiberParams<T>& p, const MedullaShape& m) {
    hairscatter::FurParams<T> f;
    f.cortex = p;
    f.kappa = T(m.kappa);
    f.sigma_s = T(m.sigma_s);
    f.sigma_a_medulla = glm::vec<3, T>(T(m.sigma_a[0]), T(m.sigma_a[1]), T(m.sigma_a[2]));
    f.g = T(m.g);
    f.rough_cortex = m.rough_cortex;
    f.facet_alpha = T(m.facet_alpha);
    return f;
}

// A fiber bound to one wo: fiber.at(wo) where the model has it, else the fiber and wo kept
// together. Either way: eval(wi), pdf(wi), eval_pdf(wi), sample(u).
template <class Fiber> class BoundFiber {
  public:
    using V3 = typename Fiber::V3;
    using V4 = typename Fiber::V4;
    BoundFiber(const Fiber& fiber, const V3& wo) : fiber_(fiber), wo_(wo) {}
    V3 eval(const V3& wi) const { return fiber_.eval(wo_, wi); }
    auto pdf(const V3& wi) const { return fiber_.pdf(wo_, wi); }
    auto eval_pdf(const V3& wi) const { return fiber_.eval_pdf(wo_, wi); }
    auto sample(const V4& u) const { return fiber_.sample(wo_, u); }

  private:
    Fiber fiber_;
    V3 wo_;
};
template <class Fiber, class = void> struct HasAt : std::false_type {};
template <class Fiber>
struct HasAt<Fiber, std::void_t<decltype(std::declval<const Fiber&>().at(std::declval<typename Fiber::V3>()))>>
    : std::true_type {};
template <class Fiber> auto bind_fiber(const Fiber& fiber, const typename Fiber::V3& wo) {
    if constexpr (HasAt<Fiber>::value) return fiber.at(wo);
    else return BoundFiber<Fiber>(fiber, wo);
}

// The artists' extras (docs/controls.md): lobe controls (every model; Huang's and
// Marschner's refuse what they cannot honour: per-lobe tilts, a residual), and one fiber
// per strand (strand_params[strand % size]; empty: every strand is the base fiber): for
// Chiang a material per strand, for Huang the base material with the strand's σa
// (HuangFiber(material, sigma_a): its tables do not depend on σa; a strand whose η, βm or
// α differs is refused, as each would need its own build, about 0.3 s).
template <typename T> struct FiberExtras {
    hairscatter::LobeControls<T> controls{};
    bool has_controls = false;
    std::vector<hairscatter::FiberParams<T>> strand_params;

    // Whether some lobe's gain × tint exceeds 1 in some channel: a fiber may then return more
    // light than it receives, and multiple scattering caps it (docs/controls.md).
    bool amplifies() const {
        if (!has_controls) return false;
        for (int p = 0; p < hairscatter::LobeControls<T>::kLobes; ++p) {
            const auto w = controls.weight(p);
            if (w.x > T(1) || w.y > T(1) || w.z > T(1)) return true;
        }
        return false;
    }
};

// The chosen model's material, built and validated once (throws std::invalid_argument
// naming the bad parameter or option). visit(f) calls f(make) with make(h, strand = 0) →
// the per-hit fiber (h is ignored by the h-integrated models: far field, tabulated,
// Marschner, Huang; the strand selects Chiang's per-strand material).
template <typename T> class FiberModels {
  public:
    FiberModels(FiberModel model, unsigned lobes, const hairscatter::FiberParams<T>& params,
                const FiberExtras<T>& extras = {}, const SectionShape& shape = {}, const MedullaShape& medulla = {})
        : model_(model), lobes_(lobes) {
        namespace hs = hairscatter;
        if (model != FiberModel::kChiang && lobes != LobeBits::kAll)
            throw std::invalid_argument(std::string("--lobes: only --model chiang keeps a subset of lobes (--model ") +
                                        to_string(model) + " has all of its lobes)");
        if (model != FiberModel::kChiang && model != FiberModel::kHuang && !extras.strand_params.empty())
            throw std::invalid_argument(std::string("per-strand variation (--strand-seed, --*-range) needs --model "
                                                    "chiang or huang (not ") + to_string(model) + ")");
        if (model == FiberModel::kHuang)
            for (const hs::FiberParams<T>& p : extras.strand_params) {
                if (p.eta != params.eta || p.beta_m != params.beta_m || p.alpha != params.alpha)
                    throw std::invalid_argument("per-strand roughness (--roughness-range) needs --model chiang: "
                                                "--model huang varies the colour per strand only");
                strand_sigma_.push_back(p.sigma_a);
            }
        with_chiang_lobes(lobes, [](auto) { return 0; });  // rejects an empty set
        chiang_ = std::make_unique<hs::ChiangMaterial<T>>(params, extras.controls);
        if (model == FiberModel::kChiang) {
            strands_.reserve(extras.strand_params.size());
            for (const hs::FiberParams<T>& p : extras.strand_params) strands_.emplace_back(p, extras.controls);
        }
        switch (model) {
            case FiberModel::kChiang: break;
            case FiberModel::kFarField:
                farfield_ = std::make_unique<hs::DeonFarFieldMaterial<T>>(params, extras.controls);
                break;
            case FiberModel::kTabulated:
                tabulated_ = std::make_unique<hs::TabulatedMaterial<T>>(params, hs::TabulatedOptions(), extras.controls);
                break;
            case FiberModel::kMarschner:
                try {
                    marschner_ = std::make_unique<hs::MarschnerMaterial<T>>(marschner_params(params), extras.controls);
                } catch (const std::invalid_argument& e) {
                    throw std::invalid_argument(std::string("--model marschner (alpha_r = -2 alpha, beta_r = "
                                                            "sqrt(v(beta_m))): ") + e.what());
                }
                break;
            case FiberModel::kHuang:
                try {
                    huang_ = std::make_unique<hs::HuangMaterial<T>>(huang_params(params, shape), extras.controls);
                } catch (const std::invalid_argument& e) {
                    throw std::invalid_argument(std::string("--model huang (roughness = beta_m, --aspect, "
                                                            "--orientation, lobe controls): ") + e.what());
                }
                break;
            case FiberModel::kFur:
                // The lobe controls act on R, TT, TRT and the residual (FurControls::lobes); the
                // medulla's lobe keeps gain and tint 1 (no command-line options for it).
                try {
                    hs::FurControls<T> controls;
                    controls.lobes = extras.controls;
                    fur_ = std::make_unique<hs::FurMaterial<T>>(fur_params(params, medulla), controls);
                } catch (const std::invalid_argument& e) {
                    throw std::invalid_argument(std::string("--model fur (kappa = --kappa, sigma_s = --medulla-sigma-s, "
                                                            "sigma_a_medulla = --medulla-sigma-a, g = --medulla-g, lobe controls): ") +
                                                e.what());
                }
                break;
        }
    }
    FiberModels(const FiberModels&) = delete;
    FiberModels& operator=(const FiberModels&) = delete;

    FiberModel model() const { return model_; }
    unsigned lobes() const { return lobes_; }
    // Always built: the dual-scattering tables of every model but fur are Chiang's.
    const hairscatter::ChiangMaterial<T>& chiang() const { return *chiang_; }
    // The fur material (--model fur only; null otherwise).
    const hairscatter::FurMaterial<T>* fur() const { return fur_.get(); }
    // Strand `strand`'s Chiang material (the base one without per-strand variation).
    const hairscatter::ChiangMaterial<T>& chiang(std::uint32_t strand) const {
        return strands_.empty() ? *chiang_ : strands_[strand % strands_.size()];
    }

    template <class F> decltype(auto) visit(F&& f) const {
        namespace hs = hairscatter;
        switch (model_) {
            case FiberModel::kFarField: {
                const hs::DeonFarFieldMaterial<T>* m = farfield_.get();
                return f([m](T, std::uint32_t = 0) { return hs::DeonFarFieldFiber<T>(*m); });
            }
            case FiberModel::kTabulated: {
                const hs::TabulatedMaterial<T>* m = tabulated_.get();
                return f([m](T, std::uint32_t = 0) { return hs::TabulatedFiber<T>(*m); });
            }
            case FiberModel::kMarschner: {
                const hs::MarschnerMaterial<T>* m = marschner_.get();
                return f([m](T, std::uint32_t = 0) { return hs::MarschnerFiber<T>(*m); });
            }
            case FiberModel::kHuang: {
                const hs::HuangMaterial<T>* m = huang_.get();
                const std::vector<glm::vec<3, T>>* strands = &strand_sigma_;
                return f([m, strands](T, std::uint32_t strand = 0) {
                    return strands->empty() ? hs::HuangFiber<T>(*m)
                                            : hs::HuangFiber<T>(*m, (*strands)[strand % strands->size()]);
                });
            }
            case FiberModel::kFur: {
                const hs::FurMaterial<T>* m = fur_.get();
                return f([m](T h, std::uint32_t = 0) { return hs::FurFiber<T>(*m, h); });
            }
            case FiberModel::kChiang: break;
        }
        const FiberModels* self = this;
        return with_chiang_lobes(lobes_, [&](auto set) -> decltype(auto) {
            return f([self](T h, std::uint32_t strand = 0) {
                return hs::BasicChiangFiber<T, decltype(set)::value>(self->chiang(strand), h);
            });
        });
    }

  private:
    FiberModel model_;
    unsigned lobes_;
    std::unique_ptr<hairscatter::ChiangMaterial<T>> chiang_;
    std::vector<hairscatter::ChiangMaterial<T>> strands_;
    std::vector<glm::vec<3, T>> strand_sigma_;  // Huang's per-strand σa (empty: the material's)
    std::unique_ptr<hairscatter::DeonFarFieldMaterial<T>> farfield_;
    std::unique_ptr<hairscatter::TabulatedMaterial<T>> tabulated_;
    std::unique_ptr<hairscatter::MarschnerMaterial<T>> marschner_;
    std::unique_ptr<hairscatter::HuangMaterial<T>> huang_;
    std::unique_ptr<hairscatter::FurMaterial<T>> fur_;
};

}  // namespace hairscatter_examples
