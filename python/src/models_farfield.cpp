// hairscatter Python bindings: d'Eon et al. 2011's far-field fiber and the same tabulated.
#include "model_impl.hpp"

namespace hairscatter::python {
namespace {

struct PyDeonFarField : PyModel {};
struct PyTabulated : PyModel {};

TabulatedOptions tabulated_options(const py::object& preset, int phi_samples, int theta_samples, int h_nodes,
                                   const std::string& longitudinal, int m_rows, int m_nodes) {
    TabulatedOptions o;
    if (!preset.is_none()) {
        const std::string name = preset.cast<std::string>();
        if (name == "coarse") return TabulatedOptions::coarse();
        if (name == "fine") return TabulatedOptions::fine();
        if (name == "fast") return TabulatedOptions::fast();
        if (name != "default") throw py::value_error("preset: '" + name + "' is not one of coarse, default, fine, fast");
        return o;
    }
    o.phi_samples = phi_samples;
    o.theta_samples = theta_samples;
    o.h_nodes = h_nodes;
    if (longitudinal == "table")
        o.longitudinal = TabulatedLongitudinal::kTable;
    else if (longitudinal != "exact")
        throw py::value_error("longitudinal: '" + longitudinal + "' is neither 'exact' nor 'table'");
    o.m_rows = m_rows;
    o.m_nodes = m_nodes;
    return o;
}

}  // namespace

void bind_farfield(py::module_& m) {
    const FiberParams<double> d;
    py::class_<PyDeonFarField, PyModel>(
        m, "DeonFarField",
        "d'Eon et al. 2011's far-field fiber: N_p integrated over h by Gauss–Legendre in γ = asin h with a "
        "wrapped-Gaussian detector; no h from the renderer (calls take h=None). Energy and sampling are exact at "
        "any node count; the cost is linear in it.")
        .def(py::init([](double eta, double beta_m, double beta_n, double alpha, const py::object& sigma_a, int nodes,
                         const py::object& controls, const py::object& dtype) {
                 const glm::dvec3 s = vec3_arg(sigma_a, "sigma_a");
                 const LobeControls<double> c = controls_arg(controls);
                 PyDeonFarField p;
                 p.name = "DeonFarField";
                 p.model = with_precision(dtype, [&](auto t) {
                     using T = decltype(t);
                     return make_model<DeonFarFieldFiber<T>>(fiber_params<T>(eta, beta_m, beta_n, alpha, s), nodes,
                                                            controls_as<T>(c));
                 });
                 p.params = fiber_params_dict(eta, beta_m, beta_n, alpha, s);
                 p.params["nodes"] = nodes;
                 return p;
             }),
             py::kw_only(), py::arg("eta") = d.eta, py::arg("beta_m") = d.beta_m, py::arg("beta_n") = d.beta_n,
             py::arg("alpha") = d.alpha, py::arg("sigma_a") = py::make_tuple(0.0, 0.0, 0.0), py::arg("nodes") = 0,
             py::arg("controls") = py::none(), py::arg("dtype") = "float64",
             "The parameters of Chiang; nodes, the Gauss–Legendre order of the h integral, 1 … 256, or 0 for "
             "auto_nodes(beta_n) (34 at βn = 0.3, 156 at 0.1).");

    const TabulatedOptions o;
    py::class_<PyTabulated, PyModel>(
        m, "Tabulated",
        "The far-field fiber tabulated: d'Eon's h-integrated N_p·A_p over (|φ|, cosθo) per lobe and channel, "
        "rows normalised (the furnace stays 1 at any resolution), sampled exactly; M_p exact or tabulated "
        "(longitudinal='table', the 'fast' preset). Relative L1 against the exact far field at βn = 0.3: coarse "
        "0.00157, default 0.000427, fine 0.000106. Calls take h=None.")
        .def(py::init([](double eta, double beta_m, double beta_n, double alpha, const py::object& sigma_a,
                         const py::object& preset, int phi_samples, int theta_samples, int h_nodes,
                         const std::string& longitudinal, int m_rows, int m_nodes, const py::object& controls,
                         const py::object& dtype) {
                 const glm::dvec3 s = vec3_arg(sigma_a, "sigma_a");
                 const LobeControls<double> c = controls_arg(controls);
                 const TabulatedOptions opt =
                     tabulated_options(preset, phi_samples, theta_samples, h_nodes, longitudinal, m_rows, m_nodes);
                 PyTabulated p;
                 p.name = "Tabulated";
                 p.model = with_precision(dtype, [&](auto t) {
                     using T = decltype(t);
                     const FiberParams<T> fp = fiber_params<T>(eta, beta_m, beta_n, alpha, s);
                     const LobeControls<T> ct = controls_as<T>(c);
                     py::gil_scoped_release no_gil;  // building the tables takes a while
                     return make_model<TabulatedFiber<T>>(fp, opt, ct);
                 });
                 p.params = fiber_params_dict(eta, beta_m, beta_n, alpha, s);
                 p.params["phi_samples"] = opt.phi_samples;
                 p.params["theta_samples"] = opt.theta_samples;
                 p.params["h_nodes"] = opt.h_nodes;
                 p.params["longitudinal"] = opt.longitudinal == TabulatedLongitudinal::kTable ? "table" : "exact";
                 p.params["m_rows"] = opt.m_rows;
                 p.params["m_nodes"] = opt.m_nodes;
                 return p;
             }),
             py::kw_only(), py::arg("eta") = d.eta, py::arg("beta_m") = d.beta_m, py::arg("beta_n") = d.beta_n,
             py::arg("alpha") = d.alpha, py::arg("sigma_a") = py::make_tuple(0.0, 0.0, 0.0),
             py::arg("preset") = py::none(), py::arg("phi_samples") = o.phi_samples,
             py::arg("theta_samples") = o.theta_samples, py::arg("h_nodes") = o.h_nodes,
             py::arg("longitudinal") = "exact", py::arg("m_rows") = o.m_rows, py::arg("m_nodes") = o.m_nodes,
             py::arg("controls") = py::none(), py::arg("dtype") = "float64",
             "The parameters of Chiang; preset 'coarse', 'default', 'fine' or 'fast' (then the resolution "
             "arguments are ignored), or phi_samples × theta_samples (96 × 28), h_nodes (0: automatic), "
             "longitudinal 'exact' or 'table' with m_rows × m_nodes.");
}

}  // namespace hairscatter::python
