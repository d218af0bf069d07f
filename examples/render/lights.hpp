// render — the lights: the area light (picked with probability p_area) and the constant
// environment, their sampling and the pdf of a direction that reached them.
#pragma once

#include <glm/glm.hpp>

#include "sampling.hpp"
#include "scene.hpp"

namespace render {

struct Lights {
    const AreaLight* area = nullptr;
    glm::vec3 env{0};
    float p_area = 0;

    explicit Lights(const SceneDescription& d) {
        if (d.light && max3(d.light->radiance) > 0) area = &*d.light;
        env = d.environment;
        const bool has_env = max3(env) > 0;
        p_area = area ? (has_env ? 0.5f : 1.0f) : 0.0f;
    }
    bool any() const { return p_area > 0 || max3(env) > 0; }

    struct Sample {
        glm::vec3 wi{0}, Le{0};
        float dist = 0, pdf = 0;  // pdf in solid angle, including the light selection
    };
    Sample sample(const glm::vec3& x, float u0, float u1, float u2) const {
        Sample s;
        if (u0 < p_area) {
            const glm::vec3 q = area->corner + u1 * area->edge_u + u2 * area->edge_v;
            glm::vec3 d = q - x;
            const float dist = glm::length(d);
            if (!(dist > 0)) return s;
            d /= dist;
            const float cos_l = -glm::dot(d, area->normal());
            if (cos_l <= 0) return s;
            s.wi = d;
            s.dist = dist;
            s.Le = area->radiance;
            s.pdf = p_area * dist * dist / (area->area() * cos_l);
        } else {
            s.wi = uniform_sphere(u1, u2);
            s.dist = kInf;
            s.Le = env;
            s.pdf = (1 - p_area) / (4 * kPi);
        }
        return s;
    }
    // The pdf with which sample() picks the direction that reached the area light at
    // distance t (front side) / escaped to the environment.
    float pdf_area(const glm::vec3& wi, float t) const {
        const float cos_l = -glm::dot(wi, area->normal());
        return cos_l > 0 ? p_area * t * t / (area->area() * cos_l) : 0.0f;
    }
    float pdf_env() const { return (1 - p_area) / (4 * kPi); }
};

}  // namespace render
