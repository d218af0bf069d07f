// hairscatter Python bindings: dual-scattering tables (build, save, load, read as arrays) and
// the dual-scattering BCSDF over any model.
#include <cmath>

#include "common.hpp"

namespace hairscatter::python {
namespace {

struct PyDual {
    std::shared_ptr<const DualModel> dual;
    PyModel model;
};

// field k of every entry, (n, 3).
template <typename T> py::array_t<T> entry_field(const DualScatteringTables<T>& t, int k) {
    py::array_t<T> a({py::ssize_t(t.size()), py::ssize_t(3)});
    for (int i = 0; i < t.size(); ++i) store3(a.mutable_data(), i, t.entry(i).fields()[k]);
    return a;
}

constexpr const char* kFieldNames[DualScatteringEntry<float>::kFields] = {
    "a_f", "a_b", "alpha_f", "alpha_b", "beta2_f", "beta2_b", "A_b", "delta_b", "sigma2_b", "mu_f", "mu_b", "rho_b"};

template <typename T> py::dict arrays_of(const DualScatteringTables<T>& t) {
    py::dict d;
    py::array_t<T> theta(t.size());
    for (int i = 0; i < t.size(); ++i) theta.mutable_data()[i] = t.theta_of(i);
    d["theta"] = theta;
    for (int k = 0; k < DualScatteringEntry<T>::kFields; ++k) d[kFieldNames[k]] = entry_field(t, k);
    // W_p(θ_i, ψ_j): (theta, lobes, psi, 3), in the tables' own order.
    const auto v = t.view();
    py::array_t<T> window({py::ssize_t(t.size()), py::ssize_t(t.lobes()), py::ssize_t(t.psi_samples()), py::ssize_t(3)});
    for (int i = 0; i < t.size(); ++i)
        for (int p = 0; p < t.lobes(); ++p)
            for (int j = 0; j < t.psi_samples(); ++j) {
                const py::ssize_t at = (py::ssize_t(i) * t.lobes() + p) * t.psi_samples() + j;
                store3(window.mutable_data(), at, t.window_data()[v.window_index(i, p, j)]);
            }
    d["window"] = window;
    py::array_t<T> psi(t.psi_samples());
    for (int j = 0; j < t.psi_samples(); ++j) psi.mutable_data()[j] = kPi<T> * T(j) / T(t.psi_samples() - 1);
    d["psi"] = psi;
    return d;
}

template <typename T> py::dict lookup_of(const DualScatteringTables<T>& t, py::handle theta_) {
    const Rows<T> theta = rows_of<T>(theta_, "theta", 0);
    CallShape shape;
    shape.add(theta, "theta");
    py::dict d;
    std::vector<py::array_t<T>> out;
    for (int k = 0; k < DualScatteringEntry<T>::kFields; ++k) out.push_back(shape.result<T>(3));
    std::vector<T*> ptr;
    for (auto& a : out) ptr.push_back(a.mutable_data());
    for_rows(shape.n(), [&](py::ssize_t i) {
        const DualScatteringEntry<T> e = t.lookup(theta.scalar(i));
        for (int k = 0; k < DualScatteringEntry<T>::kFields; ++k) store3(ptr[std::size_t(k)], i, e.fields()[k]);
    });
    for (int k = 0; k < DualScatteringEntry<T>::kFields; ++k) d[kFieldNames[k]] = out[std::size_t(k)];
    return d;
}

}  // namespace

void bind_dual(py::module_& m) {
    py::class_<Tables>(m, "DualTables",
                       "Dual-scattering tables of one fiber model (Zinke et al. 2008 §4.1; docs/dual.md), from "
                       "FiberModel.dual_tables or DualTables.load. θ is the inclination light arrives from.")
        .def_property_readonly("dtype", [](const Tables& t) {
            return std::visit([](const auto& p) { return dtype_of<typename std::decay_t<decltype(*p)>::V3::value_type>(); },
                              t.tables);
        })
        .def_property_readonly("size", [](const Tables& t) { return std::visit([](const auto& p) { return p->size(); }, t.tables); },
                               "the number of θ nodes")
        .def_property_readonly("psi_samples",
                               [](const Tables& t) { return std::visit([](const auto& p) { return p->psi_samples(); }, t.tables); })
        .def_property_readonly("lobes", [](const Tables& t) { return std::visit([](const auto& p) { return p->lobes(); }, t.tables); })
        .def_property_readonly("h_nodes", [](const Tables& t) { return std::visit([](const auto& p) { return p->h_nodes(); }, t.tables); })
        .def_property_readonly("formulation",
                               [](const Tables& t) {
                                   return std::visit(
                                       [](const auto& p) {
                                           return std::string(p->settings().formulation == DualFormulation::kImproved
                                                                  ? "improved"
                                                                  : "zinke2008");
                                       },
                                       t.tables);
                               })
        .def("arrays", [](const Tables& t) { return std::visit([](const auto& p) { return arrays_of(*p); }, t.tables); },
             "The tables as numpy arrays: theta (n,); a_f, a_b, alpha_f, alpha_b, beta2_f, beta2_b, A_b, delta_b, "
             "sigma2_b, mu_f, mu_b, rho_b (n, 3); psi (m,) and window (n, lobes, m, 3), W_p(θ, ψ).")
        .def("lookup",
             [](const Tables& t, py::handle theta) {
                 return std::visit([&](const auto& p) { return lookup_of(*p, theta); }, t.tables);
             },
             py::arg("theta"), "The entries interpolated at θ (radians, () or (N,)): a dict of (N, 3) arrays.")
        .def("save", [](const Tables& t, const std::string& path) { std::visit([&](const auto& p) { p->save(path); }, t.tables); },
             py::arg("path"), "Writes the versioned binary file (doubles, FNV-1a checksum).")
        .def_static(
            "load",
            [](const std::string& path, const py::object& dtype) {
                Tables t;
                if (precision_of(dtype) == Precision::kFloat)
                    t.tables = std::make_shared<const DualScatteringTables<float>>(DualScatteringTables<float>::load(path));
                else
                    t.tables = std::make_shared<const DualScatteringTables<double>>(DualScatteringTables<double>::load(path));
                return t;
            },
            py::arg("path"), py::arg("dtype") = "float64",
            "Reads a file written by save(); RuntimeError with the reason for a bad file.");

    py::class_<DualSampleResult>(m, "DualSample", "What DualScatteringBcsdf.sample returns.")
        .def_readonly("wi", &DualSampleResult::wi)
        .def_readonly("pdf", &DualSampleResult::pdf, "the mixture's solid-angle density; 0: no sample")
        .def_readonly("component", &DualSampleResult::component,
                      "(N,) int8: 0 single, 1 back, 2 global, 3 global back, 4 uniform (DUAL_COMPONENT_NAMES)")
        .def_readonly("f", &DualSampleResult::f, "eval at wi under the light state")
        .def_readonly("weight", &DualSampleResult::weight, "f / pdf");

    const DualScatteringLight<double> l;
    py::class_<PyDual>(m, "DualScatteringBcsdf",
                       "The dual-scattering BCSDF over a fiber model (Zinke et al. 2008, the improved formulation by "
                       "default; docs/dual.md): single scattering plus the global and local multiple scattering "
                       "read from tables, for the light state at the point (direct_fraction, n, beyond).")
        .def(py::init([](const PyModel& model, const Tables& tables) {
                 return PyDual{model.model->dual(tables), model};
             }),
             py::arg("model"), py::arg("tables"), "tables: DualTables of the model's dtype (usually model.dual_tables()).")
        .def_property_readonly("model", [](const PyDual& d) { return d.model; })
        .def("eval",
             [](const PyDual& d, py::handle wo, py::handle wi, py::handle h, py::handle direct_fraction, py::handle n,
                py::handle beyond) { return d.dual->eval(wo, wi, h, direct_fraction, n, beyond); },
             py::arg("wo"), py::arg("wi"), py::arg("h") = py::none(), py::arg("direct_fraction") = l.direct_fraction,
             py::arg("n") = l.n, py::arg("beyond") = double(l.beyond),
             "f(wo, wi) for the light state: direct_fraction 1 if the shadow ray reached the light, 0 if hair "
             "blocked it; n, the expected fibers toward the light; beyond, the fibers beyond the point (inf: deep).")
        .def("pdf",
             [](const PyDual& d, py::handle wo, py::handle wi, py::handle h, py::handle spread) {
                 return d.dual->pdf(wo, wi, h, spread);
             },
             py::arg("wo"), py::arg("wi"), py::arg("h") = py::none(), py::arg("spread") = 0.0,
             "The mixture's density; spread, the forward variance σ̄²_f the sampler widens its global lobes by.")
        .def("sample",
             [](const PyDual& d, py::handle wo, py::handle u, py::handle h, py::handle spread, py::handle direct_fraction,
                py::handle n, py::handle beyond) { return d.dual->sample(wo, u, h, spread, direct_fraction, n, beyond); },
             py::arg("wo"), py::arg("u"), py::arg("h") = py::none(), py::arg("spread") = 0.0,
             py::arg("direct_fraction") = l.direct_fraction, py::arg("n") = l.n, py::arg("beyond") = double(l.beyond),
             "Directions from four uniform numbers u, with f and weight under the light state: a DualSample.");
}

}  // namespace hairscatter::python
