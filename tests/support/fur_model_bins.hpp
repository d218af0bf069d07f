// The fur model binned as the physical fur reference is (physical_fiber_cases.hpp's
// model_bins): f (RGB) per bin, averaged over 48 midpoint offsets h over [-1, 1], the
// far-field beam the reference traces. For the tools that compare the two.
#pragma once

#include <vector>

#include <hairscatter/models/fur.hpp>

#include "physical_fiber_cases.hpp"

namespace phys_fur {

inline std::vector<glm::dvec3> fur_model_bins(const hairscatter::FurMaterial<double>& mat, const phys_fiber::CachedCase& grid) {
    constexpr int kH = 48;
    std::vector<hairscatter::FurFiber<double>> fibers;
    for (int i = 0; i < kH; ++i) fibers.emplace_back(mat, -1 + (i + 0.5) * 2.0 / kH);
    return phys_fiber::model_bins(grid, [&](const glm::dvec3& wo, const glm::dvec3& wi) {
        glm::dvec3 f(0.0);
        for (const auto& fiber : fibers) f += fiber.eval(wo, wi);
        return f / double(kH);
    });
}

}  // namespace phys_fur
