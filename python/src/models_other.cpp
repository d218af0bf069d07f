// hairscatter Python bindings: Marschner et al. 2003 and Huang et al. 2022's microfacet fiber.
#include "model_impl.hpp"

namespace hairscatter::python {
namespace {

struct PyMarschner : PyModel {};
struct PyHuang : PyModel {};

}  // namespace

void bind_other_models(py::module_& m) {
    const MarschnerParams<double> d;
    py::class_<PyMarschner, PyModel>(
        m, "Marschner",
        "Marschner et al. 2003: Gaussian M on θi + θo with Marschner's shifts, N from the roots of the cubic "
        "Φ̂(p, γ) = φ, the TRT caustic replaced as in the paper's §4.3, eccentricity through η*(φh), azimuthal "
        "roughness by Gauss–Hermite convolution (nodes). Far field (h=None); not energy conserving; no "
        "lobe_split (so no dual tables of its own).")
        .def(py::init([](double eta, const py::object& sigma_a, double alpha_r, double beta_r, double beta_n,
                         double eccentricity, double caustic_width, double caustic_gain, double caustic_fade,
                         double caustic_dh_max, int nodes, const py::object& controls, const py::object& dtype) {
                 const glm::dvec3 s = vec3_arg(sigma_a, "sigma_a");
                 const LobeControls<double> c = controls_arg(controls);
                 PyMarschner p;
                 p.name = "Marschner";
                 p.model = with_precision(dtype, [&](auto t) {
                     using T = decltype(t);
                     MarschnerParams<T> mp;
                     mp.eta = T(eta);
                     mp.sigma_a = glm::vec<3, T>(s);
                     mp.alpha_r = T(alpha_r);
                     mp.beta_r = T(beta_r);
                     mp.beta_n = T(beta_n);
                     mp.eccentricity = T(eccentricity);
                     mp.caustic_width = T(caustic_width);
                     mp.caustic_gain = T(caustic_gain);
                     mp.caustic_fade = T(caustic_fade);
                     mp.caustic_dh_max = T(caustic_dh_max);
                     return make_model<MarschnerFiber<T>>(mp, nodes, controls_as<T>(c));
                 });
                 p.params = py::dict(py::arg("eta") = eta, py::arg("sigma_a") = py::make_tuple(s.x, s.y, s.z),
                                     py::arg("alpha_r") = alpha_r, py::arg("beta_r") = beta_r,
                                     py::arg("beta_n") = beta_n, py::arg("eccentricity") = eccentricity,
                                     py::arg("caustic_width") = caustic_width, py::arg("caustic_gain") = caustic_gain,
                                     py::arg("caustic_fade") = caustic_fade, py::arg("caustic_dh_max") = caustic_dh_max,
                                     py::arg("nodes") = nodes);
                 return p;
             }),
             py::kw_only(), py::arg("eta") = d.eta, py::arg("sigma_a") = py::make_tuple(0.0, 0.0, 0.0),
             py::arg("alpha_r") = d.alpha_r, py::arg("beta_r") = d.beta_r, py::arg("beta_n") = d.beta_n,
             py::arg("eccentricity") = d.eccentricity, py::arg("caustic_width") = d.caustic_width,
             py::arg("caustic_gain") = d.caustic_gain, py::arg("caustic_fade") = d.caustic_fade,
             py::arg("caustic_dh_max") = d.caustic_dh_max, py::arg("nodes") = MarschnerMaterial<double>::kDefaultNodes,
             py::arg("controls") = py::none(), py::arg("dtype") = "float64",
             "Marschner's Table 1 (radians): eta > 1; sigma_a ≥ 0; alpha_r (-10° to -5°, |α_R| ≤ π/6); beta_r (5° "
             "to 10°, [1e-4, π/4]); beta_n, Chiang's scale, [1e-3, 1]; eccentricity a > 0; caustic_width w_c "
             "(10° to 25°); caustic_gain k_G (0.5 to 5); caustic_fade Δη' (0.2 to 0.4); caustic_dh_max Δh_M in "
             "(0, 1]; nodes, the Gauss–Hermite roughness nodes, 1 … 16. controls: no residual gain or tint.");

    const HuangParams<double> hp;
    py::class_<PyHuang, PyModel>(
        m, "Huang",
        "Huang et al. 2022's microfacet fiber: elliptical section, GGX cuticle about the tilted mesonormal, R off "
        "it, TT and TRT through microfacets inside, one residual lobe. Far field (h=None), deterministic "
        "quadrature with an exact pdf; hundreds of times slower than Chiang.")
        .def(py::init([](double eta, double roughness, double alpha, const py::object& sigma_a, double aspect_ratio,
                         double orientation, int offset_nodes, int tt_points, int trt_per_tt,
                         const py::object& controls, const py::object& dtype) {
                 const glm::dvec3 s = vec3_arg(sigma_a, "sigma_a");
                 const LobeControls<double> c = controls_arg(controls);
                 HuangQuadrature q;
                 q.offset_nodes = offset_nodes;
                 q.tt_points = tt_points;
                 q.trt_per_tt = trt_per_tt;
                 PyHuang p;
                 p.name = "Huang";
                 p.model = with_precision(dtype, [&](auto t) {
                     using T = decltype(t);
                     HuangParams<T> h;
                     h.eta = T(eta);
                     h.roughness = T(roughness);
                     h.alpha = T(alpha);
                     h.sigma_a = glm::vec<3, T>(s);
                     h.aspect_ratio = T(aspect_ratio);
                     h.orientation = T(orientation);
                     const LobeControls<T> ct = controls_as<T>(c);
                     py::gil_scoped_release no_gil;  // the interface tables take ~0.1 s
                     return make_model<HuangFiber<T>>(h, q, ct);
                 });
                 p.params = py::dict(py::arg("eta") = eta, py::arg("roughness") = roughness, py::arg("alpha") = alpha,
                                     py::arg("sigma_a") = py::make_tuple(s.x, s.y, s.z),
                                     py::arg("aspect_ratio") = aspect_ratio, py::arg("orientation") = orientation,
                                     py::arg("offset_nodes") = offset_nodes, py::arg("tt_points") = tt_points,
                                     py::arg("trt_per_tt") = trt_per_tt);
                 return p;
             }),
             py::kw_only(), py::arg("eta") = hp.eta, py::arg("roughness") = hp.roughness, py::arg("alpha") = hp.alpha,
             py::arg("sigma_a") = py::make_tuple(0.0, 0.0, 0.0), py::arg("aspect_ratio") = hp.aspect_ratio,
             py::arg("orientation") = hp.orientation, py::arg("offset_nodes") = 0, py::arg("tt_points") = 0,
             py::arg("trt_per_tt") = 0, py::arg("controls") = py::none(), py::arg("dtype") = "float64",
             "eta > 1; roughness, the cuticle's GGX β, [0.02, 1] (0.3); alpha, the cuticle tilt, |α| ≤ π/8; "
             "sigma_a per unit major semi-axis; aspect_ratio, minor over major semi-axis, [0.5, 1]; orientation, "
             "the major axis' angle from the frame's y axis, [-π, π]; the quadrature's offset_nodes (≤ 128), "
             "tt_points (≤ 1024), trt_per_tt (≤ 8), 0 for the automatic choice. controls: no per-lobe tilt.");
}

}  // namespace hairscatter::python
