// HuangParams for a case of the physical fiber reference (physical_fiber_cases.hpp): the
// same fiber as the library's model sees it, lossless or blond. Kept apart so that the
// reference itself never includes the library.
#pragma once

#include <hairscatter/models/huang.hpp>

#include "physical_fiber_cases.hpp"

namespace phys_fiber {

inline hairscatter::HuangParams<double> huang_params(const Case& c, bool blond) {
    hairscatter::HuangParams<double> p;
    p.eta = c.eta;
    p.roughness = c.roughness;
    p.alpha = c.tilt_deg * kPi / 180;
    p.aspect_ratio = c.aspect;
    p.orientation = c.psi_deg * kPi / 180;
    p.sigma_a = blond ? glm::dvec3(kBlond[0], kBlond[1], kBlond[2]) : glm::dvec3(0);
    return p;
}

}  // namespace phys_fiber
