// hairscatter Python bindings: Chiang et al. 2016's fiber and its lobe subsets.
#include <algorithm>
#include <cctype>
#include <sstream>

#include "chiang_sets.hpp"

namespace hairscatter::python {
namespace {

struct PyChiang : PyModel {};

// lobes= as a LobeSet's bits: "all", "primary", or lobe names joined by '+' ("R+TT"), or a
// sequence of names; case-insensitive.
unsigned lobe_bits(const py::object& lobes) {
    std::vector<std::string> names;
    if (py::isinstance<py::str>(lobes)) {
        std::stringstream s(lobes.cast<std::string>());
        for (std::string part; std::getline(s, part, '+');) names.push_back(part);
    } else {
        try {
            names = lobes.cast<std::vector<std::string>>();
        } catch (const py::cast_error&) {
            throw py::value_error("lobes: expected a string such as 'R+TT' or a list of lobe names");
        }
    }
    unsigned bits = 0;
    for (std::string n : names) {
        n.erase(std::remove_if(n.begin(), n.end(), [](unsigned char c) { return std::isspace(c); }), n.end());
        std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        if (n == "all") bits |= unsigned(LobeSet::kAll);
        else if (n == "primary") bits |= unsigned(LobeSet::kPrimary);
        else if (n == "r") bits |= unsigned(LobeSet::kR);
        else if (n == "tt") bits |= unsigned(LobeSet::kTT);
        else if (n == "trt") bits |= unsigned(LobeSet::kTRT);
        else if (n == "residual") bits |= unsigned(LobeSet::kResidual);
        else
            throw py::value_error("lobes: unknown lobe '" + n + "' (R, TT, TRT, residual, primary, all)");
    }
    if (bits == 0) throw py::value_error("lobes: keep at least one of R, TT, TRT, residual");
    return bits;
}

}  // namespace

void bind_chiang(py::module_& m) {
    const FiberParams<double> d;
    py::class_<PyChiang, PyModel>(
        m, "Chiang",
        "Chiang et al. 2016's near-field fiber (R, TT, TRT and a residual; d'Eon's energy-conserving M_p, "
        "pbrt-v4's cuticle tilt), importance-sampled after d'Eon, Marschner & Hanika 2013. Every call takes the "
        "offset h ∈ [-1, 1] (clamped). lobes keeps a subset, chosen at compile time in C++: a dropped lobe "
        "loses its energy (furnace below 1) and is never sampled.")
        .def(py::init([](double eta, double beta_m, double beta_n, double alpha, const py::object& sigma_a,
                         const py::object& lobes, const py::object& controls, const py::object& dtype) {
                 const unsigned set = lobe_bits(lobes);
                 const glm::dvec3 s = vec3_arg(sigma_a, "sigma_a");
                 const LobeControls<double> c = controls_arg(controls);
                 PyChiang p;
                 p.name = "Chiang";
                 p.model = with_precision(dtype, [&](auto t) {
                     using T = decltype(t);
                     return chiang_model<T>(set, fiber_params<T>(eta, beta_m, beta_n, alpha, s), controls_as<T>(c));
                 });
                 p.params = fiber_params_dict(eta, beta_m, beta_n, alpha, s);
                 p.params["lobes"] = lobes;
                 return p;
             }),
             py::kw_only(), py::arg("eta") = d.eta, py::arg("beta_m") = d.beta_m, py::arg("beta_n") = d.beta_n,
             py::arg("alpha") = d.alpha, py::arg("sigma_a") = py::make_tuple(0.0, 0.0, 0.0), py::arg("lobes") = "all",
             py::arg("controls") = py::none(), py::arg("dtype") = "float64",
             "eta > 1 (1.55); beta_m, beta_n in [1e-3, 1] (Chiang's roughness mappings, 0.3); alpha, the cuticle "
             "tilt in radians, |α| ≤ π/8 (2°); sigma_a, RGB absorption per unit fiber radius ≥ 0 (see "
             "sigma_a_from_melanin_amount); lobes 'all', 'primary' or e.g. 'R+TT'; controls a LobeControls; "
             "dtype float32 or float64. ValueError with the C++ validation's message naming every bad field.");
}

}  // namespace hairscatter::python
