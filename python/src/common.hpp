// hairscatter Python bindings: what every binding source shares — numpy arguments made
// into rows of real numbers (with their names in every error), the type-erased fiber model
// and dual-scattering objects the Python classes hold, and the registration functions.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <hairscatter/dual.hpp>
#include <hairscatter/hairscatter.hpp>

// The library reports bad parameters by throwing std::invalid_argument (config.hpp), which
// pybind11 turns into ValueError with the same message. Built without exceptions it would
// abort instead, taking the interpreter with it.
#if defined(HAIRSCATTER_NO_EXCEPTIONS)
#error "the Python module needs C++ exceptions: hairscatter's validation errors become Python exceptions"
#endif

namespace hairscatter::python {

namespace py = pybind11;

// The real type of a model, chosen by its dtype= argument ("float32" or "float64").
enum class Precision { kFloat, kDouble };
Precision precision_of(const py::object& dtype);
template <typename T> py::dtype dtype_of() { return py::dtype::of<T>(); }

// One argument of a vectorised call as C-contiguous rows of `width` reals of type T
// (width 0: one real per row). A 1-D (width > 0) or 0-D (width 0) argument is a single row
// that every row of the call shares; a 2-D (or 1-D) one holds one row per call.
template <typename T> struct Rows {
    py::array_t<T, py::array::c_style | py::array::forcecast> array;
    const T* data = nullptr;
    py::ssize_t rows = 1;
    py::ssize_t stride = 0;  // 0 for a single shared row
    bool batched = false;
    const T* at(py::ssize_t i) const { return data + i * stride; }
    T scalar(py::ssize_t i) const { return data[i * stride]; }
};

namespace detail {
// obj as a numpy array of real numbers, or ValueError naming the argument.
py::array numeric_array(py::handle obj, const char* name);
std::string shape_text(const py::array& a);
}  // namespace detail

template <typename T> Rows<T> rows_of(py::handle obj, const char* name, int width) {
    const py::array a = detail::numeric_array(obj, name);
    Rows<T> r;
    r.array = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!r.array) throw py::value_error(std::string(name) + ": cannot be converted to " + std::string(py::str(dtype_of<T>())));
    const py::ssize_t nd = r.array.ndim();
    const bool single = width > 0 ? nd == 1 && r.array.shape(0) == width : nd == 0;
    const bool batch = width > 0 ? nd == 2 && r.array.shape(1) == width : nd == 1;
    if (!single && !batch) {
        const std::string w = std::to_string(width);
        throw py::value_error(std::string(name) + ": expected shape " + (width > 0 ? "(" + w + ",) or (N, " + w + ")" : "() or (N,)") +
                              ", got " + detail::shape_text(r.array));
    }
    r.batched = batch;
    r.rows = batch ? r.array.shape(0) : 1;
    r.stride = batch ? py::ssize_t(width > 0 ? width : 1) : 0;
    r.data = r.array.data();
    return r;
}

// The rows of one call: the batched arguments must agree on N; single rows are shared.
class CallShape {
  public:
    template <typename T> void add(const Rows<T>& r, const char* name) {
        if (!r.batched) return;
        if (batched_ && r.rows != n_)
            throw py::value_error(std::string(name) + ": " + std::to_string(r.rows) + " rows, but " + first_ + " has " +
                                  std::to_string(n_));
        if (!batched_) first_ = name;
        batched_ = true;
        n_ = r.rows;
    }
    py::ssize_t n() const { return n_; }
    bool batched() const { return batched_; }
    // A result of `width` reals per row (0: one): shape (N, width) / (N,), or (width,) / ()
    // for a call without batched arguments.
    template <typename T> py::array_t<T> result(int width) const {
        std::vector<py::ssize_t> shape;
        if (batched_) shape.push_back(n_);
        if (width > 0) shape.push_back(width);
        return py::array_t<T>(shape);
    }
    template <typename T> py::array_t<T> result(std::vector<py::ssize_t> inner) const {
        if (batched_) inner.insert(inner.begin(), n_);
        return py::array_t<T>(inner);
    }

  private:
    py::ssize_t n_ = 1;
    bool batched_ = false;
    std::string first_;
};

// Runs body(i) for every row with the GIL released: one C++ loop per call.
template <typename Body> void for_rows(py::ssize_t n, Body&& body) {
    py::gil_scoped_release no_gil;
    for (py::ssize_t i = 0; i < n; ++i) body(i);
}

template <typename T> glm::vec<3, T> vec3_at(const Rows<T>& r, py::ssize_t i) {
    const T* p = r.at(i);
    return glm::vec<3, T>(p[0], p[1], p[2]);
}
template <typename T> glm::vec<4, T> vec4_at(const Rows<T>& r, py::ssize_t i) {
    const T* p = r.at(i);
    return glm::vec<4, T>(p[0], p[1], p[2], p[3]);
}
template <typename T> void store3(T* out, py::ssize_t i, const glm::vec<3, T>& v) {
    out[3 * i] = v.x;
    out[3 * i + 1] = v.y;
    out[3 * i + 2] = v.z;
}
// A 0-D result as a Python float, else the array.
template <typename T> py::object finish(const py::array_t<T>& a) {
    if (a.ndim() == 0) return py::float_(double(*a.data()));
    return std::move(a);
}

// Sample results: arrays of N rows (or single values).
struct SampleResult {
    py::object wi, weight, pdf, lobe;
};
struct DualSampleResult {
    py::object wi, pdf, component, f, weight;
};

// Dual-scattering tables of either real type, shared by the BCSDFs built on them.
using AnyTables = std::variant<std::shared_ptr<const DualScatteringTables<float>>,
                               std::shared_ptr<const DualScatteringTables<double>>>;
struct Tables {
    AnyTables tables;
};

// The dual-scattering BCSDF over one model, type-erased.
class DualModel {
  public:
    virtual ~DualModel() = default;
    virtual py::object eval(py::handle wo, py::handle wi, py::handle h, py::handle direct_fraction, py::handle n,
                            py::handle beyond) const = 0;
    virtual py::object pdf(py::handle wo, py::handle wi, py::handle h, py::handle spread) const = 0;
    virtual DualSampleResult sample(py::handle wo, py::handle u, py::handle h, py::handle spread,
                                    py::handle direct_fraction, py::handle n, py::handle beyond) const = 0;
};

// A fiber model of one real type with its material, type-erased: the Python class
// FiberModel holds one.
class Model {
  public:
    virtual ~Model() = default;
    virtual py::object eval(py::handle wo, py::handle wi, py::handle h) const = 0;
    virtual py::object pdf(py::handle wo, py::handle wi, py::handle h) const = 0;
    virtual py::tuple eval_pdf(py::handle wo, py::handle wi, py::handle h) const = 0;
    virtual SampleResult sample(py::handle wo, py::handle u, py::handle h) const = 0;
    virtual py::object albedo(py::handle wo, py::handle h) const = 0;
    virtual py::tuple lobe_split(py::handle wo, py::handle h, py::handle centre) const = 0;
    virtual Tables dual_tables(int theta_samples, int psi_samples, int h_nodes, const std::string& formulation,
                               py::object d_f, py::object d_b) const = 0;
    virtual std::shared_ptr<const DualModel> dual(const Tables& tables) const = 0;
    virtual bool near_field() const = 0;
    virtual py::dtype dtype() const = 0;
};

// What the Python class of every model holds: the model, its name and its parameters.
struct PyModel {
    std::shared_ptr<const Model> model;
    std::string name;
    py::dict params;
};

// LobeControls of the Python API (kept in double; converted to a material's type).
template <typename T> LobeControls<T> controls_as(const LobeControls<double>& c) {
    LobeControls<T> r;
    for (int p = 0; p < LobeControls<T>::kLobes; ++p) {
        r.gain[p] = T(c.gain[p]);
        r.tint[p] = glm::vec<3, T>(c.tint[p]);
    }
    for (int p = 0; p < 3; ++p) r.alpha[p] = T(c.alpha[p]);
    r.alpha_override = c.alpha_override;
    return r;
}
// controls= of a model: None or a LobeControls.
LobeControls<double> controls_arg(const py::object& controls);
glm::dvec3 vec3_arg(const py::object& v, const char* name);

void bind_helpers(py::module_& m);
void bind_model_base(py::module_& m);
void bind_chiang(py::module_& m);
void bind_farfield(py::module_& m);
void bind_other_models(py::module_& m);
void bind_dual(py::module_& m);

}  // namespace hairscatter::python
