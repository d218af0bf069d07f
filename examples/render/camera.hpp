// render — the pinhole camera's primary rays.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "sampling.hpp"
#include "scene.hpp"

namespace render {

class CameraRays {
  public:
    CameraRays(const Camera& c, int w, int h) : eye_(c.eye), width_(w), height_(h) {
        forward_ = glm::normalize(c.target - c.eye);
        right_ = glm::normalize(glm::cross(forward_, c.up));
        up_ = glm::cross(right_, forward_);
        tan_half_ = std::tan(0.5f * c.fov_y_deg * kPi / 180.0f);
        aspect_ = float(w) / float(h);
    }
    const glm::vec3& eye() const { return eye_; }
    // The direction through image point (px, py), in pixels from the top-left corner.
    glm::vec3 direction(float px, float py) const {
        const float sx = (2 * px / float(width_) - 1) * tan_half_ * aspect_;
        const float sy = (1 - 2 * py / float(height_)) * tan_half_;
        return glm::normalize(forward_ + sx * right_ + sy * up_);
    }

  private:
    glm::vec3 eye_, forward_{0}, right_{0}, up_{0};
    int width_, height_;
    float tan_half_ = 0, aspect_ = 1;
};

}  // namespace render
