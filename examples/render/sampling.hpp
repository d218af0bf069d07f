// render — the random numbers of a pixel and the small sampling helpers the integrators
// share: uniform and cosine directions, the power heuristic.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>

#include "rng.hpp"

namespace render {

inline constexpr float kPi = 3.14159265358979f;
inline constexpr float kInf = std::numeric_limits<float>::infinity();
inline constexpr float kSurfaceOffset = 1e-4f;  // rays leave a surface this far along its normal
inline constexpr float kShadowShorten = 1 - 1e-4f;  // shadow rays stop just short of the light

inline float max3(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }
inline bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
// Veach 1997 §9.2.4, β = 2.
inline float power_heuristic(float a, float b) { return a * a / (a * a + b * b); }

// The uniform numbers of one pixel's samples.
struct Sampler {
    Pcg32& rng;
    float u() { return rng.uniform(); }
    glm::vec4 u4() { return glm::vec4(u(), u(), u(), u()); }
};

inline glm::vec3 uniform_sphere(float u1, float u2) {
    const float z = 1 - 2 * u1, r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPi * u2;
    return glm::vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// An orthonormal basis around n (Duff et al. 2017).
inline void basis(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
    const float s = std::copysign(1.0f, n.z);
    const float a = -1.0f / (s + n.z), c = n.x * n.y * a;
    t = glm::vec3(1 + s * n.x * n.x * a, s * c, -s * n.x);
    b = glm::vec3(c, s + n.y * n.y * a, -n.y);
}

inline glm::vec3 cosine_hemisphere(const glm::vec3& n, float u1, float u2) {
    const float r = std::sqrt(u1), phi = 2 * kPi * u2;
    glm::vec3 t, b;
    basis(n, t, b);
    return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0f, 1 - u1)) * n);
}

}  // namespace render
