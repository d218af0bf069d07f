// render — environment lighting: a constant radiance, or a lat-long (equirectangular) map
// from an OpenEXR file or the procedural studio, importance-sampled by luminance with a 2D
// piecewise-constant distribution (pbrt-v4's PiecewiseConstant2D: a marginal over the
// rows, weighted by sin θ, and a conditional per row).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace render {

// A 1D piecewise-constant distribution over [0, 1) of n equal bins.
class Distribution1D {
  public:
    Distribution1D() = default;
    explicit Distribution1D(std::vector<float> weights);  // ≥ 0, finite; not all zero
    struct Sample {
        float x = 0;    // in [0, 1)
        float pdf = 0;  // density over [0, 1)
        int bin = 0;
    };
    Sample sample(float u) const;
    float pdf(int bin) const { return weights_[std::size_t(bin)] / mean_; }
    int size() const { return int(weights_.size()); }
    float integral() const { return mean_; }  // the weights' mean: ∫ of the step function

  private:
    std::vector<float> weights_, cdf_;  // cdf_: n + 1 entries, cdf_[0] = 0, cdf_[n] = 1
    float mean_ = 0;
};

// A lat-long RGB map, width = 2 × height, row 0 at the zenith (+y), column 0 at azimuth
// φ = 0 toward +z, φ growing toward +x (a direction's map coordinates: u = φ / 2π,
// v = θ / π). Radiance is the pixel's (nearest lookup), so sampling by the pixels'
// luminance is exact for the map alone.
struct LatLongMap {
    int width = 0, height = 0;
    std::vector<float> rgb;  // 3 floats per pixel, row-major from the zenith
    std::string name;        // the file, or "studio"
};

// Reads a lat-long map from an OpenEXR file. Throws std::invalid_argument naming `--env`
// and the file when it cannot be read, has no R, G and B channels, is not 2:1, or holds a
// negative or non-finite value.
LatLongMap read_lat_long_exr(const std::string& path);

// The procedural studio: a floor-to-ceiling grey gradient and four softboxes (a large
// key above and to the camera's left, two strip rim lights behind, a dim fill on the right),
// for the scenes' cameras, which look toward −z (the map's centre column).
LatLongMap make_studio_map(int width = 512);

class Environment {
  public:
    // A constant radiance, sampled uniformly over the sphere (the renderer's default).
    explicit Environment(const glm::vec3& radiance);
    // A map, rotated by rotate_deg about +y and scaled by `intensity`. Throws
    // std::invalid_argument naming --env when the map has no light at all.
    Environment(const LatLongMap& map, float rotate_deg, float intensity);

    bool any() const { return any_; }
    bool constant() const { return rgb_.empty(); }
    glm::vec3 radiance(const glm::vec3& dir) const;  // of the light arriving from dir
    float pdf(const glm::vec3& dir) const;           // the sampler's density in solid angle

    struct Sample {
        glm::vec3 wi{0}, Le{0};
        float pdf = 0;
    };
    Sample sample(float u1, float u2) const;

    // The map's coordinates in [0, 1)² of a world direction, and back.
    glm::vec2 to_map(const glm::vec3& dir) const;
    glm::vec3 from_map(const glm::vec2& uv) const;

  private:
    std::size_t pixel(const glm::vec2& uv) const;

    glm::vec3 constant_{0};
    bool any_ = false;
    int width_ = 0, height_ = 0;
    std::vector<float> rgb_;
    float rotate_ = 0;  // radians about +y
    Distribution1D marginal_;                 // over rows
    std::vector<Distribution1D> conditional_;  // over the columns of each row
};

}  // namespace render
