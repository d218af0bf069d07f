// render — the lights: the area light (picked with probability p_area) and the environment
// (constant or a lat-long map, environment.hpp), their sampling and the pdf of a direction
// that reached them.
#pragma once

#include <memory>

#include <glm/glm.hpp>

#include "environment.hpp"
#include "sampling.hpp"
#include "scene.hpp"

namespace render {

struct Lights {
    const AreaLight* area = nullptr;
    std::shared_ptr<const Environment> env;
    float p_area = 0;

    explicit Lights(const SceneDescription& d)
        : env(d.environment_map ? d.environment_map : std::make_shared<const Environment>(d.environment)) {
        if (d.light && max3(d.light->radiance) > 0) area = &*d.light;
        p_area = area ? (env->any() ? 0.5f : 1.0f) : 0.0f;
    }
    bool any() const { return p_area > 0 || env->any(); }
    bool has_env() const { return env->any(); }
    // The radiance arriving from the environment along -d (d: a ray that escaped).
    glm::vec3 env_radiance(const glm::vec3& d) const { return env->radiance(d); }

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
            const Environment::Sample e = env->sample(u1, u2);
            s.wi = e.wi;
            s.dist = kInf;
            s.Le = e.Le;
            s.pdf = (1 - p_area) * e.pdf;
        }
        return s;
    }
    // The pdf with which sample() picks the direction that reached the area light at
    // distance t (front side) / escaped to the environment.
    float pdf_area(const glm::vec3& wi, float t) const {
        const float cos_l = -glm::dot(wi, area->normal());
        return cos_l > 0 ? p_area * t * t / (area->area() * cos_l) : 0.0f;
    }
    float pdf_env(const glm::vec3& wi) const { return (1 - p_area) * env->pdf(wi); }
};

}  // namespace render
