// hairscatter Python bindings: the 15 lobe sets of the Chiang fiber in float (chiang_sets.hpp).
#include "chiang_sets.hpp"

template std::shared_ptr<const hairscatter::python::Model> hairscatter::python::chiang_model<float>(
    unsigned, const hairscatter::FiberParams<float>&, const hairscatter::LobeControls<float>&);
