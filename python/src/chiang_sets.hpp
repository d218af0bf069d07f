// hairscatter Python bindings: the Chiang fiber of a lobe set chosen at run time. Each of the
// 15 sets is its own C++ type (BasicChiangFiber<T, set>); they are compiled in one source
// per real type (chiang_float.cpp, chiang_double.cpp), which build side by side.
#pragma once

#include "model_impl.hpp"

namespace hairscatter::python {

namespace detail {

template <typename T, unsigned kSet = 1u>
std::shared_ptr<const Model> chiang_model_from(unsigned set, const FiberParams<T>& params,
                                               const LobeControls<T>& controls) {
    if constexpr (kSet > unsigned(LobeSet::kAll)) {
        (void)set, (void)params, (void)controls;
        throw py::value_error("lobes: no such lobe set");
    } else {
        if (set == kSet) return make_model<BasicChiangFiber<T, LobeSet(kSet)>>(params, controls);
        return chiang_model_from<T, kSet + 1u>(set, params, controls);
    }
}

}  // namespace detail

// The model of BasicChiangFiber<T, LobeSet(set)>, set in 1 … 15.
template <typename T>
std::shared_ptr<const Model> chiang_model(unsigned set, const FiberParams<T>& params, const LobeControls<T>& controls) {
    return detail::chiang_model_from<T>(set, params, controls);
}

extern template std::shared_ptr<const Model> chiang_model<float>(unsigned, const FiberParams<float>&,
                                                                 const LobeControls<float>&);
extern template std::shared_ptr<const Model> chiang_model<double>(unsigned, const FiberParams<double>&,
                                                                  const LobeControls<double>&);

}  // namespace hairscatter::python
