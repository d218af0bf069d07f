// hairscatter — what every single-fiber model shares: the result types of sample and
// eval_pdf, the sampled-lobe tags, the bound-at-wo object, the "is a fiber model" trait
// and the uniform-sphere baseline. Every model includes this header; no model includes
// another model.
//
// The contract, for a model F over the real type T = F::Real (unit vectors in the fiber
// frame, fiber/frame.hpp; wo toward the viewer, wi toward the light; eval with the cosine
// inside, pdf in solid angle, u four uniform numbers in [0, 1]):
//   F::Real                          the real type;
//   F::kLobes                        the number of explicit lobes (R, TT, TRT: 3); a model
//                                    with a residual gives it index kLobes;
//   eval(wo, wi)      → vec3         f, RGB;
//   pdf(wo, wi)       → T            the density sample() draws wi with;
//   eval_pdf(wo, wi)  → HairEvalPdf  both, sharing their terms;
//   sample(wo, u)     → HairSample   wi, weight = eval / pdf, pdf and the lobe drawn;
//   at(wo)            → bound object with eval(wi), pdf(wi), eval_pdf(wi), sample(u),
//                                    equal to the above with the wo terms computed once;
//   albedo(wo)        → vec3         ∫ eval(wo, wi) dωi.
// is_fiber_model_v<F> checks these signatures. Models that can also split the albedo per
// lobe offer lobe_split(wo) (has_lobe_split_v<F>); their materials offer lobe_shift(p)
// and lobe_variance(p).
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/constants.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"

namespace hairscatter {

// The lobe a sample was drawn from. kR … kResidual are the single-fiber lobes (their
// values are the lobe indices 0 … 3 every model uses); the dual-scattering BCSDF adds
// its three components; kUniform marks the uniform-sphere baseline; kNone an empty sample.
enum class SampledLobe : int { kR, kTT, kTRT, kResidual, kDualBack, kDualGlobal, kDualGlobalBack, kUniform, kNone };

// Lobe index p (0 R, 1 TT, 2 TRT, 3 residual) ↔ its tag.
HAIRSCATTER_HD constexpr SampledLobe lobe_tag(int p) { return SampledLobe(p); }
HAIRSCATTER_HD constexpr int lobe_index(SampledLobe lobe) { return int(lobe); }

// What sample() returns. pdf is in solid-angle measure, weight = eval / pdf. A sample
// whose pdf is 0 (only from underflow in extreme parameters) carries weight 0.
//
// Non-finite input, every model: a NaN or ±Inf component in wo, wi or u, or a zero wo or
// wi, makes eval 0, pdf 0, eval_pdf {0, 0} and sample this default sample (wi 0, weight 0,
// pdf 0): a renderer ends the path, and neither a NaN nor an out-of-table read can follow
// (the test reads the bits, so it holds under -ffast-math as well). Finite directions of
// any other length are normalised (the largest floats included) and u is clamped into
// [0, 1]. A sample's pdf and weight are pdf(wo, wi) and eval / pdf at its own wi, exactly
// at the poles θi = ±90° too. docs/robustness.md.
template <typename T> struct HairSample {
    glm::vec<3, T> wi{T(0)};
    glm::vec<3, T> weight{T(0)};
    T pdf = T(0);
    SampledLobe lobe = SampledLobe::kNone;
};

// f and pdf of one direction pair, computed together (they share every lobe term).
template <typename T> struct HairEvalPdf {
    glm::vec<3, T> f{T(0)};
    T pdf = T(0);
};

// The sample of direction wi drawn from `lobe`, given its f and pdf: weight = f / pdf, 0
// where the pdf underflowed. Every model's sample() ends here.
template <typename T>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE HairSample<T> make_sample(const glm::vec<3, T>& wi, SampledLobe lobe,
                                                            const HairEvalPdf<T>& e) {
    HairSample<T> r;
    r.wi = wi;
    r.lobe = lobe;
    r.pdf = e.pdf;
    r.weight = e.pdf > T(0) ? e.f / e.pdf : glm::vec<3, T>(T(0));
    return r;
}

template <typename Fiber> class BoundFiber;

// The offset h ∈ [-1, 1] across the fiber, as a near-field model stores it: clamped (hit
// offsets round slightly out), NaN made -1 (read from the bits: -ffast-math keeps it).
template <typename T> HAIRSCATTER_HD T clamped_offset(T h) {
    h = h > T(1) ? T(1) : (h >= T(-1) ? h : T(-1));
    return is_finite(h) ? h : T(-1);
}
// Host: h itself, which must lie in [-1, 1] (throws std::invalid_argument).
template <typename T> T checked_offset(T h) {
    if (!(is_finite(h) && h >= T(-1) && h <= T(1)))  // (the bits: -ffast-math keeps NaN out)
        HAIRSCATTER_THROW(std::invalid_argument("hairscatter: h = " + std::to_string(double(h)) +
                                                " is outside its range [-1, 1]"));
    return h;
}

// The shared front of every model (CRTP). A model M derives from FiberModel<M, T>,
// befriends it and BoundFiber<M>, and writes three private pieces once:
//   struct Outgoing;                          the terms that depend on wo only;
//   template <bool kW> Outgoing outgoing(wo); kW: also what sampling and pdf need;
//   template <bool kF, bool kPdf> HairEvalPdf<T> query(o, wo, wi);  f and/or pdf;
//   HairSample<T> sample_from(o, wo, u).
// Optionally also HairSample<T> sample_fresh(o, wo, u), the same samples for the stateless
// sample, whose o has just been computed (a model may order the work differently when its
// wo terms arrive last; without it, sample_from serves both). Optionally also Bound bind(wo),
// what at(wo) keeps instead of outgoing<true>(wo) when several calls at one hit can share
// more than the stateless calls compute (query and sample_from then also take a Bound).
// Then eval, pdf, eval_pdf, sample and at(wo) are these, here, for every model alike.
template <typename Model, typename T> class FiberModel {
  public:
    using Real = T;
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    using At = BoundFiber<Model>;  // what at(wo) returns

    // Non-finite input gives 0 / no sample before anything reads a table (see HairSample).
    // Finite directions of any non-zero length are normalised, and u is clamped into [0, 1]
    // (see HairSample).
    HAIRSCATTER_HD V3 eval(V3 wo, V3 wi) const {
        if (!unit_directions(wo, wi)) return V3(T(0));
        return self().template query<true, false>(self().template outgoing<false>(wo), wo, wi).f;
    }
    HAIRSCATTER_HD T pdf(V3 wo, V3 wi) const {
        if (!unit_directions(wo, wi)) return T(0);
        return self().template query<false, true>(self().template outgoing<true>(wo), wo, wi).pdf;
    }
    HAIRSCATTER_HD HairEvalPdf<T> eval_pdf(V3 wo, V3 wi) const {
        if (!unit_directions(wo, wi)) return HairEvalPdf<T>{};
        return self().template query<true, true>(self().template outgoing<true>(wo), wo, wi);
    }
    HAIRSCATTER_HD HairSample<T> sample(V3 wo, V4 u) const {
        if (!unit_direction_and_numbers(wo, u)) return HairSample<T>{};
        return fresh_sample(self(), self().template outgoing<true>(wo), wo, u, 0);
    }

    // The model at a fixed outgoing direction: everything that depends on wo alone is
    // computed once here, and eval, pdf, eval_pdf and sample of the returned object take
    // only wi or u, with the results of the calls above. A renderer that evaluates a
    // light sample and draws a continuation at the same hit pays for wo once. It holds a
    // copy of the fiber (which refers to its material: the material must outlive it).
    HAIRSCATTER_HD BoundFiber<Model> at(const V3& wo) const { return BoundFiber<Model>(self(), wo); }

  private:
    // The model's sample_fresh where it has one (found here, where its private members are
    // visible), else its sample_from.
    template <typename M, typename O>
    static HAIRSCATTER_HD auto fresh_sample(const M& m, const O& o, const V3& wo, const V4& u, int)
        -> decltype(m.sample_fresh(o, wo, u)) {
        return m.sample_fresh(o, wo, u);
    }
    template <typename M, typename O>
    static HAIRSCATTER_HD HairSample<T> fresh_sample(const M& m, const O& o, const V3& wo, const V4& u, long) {
        return m.sample_from(o, wo, u);
    }
    HAIRSCATTER_HD const Model& self() const { return static_cast<const Model&>(*this); }
};

// What at(wo) returns (see FiberModel::at).
template <typename Fiber> class BoundFiber {
  public:
    using Real = typename Fiber::Real;
    using V3 = glm::vec<3, Real>;
    using V4 = glm::vec<4, Real>;

    // wo is normalised (any finite non-zero length); a non-finite or zero wo binds a valid
    // direction instead and marks the object empty: every call then gives 0 / no sample.
    HAIRSCATTER_HD BoundFiber(const Fiber& fiber, const V3& wo)
        : fiber_(fiber), wo_(wo), valid_(unit_or_stand_in(wo_)), o_(bind_state(fiber, wo_, 0)) {}

    HAIRSCATTER_HD V3 eval(V3 wi) const {
        if (!(valid_ && unit_direction(wi))) return V3(Real(0));
        return fiber_.template query<true, false>(o_, wo_, wi).f;
    }
    HAIRSCATTER_HD Real pdf(V3 wi) const {
        if (!(valid_ && unit_direction(wi))) return Real(0);
        return fiber_.template query<false, true>(o_, wo_, wi).pdf;
    }
    HAIRSCATTER_HD HairEvalPdf<Real> eval_pdf(V3 wi) const {
        if (!(valid_ && unit_direction(wi))) return HairEvalPdf<Real>{};
        return fiber_.template query<true, true>(o_, wo_, wi);
    }
    HAIRSCATTER_HD HairSample<Real> sample(V4 u) const {
        if (!(valid_ && unit_numbers(u))) return HairSample<Real>{};
        return fiber_.sample_from(o_, wo_, u);
    }
    // The bound wo, normalised (or the stand-in of an empty object), and whether it was valid.
    HAIRSCATTER_HD const V3& wo() const { return wo_; }
    HAIRSCATTER_HD bool valid() const { return valid_; }
    HAIRSCATTER_HD const Fiber& fiber() const { return fiber_; }
    // The fiber's albedo(wo): from the bound terms when the model offers albedo_from(o)
    // (no second pass over the wo terms), else by albedo(wo).
    HAIRSCATTER_HD V3 albedo() const { return albedo_of(0); }

  private:
    // The state bound at wo: the model's bind(wo) where it offers one (a model that keeps
    // more for several calls at one hit than its stateless calls need, which its query and
    // sample_from then also take), else its outgoing<true>(wo).
    template <typename F>
    static HAIRSCATTER_HD auto bind_state(const F& f, const V3& wo, int) -> decltype(f.bind(wo)) {
        return f.bind(wo);
    }
    template <typename F> static HAIRSCATTER_HD typename F::Outgoing bind_state(const F& f, const V3& wo, long) {
        return f.template outgoing<true>(wo);
    }
    using State = decltype(bind_state(std::declval<const Fiber&>(), std::declval<const V3&>(), 0));

    // w made unit in place, or (non-finite or zero) replaced by a valid direction to bind
    // instead, the object then empty: every call gives 0 / no sample (see HairSample).
    static HAIRSCATTER_HD bool unit_or_stand_in(V3& w) {
        if (unit_direction(w)) return true;
        w = V3(Real(0), Real(1), Real(0));
        return false;
    }

    template <typename F = Fiber, typename O = State>
    HAIRSCATTER_HD auto albedo_of(int) const -> decltype(std::declval<const F&>().albedo_from(std::declval<const O&>())) {
        return fiber_.albedo_from(o_);
    }
    template <typename F = Fiber> HAIRSCATTER_HD V3 albedo_of(long) const { return fiber_.albedo(wo_); }

    Fiber fiber_;
    V3 wo_;
    bool valid_;
    State o_;
};

namespace detail {

template <typename F> using real_of = typename F::Real;
template <typename F> using v3_of = glm::vec<3, real_of<F>>;
template <typename F> using v4_of = glm::vec<4, real_of<F>>;
template <typename F> const F& lvalue();

template <typename F> using eval_t = decltype(lvalue<F>().eval(lvalue<v3_of<F>>(), lvalue<v3_of<F>>()));
template <typename F> using pdf_t = decltype(lvalue<F>().pdf(lvalue<v3_of<F>>(), lvalue<v3_of<F>>()));
template <typename F> using eval_pdf_t = decltype(lvalue<F>().eval_pdf(lvalue<v3_of<F>>(), lvalue<v3_of<F>>()));
template <typename F> using sample_t = decltype(lvalue<F>().sample(lvalue<v3_of<F>>(), lvalue<v4_of<F>>()));
template <typename F> using albedo_t = decltype(lvalue<F>().albedo(lvalue<v3_of<F>>()));
template <typename F> using at_t = decltype(lvalue<F>().at(lvalue<v3_of<F>>()));
template <typename F, typename B> using bound_eval_t = decltype(lvalue<B>().eval(lvalue<v3_of<F>>()));
template <typename F, typename B> using bound_pdf_t = decltype(lvalue<B>().pdf(lvalue<v3_of<F>>()));
template <typename F, typename B> using bound_eval_pdf_t = decltype(lvalue<B>().eval_pdf(lvalue<v3_of<F>>()));
template <typename F, typename B> using bound_sample_t = decltype(lvalue<B>().sample(lvalue<v4_of<F>>()));
template <typename F> using lobe_split_t = decltype(lvalue<F>().lobe_split(lvalue<v3_of<F>>()));

template <typename F, typename = void> struct is_fiber_model : std::false_type {};
template <typename F>
struct is_fiber_model<F, std::void_t<real_of<F>, decltype(F::kLobes), eval_t<F>, pdf_t<F>, eval_pdf_t<F>, sample_t<F>,
                                     albedo_t<F>, at_t<F>, bound_eval_t<F, at_t<F>>, bound_pdf_t<F, at_t<F>>,
                                     bound_eval_pdf_t<F, at_t<F>>, bound_sample_t<F, at_t<F>>>>
    : std::bool_constant<std::is_same_v<eval_t<F>, v3_of<F>> && std::is_same_v<pdf_t<F>, real_of<F>> &&
                         std::is_same_v<eval_pdf_t<F>, HairEvalPdf<real_of<F>>> &&
                         std::is_same_v<sample_t<F>, HairSample<real_of<F>>> && std::is_same_v<albedo_t<F>, v3_of<F>> &&
                         std::is_same_v<bound_eval_t<F, at_t<F>>, v3_of<F>> &&
                         std::is_same_v<bound_pdf_t<F, at_t<F>>, real_of<F>> &&
                         std::is_same_v<bound_eval_pdf_t<F, at_t<F>>, HairEvalPdf<real_of<F>>> &&
                         std::is_same_v<bound_sample_t<F, at_t<F>>, HairSample<real_of<F>>>> {};

template <typename F, typename = void> struct has_lobe_split : std::false_type {};
template <typename F> struct has_lobe_split<F, std::void_t<lobe_split_t<F>>> : std::true_type {};

}  // namespace detail

// Whether F offers the whole contract above with the right signatures.
template <typename F> struct is_fiber_model : detail::is_fiber_model<F> {};
template <typename F> inline constexpr bool is_fiber_model_v = is_fiber_model<F>::value;
// Whether F also splits its albedo per lobe (lobe_split(wo)).
template <typename F> inline constexpr bool has_lobe_split_v = detail::has_lobe_split<F>::value;

// Per lobe p = 0 … kLobes: A_p(wo), the energy of lobe p (Σ_p a[p] = albedo(wo)), and the
// fraction of it that scatters backward (|φ| < π/2), weighted by the channel sum of the
// lobe's energy where its azimuthal shape depends on the channel. These are what the
// dual-scattering tables integrate (dual/tables.hpp).
template <typename T, int kLobes> struct LobeSplit {
    glm::vec<3, T> a[std::size_t(kLobes + 1)];
    T backward[std::size_t(kLobes + 1)];
};

// No energy, each lobe split evenly: what lobe_split returns for a non-finite or zero wo.
template <typename T, int kLobes> HAIRSCATTER_HD LobeSplit<T, kLobes> empty_lobe_split() {
    LobeSplit<T, kLobes> r;
    for (int p = 0; p <= kLobes; ++p) {
        r.a[p] = glm::vec<3, T>(T(0));
        r.backward[p] = T(0.5);
    }
    return r;
}

// Σ_p a[p]: the albedo a lobe split accounts for.
template <typename T, int kLobes>
HAIRSCATTER_HD glm::vec<3, T> split_albedo(const LobeSplit<T, kLobes>& split) {
    glm::vec<3, T> a(T(0));
    for (int p = 0; p <= kLobes; ++p) a += split.a[p];
    return a;
}

// Uniform directions on the sphere for any model with eval(wo, wi): the baseline the
// origin study [Lemein 2019] measures importance sampling against. Holds a copy of the model.
template <typename Model> class UniformSphereSampling {
  public:
    explicit UniformSphereSampling(const Model& model) : model_(model) {}
    template <typename V3> auto eval(const V3& wo, const V3& wi) const { return model_.eval(wo, wi); }
    template <typename V3> auto pdf(const V3&, const V3&) const -> typename V3::value_type {
        using T = typename V3::value_type;
        return T(0.25) * kInvPi<T>;
    }
    template <typename V3> auto eval_pdf(const V3& wo, const V3& wi) const {
        HairEvalPdf<typename V3::value_type> r;
        r.f = eval(wo, wi);
        r.pdf = pdf(wo, wi);
        return r;
    }
    template <typename V3, typename V4> auto sample(const V3& wo, const V4& u) const {
        using T = typename V3::value_type;
        const T z = T(1) - T(2) * u.y;
        const T r = cos_from_sin(z);
        T s, c;
        elem::sincos(kTwoPi<T> * u.z, s, c);
        HairEvalPdf<T> e;
        e.pdf = T(0.25) * kInvPi<T>;
        const V3 wi(z, r * c, r * s);
        e.f = model_.eval(wo, wi);
        return make_sample(wi, SampledLobe::kUniform, e);
    }

  private:
    Model model_;
};

}  // namespace hairscatter
