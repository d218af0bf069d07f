// render — a least-squares plane through values on a small lattice neighbourhood, read at
// its centre (local linear regression): the glow volume's smoothing (integrators/two_stream.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include <glm/glm.hpp>

namespace render {

// A weighted least-squares plane v ≈ c + g·d through values at offsets d, read at d = 0
// (local linear regression; e.g. Hastie, Tibshirani & Friedman, The Elements of Statistical
// Learning, 2nd ed. 2009, §6.1.1: unlike a local mean it has no first-order bias where the
// neighbourhood is one-sided; it reproduces linear data up to the ridge's small shrinkage).
// A small ridge on g keeps it defined where the offsets do not span three dimensions (a layer
// one cell thick), and c stays within the values' range, so noise in a one-sided
// neighbourhood cannot carry it past what was measured. Values must be finite.
class LocalPlane {
  public:
    void add(const glm::dvec3& d, const glm::dvec3& v, std::uint32_t weight) {
        if (weight == 0) return;
        const double w = double(weight), e[4] = {1.0, d.x, d.y, d.z};
        for (int r = 0; r < 4; ++r) {
            for (int c = 0; c < 4; ++c) a_[r][c] += w * e[r] * e[c];
            b_[r] += w * e[r] * v;
        }
        lo_ = points_ == 0 ? v : glm::min(lo_, v);
        hi_ = points_ == 0 ? v : glm::max(hi_, v);
        points_ += weight;
    }

    std::uint32_t points() const { return points_; }

    // The plane at the centre (0 where nothing was added).
    glm::dvec3 at_centre() const {
        if (points_ == 0) return glm::dvec3(0);
        double a[4][4];
        glm::dvec3 b[4];
        for (int r = 0; r < 4; ++r) {
            for (int c = 0; c < 4; ++c) a[r][c] = a_[r][c] + (r == c && r > 0 ? kRidge * a_[0][0] : 0.0);
            b[r] = b_[r];
        }
        // Gaussian elimination with partial pivoting (the ridge makes the system positive
        // definite, so no pivot is zero).
        for (int col = 0; col < 4; ++col) {
            int pivot = col;
            for (int r = col + 1; r < 4; ++r)
                if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
            for (int c = 0; c < 4; ++c) std::swap(a[col][c], a[pivot][c]);
            std::swap(b[col], b[pivot]);
            for (int r = col + 1; r < 4; ++r) {
                const double f = a[r][col] / a[col][col];
                for (int c = col; c < 4; ++c) a[r][c] -= f * a[col][c];
                b[r] -= f * b[col];
            }
        }
        glm::dvec3 x[4];
        for (int r = 3; r >= 0; --r) {
            glm::dvec3 v = b[r];
            for (int c = r + 1; c < 4; ++c) v -= a[r][c] * x[c];
            x[r] = v / a[r][r];
        }
        return glm::clamp(x[0], lo_, hi_);
    }

  private:
    static constexpr double kRidge = 1e-3;  // of the total weight, on the slope's diagonal
    double a_[4][4] = {};
    glm::dvec3 b_[4] = {};
    glm::dvec3 lo_{0}, hi_{0};
    std::uint32_t points_ = 0;
};

}  // namespace render
