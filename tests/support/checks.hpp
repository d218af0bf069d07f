// Shared assertions of the extreme-input sweeps: a sample must have a finite non-negative
// pdf and weight and a finite unit direction.
#pragma once

#include <cmath>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

template <typename Sample> ::testing::AssertionResult valid_sample(const Sample& s) {
    if (!(std::isfinite(s.pdf) && s.pdf >= 0)) return ::testing::AssertionFailure() << "pdf " << s.pdf;
    for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(s.wi[c])) return ::testing::AssertionFailure() << "wi[" << c << "] " << s.wi[c];
        if (!(std::isfinite(s.weight[c]) && s.weight[c] >= 0))
            return ::testing::AssertionFailure() << "weight[" << c << "] " << s.weight[c];
    }
    const double len = double(glm::length(s.wi));
    if (std::abs(len - 1.0) > 1e-3) return ::testing::AssertionFailure() << "|wi| = " << len;
    return ::testing::AssertionSuccess();
}
