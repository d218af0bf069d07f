// hairscatter Python bindings: the vectorised calls of one fiber model type (ModelOf) and of
// the dual-scattering BCSDF over it (DualOf), each one C++ loop over the rows with the GIL
// released. Included by the sources that bind the models.
#pragma once

#include <limits>
#include <type_traits>
#include <utility>

#include "common.hpp"

namespace hairscatter::python {

// The per-hit fiber of a model at offset h: near-field models take h (clamped into [-1, 1]
// as the per-hit constructor does), far-field ones have none.
template <typename Fiber> inline constexpr bool kNearField =
    std::is_constructible_v<Fiber, const typename Fiber::Material&, typename Fiber::Real>;

template <typename Fiber> class ModelOf;

// Whether offset h can be used: any for a far-field model (it has none), a finite one for a
// near-field model. A NaN h would be clamped to -1 by the per-hit fiber; the module gives
// such a row the contract's zeros instead, as for a non-finite direction.
template <typename Fiber, typename T> bool usable_offset(T h) { return !kNearField<Fiber> || is_finite(h); }

// Whether the module compiles the dual-scattering tables and BCSDF over Fiber: every model
// but the Chiang fiber's lobe subsets (each would add seconds of build time, times 28).
template <typename Fiber> inline constexpr bool kWithDual = has_lobe_split_v<Fiber>;
template <typename T, LobeSet kKept>
inline constexpr bool kWithDual<BasicChiangFiber<T, kKept>> = kKept == LobeSet::kAll;

// Why Fiber has no dual scattering in the module.
template <typename Fiber> const char* no_dual_reason() {
    if constexpr (has_lobe_split_v<Fiber>)
        return "the dual-scattering tables and BCSDF of a Chiang lobe subset are not compiled into the module "
               "(use lobes='all')";
    else
        return "the dual-scattering tables integrate lobe_split, which this model does not offer (Marschner et al. "
               "2003); build them from another model and pass them to DualScatteringBcsdf";
}

// The offsets h of a call: required (and N or one) for a near-field model, refused for a far-field one.
template <typename Fiber, typename T = typename Fiber::Real>
Rows<T> offsets(py::handle h, CallShape& shape) {
    if constexpr (kNearField<Fiber>) {
        if (h.is_none()) throw py::value_error("h: this near-field model needs the offsets h in [-1, 1]");
        Rows<T> r = rows_of<T>(h, "h", 0);
        shape.add(r, "h");
        return r;
    } else {
        if (!h.is_none()) throw py::value_error("h: this far-field model integrates over h; pass h=None");
        Rows<T> r;
        static const T zero = T(0);
        r.data = &zero;
        return r;
    }
}

template <typename Fiber> class DualOf final : public DualModel {
  public:
    using T = typename Fiber::Real;
    using Material = typename Fiber::Material;
    using Bcsdf = DualScatteringBcsdf<Fiber>;

    DualOf(std::shared_ptr<const Material> material, std::shared_ptr<const DualScatteringTables<T>> tables)
        : mat_(std::move(material)), tables_(std::move(tables)) {}

    py::object eval(py::handle wo_, py::handle wi_, py::handle h_, py::handle direct_, py::handle n_,
                    py::handle beyond_) const override {
        CallShape shape;
        const Rows<T> wo = arg(wo_, "wo", 3, shape), wi = arg(wi_, "wi", 3, shape);
        const Rows<T> h = offsets<Fiber>(h_, shape);
        const Rows<T> direct = arg(direct_, "direct_fraction", 0, shape), n = arg(n_, "n", 0, shape),
                      beyond = arg(beyond_, "beyond", 0, shape);
        py::array_t<T> out = shape.result<T>(3);
        T* o = out.mutable_data();
        for_rows(shape.n(), [&](py::ssize_t i) {
            if (!usable_offset<Fiber>(h.scalar(i))) return store3(o, i, glm::vec<3, T>(T(0)));
            store3(o, i, bcsdf(h.scalar(i)).eval(vec3_at(wo, i), vec3_at(wi, i), light(direct, n, beyond, i)));
        });
        return std::move(out);
    }

    py::object pdf(py::handle wo_, py::handle wi_, py::handle h_, py::handle spread_) const override {
        CallShape shape;
        const Rows<T> wo = arg(wo_, "wo", 3, shape), wi = arg(wi_, "wi", 3, shape);
        const Rows<T> h = offsets<Fiber>(h_, shape);
        const Rows<T> spread = arg(spread_, "spread", 0, shape);
        py::array_t<T> out = shape.result<T>(0);
        T* o = out.mutable_data();
        for_rows(shape.n(), [&](py::ssize_t i) {
            o[i] = usable_offset<Fiber>(h.scalar(i))
                       ? bcsdf(h.scalar(i)).at(vec3_at(wo, i), spread.scalar(i)).pdf(vec3_at(wi, i))
                       : T(0);
        });
        return finish(out);
    }

    DualSampleResult sample(py::handle wo_, py::handle u_, py::handle h_, py::handle spread_, py::handle direct_,
                            py::handle n_, py::handle beyond_) const override {
        CallShape shape;
        const Rows<T> wo = arg(wo_, "wo", 3, shape), u = arg(u_, "u", 4, shape);
        const Rows<T> h = offsets<Fiber>(h_, shape);
        const Rows<T> spread = arg(spread_, "spread", 0, shape), direct = arg(direct_, "direct_fraction", 0, shape),
                      n = arg(n_, "n", 0, shape), beyond = arg(beyond_, "beyond", 0, shape);
        py::array_t<T> wi = shape.result<T>(3), f = shape.result<T>(3), weight = shape.result<T>(3),
                       pdf = shape.result<T>(0);
        py::array_t<std::int8_t> component = shape.result<std::int8_t>(0);
        T *wi_o = wi.mutable_data(), *f_o = f.mutable_data(), *w_o = weight.mutable_data(), *p_o = pdf.mutable_data();
        std::int8_t* c_o = component.mutable_data();
        for_rows(shape.n(), [&](py::ssize_t i) {
            const DualSample<T> s = usable_offset<Fiber>(h.scalar(i))
                                        ? bcsdf(h.scalar(i))
                                              .at(vec3_at(wo, i), spread.scalar(i))
                                              .sample(vec4_at(u, i), light(direct, n, beyond, i))
                                        : DualSample<T>{};
            store3(wi_o, i, s.wi);
            store3(f_o, i, s.f);
            store3(w_o, i, s.weight);
            p_o[i] = s.pdf;
            c_o[i] = std::int8_t(s.component);
        });
        return {std::move(wi), finish(pdf), std::move(component), std::move(f), std::move(weight)};
    }

  private:
    static Rows<T> arg(py::handle obj, const char* name, int width, CallShape& shape) {
        Rows<T> r = rows_of<T>(obj, name, width);
        shape.add(r, name);
        return r;
    }
    static DualScatteringLight<T> light(const Rows<T>& direct, const Rows<T>& n, const Rows<T>& beyond, py::ssize_t i) {
        DualScatteringLight<T> l;
        l.direct_fraction = direct.scalar(i);
        l.n = n.scalar(i);
        l.beyond = beyond.scalar(i);
        return l;
    }
    Bcsdf bcsdf(T h) const { return Bcsdf(ModelOf<Fiber>::fiber_of(*mat_, h), tables_->view()); }

    std::shared_ptr<const Material> mat_;
    std::shared_ptr<const DualScatteringTables<T>> tables_;
};

template <typename Fiber> class ModelOf final : public Model {
  public:
    using T = typename Fiber::Real;
    using V3 = glm::vec<3, T>;
    using Material = typename Fiber::Material;
    static constexpr int kSplitLobes = Fiber::kLobes + 1;

    explicit ModelOf(std::shared_ptr<const Material> material) : mat_(std::move(material)) {}

    static Fiber fiber_of(const Material& m, T h) {
        if constexpr (kNearField<Fiber>)
            return Fiber(m, h);
        else {
            (void)h;
            return Fiber(m);
        }
    }

    py::object eval(py::handle wo_, py::handle wi_, py::handle h_) const override {
        py::array_t<T> f;
        per_pair(wo_, wi_, h_, f, [](const Fiber& fiber, const V3& wo, const V3& wi) { return fiber.eval(wo, wi); });
        return std::move(f);
    }

    py::object pdf(py::handle wo_, py::handle wi_, py::handle h_) const override {
        py::array_t<T> pdf;
        per_pair(wo_, wi_, h_, pdf, [](const Fiber& fiber, const V3& wo, const V3& wi) { return fiber.pdf(wo, wi); });
        return finish(pdf);
    }

    py::tuple eval_pdf(py::handle wo_, py::handle wi_, py::handle h_) const override {
        py::array_t<T> f, pdf;
        per_pair(wo_, wi_, h_, f, pdf,
                 [](const Fiber& fiber, const V3& wo, const V3& wi) { return fiber.eval_pdf(wo, wi); });
        return py::make_tuple(std::move(f), finish(pdf));
    }

    SampleResult sample(py::handle wo_, py::handle u_, py::handle h_) const override {
        CallShape shape;
        const Rows<T> wo = rows_of<T>(wo_, "wo", 3), u = rows_of<T>(u_, "u", 4);
        shape.add(wo, "wo");
        shape.add(u, "u");
        const Rows<T> h = offsets<Fiber>(h_, shape);
        py::array_t<T> wi = shape.result<T>(3), weight = shape.result<T>(3), pdf = shape.result<T>(0);
        py::array_t<std::int8_t> lobe = shape.result<std::int8_t>(0);
        T *wi_o = wi.mutable_data(), *w_o = weight.mutable_data(), *p_o = pdf.mutable_data();
        std::int8_t* l_o = lobe.mutable_data();
        const Material& m = *mat_;
        for_rows(shape.n(), [&](py::ssize_t i) {
            const HairSample<T> s = usable_offset<Fiber>(h.scalar(i))
                                        ? fiber_of(m, h.scalar(i)).sample(vec3_at(wo, i), vec4_at(u, i))
                                        : HairSample<T>{};
            store3(wi_o, i, s.wi);
            store3(w_o, i, s.weight);
            p_o[i] = s.pdf;
            l_o[i] = std::int8_t(lobe_index(s.lobe));
        });
        return {std::move(wi), std::move(weight), finish(pdf), std::move(lobe)};
    }

    py::object albedo(py::handle wo_, py::handle h_) const override {
        CallShape shape;
        const Rows<T> wo = rows_of<T>(wo_, "wo", 3);
        shape.add(wo, "wo");
        const Rows<T> h = offsets<Fiber>(h_, shape);
        py::array_t<T> out = shape.result<T>(3);
        T* o = out.mutable_data();
        const Material& m = *mat_;
        // A bad wo is the C++ call's to refuse (0); a row with a non-finite h is 0 too.
        for_rows(shape.n(), [&](py::ssize_t i) {
            const T hh = h.scalar(i);
            store3(o, i, usable_offset<Fiber>(hh) ? fiber_of(m, hh).albedo(vec3_at(wo, i)) : V3(T(0)));
        });
        return std::move(out);
    }

    py::tuple lobe_split(py::handle wo_, py::handle h_, py::handle centre_) const override {
        if constexpr (has_lobe_split_v<Fiber>) {
            CallShape shape;
            const Rows<T> wo = rows_of<T>(wo_, "wo", 3), centre = rows_of<T>(centre_, "centre", 0);
            shape.add(wo, "wo");
            shape.add(centre, "centre");
            const Rows<T> h = offsets<Fiber>(h_, shape);
            py::array_t<T> a = shape.result<T>({kSplitLobes, 3}), backward = shape.result<T>({kSplitLobes});
            T *a_o = a.mutable_data(), *b_o = backward.mutable_data();
            const Material& m = *mat_;
            // A bad wo is the C++ call's to refuse (no energy, each half 1/2); a row with a
            // non-finite h or centre gets the same empty split.
            for_rows(shape.n(), [&](py::ssize_t i) {
                const T hh = h.scalar(i), c = centre.scalar(i);
                const typename Fiber::LobeSplit s = usable_offset<Fiber>(hh) && is_finite(c)
                                                        ? fiber_of(m, hh).lobe_split(vec3_at(wo, i), c)
                                                        : empty_lobe_split<T, Fiber::kLobes>();
                for (int p = 0; p < kSplitLobes; ++p) {
                    store3(a_o, i * kSplitLobes + p, s.a[p]);
                    b_o[i * kSplitLobes + p] = s.backward[p];
                }
            });
            return py::make_tuple(std::move(a), std::move(backward));
        } else {
            (void)wo_, (void)h_, (void)centre_;
            throw py::type_error("lobe_split: this model does not split its albedo per lobe (Marschner et al. 2003)");
        }
    }

    Tables dual_tables(int theta_samples, int psi_samples, int h_nodes, const std::string& formulation, py::object d_f,
                       py::object d_b) const override {
        if constexpr (kWithDual<Fiber>) {
            DualTableOptions<T> opt;
            opt.theta_samples = theta_samples;
            opt.psi_samples = psi_samples;
            opt.h_nodes = h_nodes;
            if (formulation == "zinke2008")
                opt.settings = DualScatteringSettings<T>::zinke2008();
            else if (formulation != "improved")
                throw py::value_error("formulation: '" + formulation + "' is neither 'improved' nor 'zinke2008'");
            if (!d_f.is_none()) opt.settings.d_f = d_f.cast<T>();
            if (!d_b.is_none()) opt.settings.d_b = d_b.cast<T>();
            std::shared_ptr<const DualScatteringTables<T>> t;
            {
                py::gil_scoped_release no_gil;
                t = std::make_shared<const DualScatteringTables<T>>(
                    DualScatteringTables<T>::template build<Fiber>(*mat_, opt));
            }
            return Tables{t};
        } else {
            (void)theta_samples, (void)psi_samples, (void)h_nodes, (void)formulation, (void)d_f, (void)d_b;
            throw py::type_error(std::string("dual_tables: ") + no_dual_reason<Fiber>());
        }
    }

    std::shared_ptr<const DualModel> dual(const Tables& tables) const override {
        if constexpr (kWithDual<Fiber> || !has_lobe_split_v<Fiber>) {
            using Ptr = std::shared_ptr<const DualScatteringTables<T>>;
            const Ptr* t = std::get_if<Ptr>(&tables.tables);
            if (t == nullptr)
                throw py::value_error("tables: their dtype differs from the model's (" +
                                      py::str(dtype()).cast<std::string>() + ")");
            return std::make_shared<DualOf<Fiber>>(mat_, *t);
        } else {
            (void)tables;
            throw py::type_error(std::string("DualScatteringBcsdf: ") + no_dual_reason<Fiber>());
        }
    }

    bool near_field() const override { return kNearField<Fiber>; }
    py::dtype dtype() const override { return dtype_of<T>(); }

  private:
    // The (N, 3) or (N,) result of query(fiber at h, wo, wi) per row: eval or pdf.
    template <typename Query>
    void per_pair(py::handle wo_, py::handle wi_, py::handle h_, py::array_t<T>& out, Query&& query) const {
        const Pair a(wo_, wi_, h_);
        using R = decltype(query(std::declval<const Fiber&>(), V3(), V3()));
        out = a.shape.template result<T>(std::is_same_v<R, V3> ? 3 : 0);
        T* o = out.mutable_data();
        const Material& m = *mat_;
        for_rows(a.shape.n(), [&](py::ssize_t i) {
            const R r = usable_offset<Fiber>(a.h.scalar(i))
                            ? query(fiber_of(m, a.h.scalar(i)), vec3_at(a.wo, i), vec3_at(a.wi, i))
                            : R(T(0));
            if constexpr (std::is_same_v<R, V3>)
                store3(o, i, r);
            else
                o[i] = r;
        });
    }
    // The same for eval_pdf: f (N, 3) and pdf (N,).
    template <typename Query>
    void per_pair(py::handle wo_, py::handle wi_, py::handle h_, py::array_t<T>& f, py::array_t<T>& pdf,
                  Query&& query) const {
        const Pair a(wo_, wi_, h_);
        f = a.shape.template result<T>(3);
        pdf = a.shape.template result<T>(0);
        T *f_o = f.mutable_data(), *p_o = pdf.mutable_data();
        const Material& m = *mat_;
        for_rows(a.shape.n(), [&](py::ssize_t i) {
            const HairEvalPdf<T> e = usable_offset<Fiber>(a.h.scalar(i))
                                         ? query(fiber_of(m, a.h.scalar(i)), vec3_at(a.wo, i), vec3_at(a.wi, i))
                                         : HairEvalPdf<T>{};
            store3(f_o, i, e.f);
            p_o[i] = e.pdf;
        });
    }

    // wo, wi and h, converted and checked together.
    struct Pair {
        CallShape shape;
        Rows<T> wo, wi, h;
        Pair(py::handle wo_, py::handle wi_, py::handle h_) : wo(rows_of<T>(wo_, "wo", 3)), wi(rows_of<T>(wi_, "wi", 3)) {
            shape.add(wo, "wo");
            shape.add(wi, "wi");
            h = offsets<Fiber>(h_, shape);
        }
    };

    std::shared_ptr<const Material> mat_;
};

// A PyModel of Fiber over a material built from the arguments.
template <typename Fiber, typename... Args> std::shared_ptr<const Model> make_model(Args&&... args) {
    using Material = typename Fiber::Material;
    auto material = std::make_shared<const Material>(std::forward<Args>(args)...);
    return std::make_shared<const ModelOf<Fiber>>(std::move(material));
}

}  // namespace hairscatter::python

namespace hairscatter::python {

// FiberParams<T> from the keyword arguments of the Python constructors (validated by the
// material that takes them).
template <typename T>
FiberParams<T> fiber_params(double eta, double beta_m, double beta_n, double alpha, const glm::dvec3& sigma_a) {
    FiberParams<T> p;
    p.eta = T(eta);
    p.beta_m = T(beta_m);
    p.beta_n = T(beta_n);
    p.alpha = T(alpha);
    p.sigma_a = glm::vec<3, T>(sigma_a);
    return p;
}

// The parameters of FiberParams as a model's params dict (extended by each model).
inline py::dict fiber_params_dict(double eta, double beta_m, double beta_n, double alpha, const glm::dvec3& sigma_a) {
    return py::dict(py::arg("eta") = eta, py::arg("beta_m") = beta_m, py::arg("beta_n") = beta_n,
                    py::arg("alpha") = alpha, py::arg("sigma_a") = py::make_tuple(sigma_a.x, sigma_a.y, sigma_a.z));
}

// The model of the precision dtype= asks for: make(T{}) with T float or double.
template <typename Make> std::shared_ptr<const Model> with_precision(const py::object& dtype, Make&& make) {
    if (precision_of(dtype) == Precision::kFloat) return make(float{});
    return make(double{});
}

}  // namespace hairscatter::python
