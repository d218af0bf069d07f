// hairscatter Python bindings: the 15 lobe sets of the Chiang fiber in double (chiang_sets.hpp).
#include "chiang_sets.hpp"

template std::shared_ptr<const hairscatter::python::Model> hairscatter::python::chiang_model<double>(
    unsigned, const hairscatter::FiberParams<double>&, const hairscatter::LobeControls<double>&);
