// hairscatter Python bindings: the module, argument conversion, the FiberModel base class
// with the vectorised contract, and the helpers (pigments, lobe controls, per-strand
// variation, fiber frames). docs/python.md.
#include <sstream>

#include "common.hpp"

namespace hairscatter::python {

Precision precision_of(const py::object& dtype) {
    py::dtype dt;
    try {
        dt = py::dtype::from_args(dtype);
    } catch (const py::error_already_set&) {
        throw py::value_error("dtype: " + std::string(py::repr(dtype)) + " is not a numpy dtype (float32 or float64)");
    }
    if (dt.kind() == 'f' && dt.itemsize() == 4) return Precision::kFloat;
    if (dt.kind() == 'f' && dt.itemsize() == 8) return Precision::kDouble;
    throw py::value_error("dtype: " + std::string(py::str(dt)) + " is neither float32 nor float64");
}

namespace detail {

py::array numeric_array(py::handle obj, const char* name) {
    if (obj.is_none()) throw py::value_error(std::string(name) + ": expected numbers, got None");
    py::array a;
    try {
        a = py::array::ensure(obj);
    } catch (const py::error_already_set&) {
    }
    if (!a) throw py::value_error(std::string(name) + ": cannot be read as a numpy array of numbers");
    const char kind = a.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b')
        throw py::value_error(std::string(name) + ": expected real numbers, got dtype " + std::string(py::str(a.dtype())));
    return a;
}

std::string shape_text(const py::array& a) {
    std::ostringstream s;
    s << "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k) s << (k ? ", " : "") << a.shape(k);
    s << (a.ndim() == 1 ? ",)" : ")");
    return s.str();
}

}  // namespace detail

glm::dvec3 vec3_arg(const py::object& v, const char* name) {
    const Rows<double> r = rows_of<double>(v, name, 3);
    if (r.batched) throw py::value_error(std::string(name) + ": expected three numbers, got " + detail::shape_text(r.array));
    return glm::dvec3(r.data[0], r.data[1], r.data[2]);
}

LobeControls<double> controls_arg(const py::object& controls) {
    if (controls.is_none()) return LobeControls<double>();
    try {
        return controls.cast<LobeControls<double>>();
    } catch (const py::cast_error&) {
        throw py::value_error("controls: expected None or a hairscatter.LobeControls, got " +
                              std::string(py::str(py::type::of(controls))));
    }
}

namespace {

constexpr const char* kLobeNames[4] = {"r", "tt", "trt", "residual"};

// The Python LobeControls: keyword per lobe (the names validate() reports).
LobeControls<double> make_controls(const py::kwargs& kw) {
    LobeControls<double> c;
    for (const auto& item : kw) {
        const std::string key = py::str(item.first);
        bool known = false;
        for (int p = 0; p < 4 && !known; ++p) {
            if (key == std::string("gain_") + kLobeNames[p]) {
                c.gain[p] = item.second.cast<double>();
                known = true;
            } else if (key == std::string("tint_") + kLobeNames[p]) {
                c.tint[p] = vec3_arg(py::reinterpret_borrow<py::object>(item.second), key.c_str());
                known = true;
            } else if (p < 3 && key == std::string("alpha_") + kLobeNames[p]) {
                if (!item.second.is_none()) c.override_alpha(p, item.second.cast<double>());
                known = true;
            }
        }
        if (!known)
            throw py::type_error("LobeControls: unknown keyword '" + key +
                                 "' (gain_X, tint_X for X in r, tt, trt, residual; alpha_X for X in r, tt, trt)");
    }
    return c;
}

py::array_t<double> vec3_array(const glm::dvec3& v) {
    py::array_t<double> a(3);
    double* d = a.mutable_data();
    for (int k = 0; k < 3; ++k) d[k] = v[k];
    return a;
}

// Applies f(w) → vec3 to every row of w (shape (3,) or (N, 3)).
template <typename F> py::array_t<double> map3(py::handle w_, const char* name, F&& f) {
    const Rows<double> w = rows_of<double>(w_, name, 3);
    CallShape shape;
    shape.add(w, name);
    py::array_t<double> out = shape.result<double>(3);
    double* o = out.mutable_data();
    for_rows(shape.n(), [&](py::ssize_t i) { store3(o, i, f(vec3_at(w, i))); });
    return out;
}

}  // namespace

void bind_helpers(py::module_& m) {
    // Pigments (docs/controls.md).
    const auto from_concentrations = [](double eumelanin, double pheomelanin) {
        return vec3_array(sigma_a_from_concentrations(eumelanin, pheomelanin));
    };
    m.def("sigma_a_from_concentrations", from_concentrations, py::arg("eumelanin"), py::arg("pheomelanin") = 0.0,
          "Absorption per unit fiber radius from eumelanin and pheomelanin concentrations (pbrt-v4's "
          "SigmaAFromConcentration, Mitsuba 3's eumelanin/pheomelanin; Chiang et al. 2016 §4.3): "
          "ce (0.419, 0.697, 1.37) + cp (0.187, 0.4, 1.05). Not an amount in [0, 1]: see "
          "sigma_a_from_melanin_amount.");
    m.def("sigma_a_from_melanin", from_concentrations, py::arg("eumelanin"), py::arg("pheomelanin") = 0.0,
          "The former name of sigma_a_from_concentrations (it takes concentrations).");
    m.def(
        "melanin_concentrations",
        [](double melanin, double redness) {
            const MelaninConcentrations<double> c = melanin_concentrations(melanin, redness);
            return py::make_tuple(c.eumelanin, c.pheomelanin);
        },
        py::arg("melanin"), py::arg("redness") = 0.0,
        "(eumelanin, pheomelanin) of Cycles' melanin amount m and redness r: c = -ln(max(1 - m, 1e-4)), split "
        "c (1 - r), c r.");
    const auto from_amount = [](double melanin, double redness) {
        return vec3_array(sigma_a_from_melanin_amount(melanin, redness));
    };
    m.def("sigma_a_from_melanin_amount", from_amount, py::arg("melanin"), py::arg("redness") = 0.0,
          "σa of Cycles' melanin amount m ∈ [0, 1] and redness r ∈ [0, 1] (Principled Hair's Melanin and "
          "Melanin Redness): melanin_concentrations, then sigma_a_from_concentrations.");
    m.def("sigma_a_from_melanin_redness", from_amount, py::arg("melanin"), py::arg("redness") = 0.0,
          "The former name of sigma_a_from_melanin_amount (it takes an amount in [0, 1]).");
    m.def(
        "sigma_a_from_dye",
        [](const py::object& dye, double beta_n) { return vec3_array(sigma_a_from_dye(vec3_arg(dye, "dye"), beta_n)); },
        py::arg("dye"), py::arg("beta_n") = 0.3,
        "σa of a dye colour (channels in (0, 1]; white adds nothing) at azimuthal roughness beta_n (Chiang et "
        "al. 2016 eq. 9, unchecked).");
    m.def(
        "sigma_a_from_color",
        [](const py::object& color, double beta_n) {
            return vec3_array(sigma_a_from_color(vec3_arg(color, "color"), beta_n));
        },
        py::arg("color"), py::arg("beta_n") = 0.3,
        "σa that gives roughly the diffuse-looking colour (channels in (0, 1]) at azimuthal roughness beta_n "
        "(Chiang et al. 2016 eq. 9). Raises ValueError outside the ranges.");
    m.def(
        "sigma_a_from_pigments",
        [](double melanin, double redness, const py::object& dye, double beta_n) {
            HairPigments<double> p;
            p.melanin = melanin;
            p.redness = redness;
            p.dye = vec3_arg(dye, "dye");
            require_valid(p);
            return vec3_array(sigma_a_from_pigments(p, beta_n));
        },
        py::arg("melanin") = HairPigments<double>().melanin, py::arg("redness") = 0.0,
        py::arg("dye") = py::make_tuple(1.0, 1.0, 1.0), py::arg("beta_n") = 0.3,
        "σa of the whole colour: melanin amount and redness plus a dye at beta_n, validated (ValueError naming "
        "the bad field).");

    // Per-lobe controls.
    py::class_<LobeControls<double>>(m, "LobeControls",
                                     "Per-lobe gains, RGB tints and cuticle tilts (docs/controls.md): A_p ← gain_p · "
                                     "tint_p · A_p; alpha_X replaces the tilt of lobe X. Validated by the model "
                                     "that takes them.")
        .def(py::init(&make_controls),
             "LobeControls(**kw): gain_r, gain_tt, gain_trt, gain_residual (in [0, 1e6]); tint_r … tint_residual "
             "(RGB, each in [0, 1e6]); alpha_r, alpha_tt, alpha_trt (radians, |α| ≤ π/8; None keeps the fiber's).")
        .def_property_readonly("gain",
                               [](const LobeControls<double>& c) {
                                   return py::make_tuple(c.gain[0], c.gain[1], c.gain[2], c.gain[3]);
                               })
        .def_property_readonly("tint",
                               [](const LobeControls<double>& c) {
                                   py::array_t<double> a({4, 3});
                                   for (int p = 0; p < 4; ++p) store3(a.mutable_data(), p, c.tint[p]);
                                   return a;
                               })
        .def_property_readonly("alpha",
                               [](const LobeControls<double>& c) {
                                   py::list l;
                                   for (int p = 0; p < 3; ++p)
                                       l.append(((c.alpha_override >> p) & 1u) ? py::object(py::float_(c.alpha[p]))
                                                                                : py::object(py::none()));
                                   return py::tuple(l);
                               })
        .def("validate", [](const LobeControls<double>& c) { return validate(c); },
             "The C++ validation's message: empty when valid, else one clause per bad field.");

    // Per-strand variation.
    py::class_<StrandVariation<double>>(m, "StrandVariation",
                                        "What varies from strand to strand, each uniformly in its interval "
                                        "(docs/controls.md): strand s's values are a PCG hash of (s, seed).")
        .def(py::init([](std::uint32_t seed, std::pair<double, double> melanin, std::pair<double, double> redness,
                         std::pair<double, double> roughness_scale) {
                 StrandVariation<double> v;
                 v.seed = seed;
                 v.melanin = {melanin.first, melanin.second};
                 v.redness = {redness.first, redness.second};
                 v.roughness_scale = {roughness_scale.first, roughness_scale.second};
                 require_valid(v);
                 return v;
             }),
             py::arg("seed") = 0u, py::arg("melanin") = std::make_pair(0.8, 0.8),
             py::arg("redness") = std::make_pair(0.0, 0.0), py::arg("roughness_scale") = std::make_pair(1.0, 1.0))
        .def(
            "at",
            [](const StrandVariation<double>& v, std::uint32_t strand) {
                const StrandTraits<double> s = v.at(strand);
                return py::dict(py::arg("melanin") = s.melanin, py::arg("redness") = s.redness,
                                py::arg("roughness_scale") = s.roughness_scale);
            },
            py::arg("strand"), "The strand's melanin, redness and roughness_scale.")
        .def(
            "params",
            [](const StrandVariation<double>& v, std::uint32_t strand, double eta, double beta_m, double beta_n,
               double alpha, const py::object& dye) {
                FiberParams<double> base;
                base.eta = eta;
                base.beta_m = beta_m;
                base.beta_n = beta_n;
                base.alpha = alpha;
                const FiberParams<double> p = strand_params(base, v.at(strand), vec3_arg(dye, "dye"));
                return py::dict(py::arg("eta") = p.eta, py::arg("beta_m") = p.beta_m, py::arg("beta_n") = p.beta_n,
                                py::arg("alpha") = p.alpha, py::arg("sigma_a") = vec3_array(p.sigma_a));
            },
            py::arg("strand"), py::arg("eta") = FiberParams<double>().eta, py::arg("beta_m") = FiberParams<double>().beta_m,
            py::arg("beta_n") = FiberParams<double>().beta_n, py::arg("alpha") = FiberParams<double>().alpha,
            py::arg("dye") = py::make_tuple(1.0, 1.0, 1.0),
            "The strand's fiber parameters as keyword arguments of Chiang, DeonFarField or Tabulated: β times the "
            "strand's roughness scale (clamped into [1e-3, 1]), σa from its melanin and redness plus the dye.");

    // Frames.
    py::class_<FiberFrame<double>>(m, "FiberFrame",
                                   "The fiber frame: x = tangent (root to tip), y across the fiber (the h axis), "
                                   "z = x × y. With reference = wo, wo lies in the x–z plane and h = dot(hit - "
                                   "axis, y) / radius.")
        .def(py::init([](const py::object& tangent, const py::object& reference) {
                 return FiberFrame<double>(vec3_arg(tangent, "tangent"), vec3_arg(reference, "reference"));
             }),
             py::arg("tangent"), py::arg("reference"))
        .def_static(
            "facing",
            [](const py::object& tangent, const py::object& reference, const py::object& wo) {
                return FiberFrame<double>::facing(vec3_arg(tangent, "tangent"), vec3_arg(reference, "reference"),
                                                  vec3_arg(wo, "wo"));
            },
            py::arg("tangent"), py::arg("reference"), py::arg("wo"),
            "The frame with z on wo's side (a ribbon's normal seen from behind is flipped first).")
        .def_property_readonly("x", [](const FiberFrame<double>& f) { return vec3_array(f.x); })
        .def_property_readonly("y", [](const FiberFrame<double>& f) { return vec3_array(f.y); })
        .def_property_readonly("z", [](const FiberFrame<double>& f) { return vec3_array(f.z); })
        .def(
            "to_local",
            [](const FiberFrame<double>& f, const py::object& w) {
                return map3(w, "w", [&](const glm::dvec3& v) { return f.to_local(v); });
            },
            py::arg("w"), "World directions (3,) or (N, 3) into the fiber frame.")
        .def(
            "to_world",
            [](const FiberFrame<double>& f, const py::object& w) {
                return map3(w, "w", [&](const glm::dvec3& v) { return f.to_world(v); });
            },
            py::arg("w"), "Fiber-frame directions (3,) or (N, 3) into the world.");
}

void bind_model_base(py::module_& m) {
    py::class_<SampleResult>(m, "Sample", "What FiberModel.sample returns: arrays of N rows (or one row).")
        .def_readonly("wi", &SampleResult::wi, "sampled directions toward the light, (N, 3); 0 for no sample")
        .def_readonly("weight", &SampleResult::weight, "eval / pdf, (N, 3)")
        .def_readonly("pdf", &SampleResult::pdf, "solid-angle density, (N,); 0 for no sample")
        .def_readonly("lobe", &SampleResult::lobe,
                      "the lobe drawn, (N,) int8: 0 R, 1 TT, 2 TRT, 3 residual, 8 no sample (LOBE_NAMES)");

    const char* h_doc = "h: offsets across the fiber, () or (N,), for near-field models (Chiang); None for the others.";
    py::class_<PyModel>(m, "FiberModel",
                        "A fiber model of the contract (docs/models.md). Directions are unit vectors in the fiber "
                        "frame (x = tangent, sinθ = w.x, φ = atan2(w.z, w.y)), wo toward the viewer, wi toward the "
                        "light; (3,) or (N, 3) arrays, broadcast against each other. Non-finite input gives 0.")
        .def_property_readonly("dtype", [](const PyModel& p) { return p.model->dtype(); },
                               "float32 or float64: the C++ real type; inputs are converted to it")
        .def_property_readonly("near_field", [](const PyModel& p) { return p.model->near_field(); },
                               "whether the calls take the offset h")
        .def_property_readonly("params", [](const PyModel& p) { return p.params; }, "the constructor's arguments")
        .def("__repr__",
             [](const PyModel& p) {
                 std::string s = "hairscatter." + p.name + "(";
                 for (const auto& item : p.params)
                     s += py::str(item.first).cast<std::string>() + "=" + py::repr(item.second).cast<std::string>() + ", ";
                 return s + "dtype=" + py::str(p.model->dtype()).cast<std::string>() + ")";
             })
        .def("eval", [](const PyModel& p, py::handle wo, py::handle wi, py::handle h) { return p.model->eval(wo, wi, h); },
             py::arg("wo"), py::arg("wi"), py::arg("h") = py::none(),
             (std::string("f(wo, wi), RGB with the cosine inside: Lo = ∫ eval Li dωi; (N, 3) or (3,). ") + h_doc).c_str())
        .def("pdf", [](const PyModel& p, py::handle wo, py::handle wi, py::handle h) { return p.model->pdf(wo, wi, h); },
             py::arg("wo"), py::arg("wi"), py::arg("h") = py::none(),
             (std::string("The solid-angle density sample() draws wi with; (N,) or a float. ") + h_doc).c_str())
        .def("eval_pdf",
             [](const PyModel& p, py::handle wo, py::handle wi, py::handle h) { return p.model->eval_pdf(wo, wi, h); },
             py::arg("wo"), py::arg("wi"), py::arg("h") = py::none(), "(eval, pdf) in one pass.")
        .def("sample", [](const PyModel& p, py::handle wo, py::handle u, py::handle h) { return p.model->sample(wo, u, h); },
             py::arg("wo"), py::arg("u"), py::arg("h") = py::none(),
             (std::string("Directions wi drawn from four uniform numbers u, (4,) or (N, 4), clamped into [0, 1]: a "
                          "Sample (wi, weight = eval / pdf, pdf, lobe). ") +
              h_doc)
                 .c_str())
        .def("albedo", [](const PyModel& p, py::handle wo, py::handle h) { return p.model->albedo(wo, h); },
             py::arg("wo"), py::arg("h") = py::none(),
             "∫ eval(wo, wi) dωi, RGB (exact for the energy-conserving models; Marschner's is a 4,096-sample "
             "estimate).")
        .def("lobe_split",
             [](const PyModel& p, py::handle wo, py::handle h, py::handle centre) {
                 return p.model->lobe_split(wo, h, centre);
             },
             py::arg("wo"), py::arg("h") = py::none(), py::arg("centre") = 0.0,
             "(a, backward): per lobe p (R, TT, TRT, residual) A_p(wo), (N, 4, 3), and the fraction of N_p in "
             "|φ - centre| < π/2, (N, 4): what the dual-scattering tables integrate. TypeError for Marschner.")
        .def("dual_tables",
             [](const PyModel& p, int theta_samples, int psi_samples, int h_nodes, const std::string& formulation,
                py::object d_f, py::object d_b) {
                 return p.model->dual_tables(theta_samples, psi_samples, h_nodes, formulation, d_f, d_b);
             },
             py::arg("theta_samples") = DualTableOptions<double>().theta_samples,
             py::arg("psi_samples") = DualTableOptions<double>().psi_samples,
             py::arg("h_nodes") = DualTableOptions<double>().h_nodes, py::arg("formulation") = "improved",
             py::arg("d_f") = py::none(), py::arg("d_b") = py::none(),
             "Builds the dual-scattering tables of this model (Zinke et al. 2008 §4.1; docs/dual.md): a_f, a_b, "
             "the lobes' shifts and variances, the backscattering terms and the windows W_p. formulation "
             "'improved' or 'zinke2008'; d_f, d_b override its density factors.");
}

}  // namespace hairscatter::python

PYBIND11_MODULE(_core, m) {
    namespace hp = hairscatter::python;
    m.doc() = "hairscatter: physically based hair scattering (C++ header-only library), vectorised over numpy arrays.";
    m.attr("__version__") = std::to_string(HAIRSCATTER_VERSION_MAJOR) + "." + std::to_string(HAIRSCATTER_VERSION_MINOR) +
                            "." + std::to_string(HAIRSCATTER_VERSION_PATCH);
    hp::bind_helpers(m);
    hp::bind_model_base(m);
    hp::bind_chiang(m);
    hp::bind_farfield(m);
    hp::bind_other_models(m);
    hp::bind_dual(m);
}
