// hairscatter — the shipped density grid's queries (dual/density_grid.hpp builds it): the
// per-cell hair length tensor, its trilinear lookup and the march of the fiber count n
// along a ray (the density source of dual/density_source.hpp). Device-callable.
#pragma once

#include <cmath>
#include <cstddef>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/constants.hpp"
#include "../math/functions.hpp"
#include "settings.hpp"

namespace hairscatter {

// Each cell stores M = Σ ℓ t tᵀ over the hair inside it (ℓ a piece's length, t its unit
// tangent), built by splitting every strand segment at the cell faces, so the deposited
// length is exact. trace M is the hair length in the cell, L_v = trace M / cell volume.
// Lookups interpolate M trilinearly between cell centres (the boundary cells' values hold
// out to the box faces; zero outside the box).
//
// Orientation model. A ray crosses parallel fibers of diameter D at the rate L_v·D·sinψ
// per unit length, ψ the angle between ray and fibers (sinψ = cosθ for θ the ray's
// inclination from the fibers' normal plane, docs/theory.md §5.2). With d the ray direction,
// dᵀMd / trace M is the length-weighted mean cos²ψ, and
//   kTracked   (default) uses mean sinψ ≈ sqrt(1 - mean cos²ψ): exact wherever the hair a
//              lookup reaches is parallel (combed, locally aligned hair), too large where
//              directions mix (Jensen; sqrt is concave): +3.9 % for isotropic hair
//              (sqrt(2/3) against π/4), +41 % for a ray along one of two crossed families
//              (sqrt(1/2) against 1/2). Strands running either way add up, never cancel.
//   kIsotropic ignores the tangents and uses the isotropic mean sinψ = π/4.
// n = ∫ L_v·D·(mean sinψ) ds along the ray, by the midpoint rule in equal steps no longer
// than march_step (default half a cell). The integrand has kinks at cell centres, so the
// error is O(step²), largest across the faces of a block of parallel strands and 0 inside
// it (tests/density_test.cpp bounds it; docs/test_figures.txt). n is the expectation over where
// the ray passes between the fibers; a grid cannot resolve finer structure than its cells.
enum class FiberOrientation { kTracked, kIsotropic };

// Σ ℓ t tᵀ of the hair in a cell (or, after division by the cell volume, per unit volume).
template <typename T> struct HairLengthTensor {
    T xx = T(0), yy = T(0), zz = T(0), xy = T(0), xz = T(0), yz = T(0);

    // ℓ t tᵀ for a piece of length ℓ along the unit tangent t.
    HAIRSCATTER_HD static HairLengthTensor piece(T length, const glm::vec<3, T>& t) {
        HairLengthTensor m;
        m.xx = length * t.x * t.x;
        m.yy = length * t.y * t.y;
        m.zz = length * t.z * t.z;
        m.xy = length * t.x * t.y;
        m.xz = length * t.x * t.z;
        m.yz = length * t.y * t.z;
        return m;
    }
    HAIRSCATTER_HD T length() const { return xx + yy + zz; }  // trace: t·t = 1
    // dᵀ M d: the length-weighted Σ ℓ cos²ψ for a unit d.
    HAIRSCATTER_HD T along(const glm::vec<3, T>& d) const {
        return xx * d.x * d.x + yy * d.y * d.y + zz * d.z * d.z +
               T(2) * (xy * d.x * d.y + xz * d.x * d.z + yz * d.y * d.z);
    }
    HAIRSCATTER_HD HairLengthTensor& operator+=(const HairLengthTensor& o) {
        xx += o.xx, yy += o.yy, zz += o.zz, xy += o.xy, xz += o.xz, yz += o.yz;
        return *this;
    }
    HAIRSCATTER_HD void add_scaled(T w, const HairLengthTensor& o) {
        xx += w * o.xx, yy += w * o.yy, zz += w * o.zz, xy += w * o.xy, xz += w * o.xz, yz += w * o.yz;
    }
};

namespace detail {

template <typename T> HAIRSCATTER_HD bool finite3(const glm::vec<3, T>& v) {
    using std::isfinite;
    return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

// The parameter interval [t0, t1] of o + t·d inside the closed box [lo, hi], t ∈ [0, t_max];
// empty when !(t1 > t0). d need not be unit. An axis with d = 0 constrains only whether o
// lies in that slab (1/0 would give 0·∞ = NaN for o on a face).
template <typename T> struct Span {
    T t0, t1;
};
template <typename T>
HAIRSCATTER_HD Span<T> clip_to_box(const glm::vec<3, T>& lo, const glm::vec<3, T>& hi, const glm::vec<3, T>& o,
                                   const glm::vec<3, T>& d, T t_max) {
    Span<T> s{T(0), t_max};
    for (int a = 0; a < 3; ++a) {
        if (d[a] != T(0)) {
            const T inv = T(1) / d[a];
            T ta = (lo[a] - o[a]) * inv, tb = (hi[a] - o[a]) * inv;
            if (ta > tb) {
                const T tmp = ta;
                ta = tb;
                tb = tmp;
            }
            // Written so that a NaN (o on a face and a subnormal d: 0·∞) leaves s unchanged.
            s.t0 = ta > s.t0 ? ta : s.t0;
            s.t1 = tb < s.t1 ? tb : s.t1;
        } else if (!(o[a] >= lo[a] && o[a] <= hi[a])) {
            return Span<T>{T(0), T(0)};
        }
    }
    return s;
}

}  // namespace detail

template <typename T> class DensityGrid;

// The queries of a DensityGrid over cell data it does not own: trivially copyable, so it
// can be passed by value to a GPU kernel once the cells are copied to device memory
// (grid.view(device_pointer)). Every query is HAIRSCATTER_HD and check-free.
template <typename T> class DensityGridView {
  public:
    using V3 = glm::vec<3, T>;
    using Cell = HairLengthTensor<T>;

    // No grid: assign one from DensityGrid::view() before querying.
    DensityGridView() = default;

    // The same grid over a copy of its cells elsewhere (e.g. in device memory).
    HAIRSCATTER_HD DensityGridView with_cells(const Cell* cells) const {
        DensityGridView v = *this;
        v.cells_ = cells;
        return v;
    }

    HAIRSCATTER_HD bool contains(const V3& p) const {
        return p.x >= lo_.x && p.x <= hi_.x && p.y >= lo_.y && p.y <= hi_.y && p.z >= lo_.z && p.z <= hi_.z;
    }

    // M per unit volume at p, trilinear between cell centres; zero outside the box (and
    // for a NaN p).
    HAIRSCATTER_HD Cell tensor_density(const V3& p) const { return contains(p) ? interpolate(p) : Cell{}; }

    // L_v: hair length per unit volume at p.
    HAIRSCATTER_HD T length_density(const V3& p) const { return tensor_density(p).length(); }

    // Expected fibers crossed per unit path length at p by a ray along the unit vector d:
    // L_v·D·(mean sinψ), the orientation model above FiberOrientation.
    HAIRSCATTER_HD T crossing_density(const V3& p, const V3& d) const { return crossing(tensor_density(p), d); }
    // The same from a tensor density already read at a point (tensor_density(p)): a caller
    // that asks along many directions at one point reads the grid once.
    HAIRSCATTER_HD T crossing_density_of(const Cell& tensor, const V3& d) const { return crossing(tensor, d); }

    // n between origin and origin + max_distance·direction, marched through the part of the
    // ray inside the box in equal steps no longer than march_step (midpoint rule). direction
    // need not be unit (it is normalised; max_distance is a distance). A zero, NaN or
    // infinite direction, a non-finite origin, max_distance ≤ 0 or NaN, or a ray that misses
    // the box give 0; max_distance = kUnbounded<T> marches to where the ray leaves the box.
    HAIRSCATTER_HD T fibers_crossed(const V3& origin, const V3& direction, T max_distance) const {
        using std::ceil;
        using std::isfinite;
        using std::sqrt;
        const T len2 = glm::dot(direction, direction);
        if (!(len2 > T(0)) || !isfinite(len2) || !(max_distance > T(0)) || !detail::finite3(origin)) return T(0);
        const V3 d = direction / sqrt(len2);
        const detail::Span<T> s = detail::clip_to_box(lo_, hi_, origin, d, max_distance);
        if (!(s.t1 > s.t0)) return T(0);
        // t1 - t0 ≤ the box diagonal, and the grid checked diagonal / step ≤ kMaxMarchSteps.
        const int steps = int(ceil((s.t1 - s.t0) / step_));
        const int m = steps > 1 ? steps : 1;
        const T h = (s.t1 - s.t0) / T(m);
        T n = T(0);
        // The samples lie inside the box up to rounding, which interpolate()'s clamp absorbs.
        for (int i = 0; i < m; ++i) n += crossing(interpolate(origin + (s.t0 + (T(i) + T(0.5)) * h) * d), d);
        return n * h;
    }

    HAIRSCATTER_HD const V3& box_min() const { return lo_; }
    HAIRSCATTER_HD const V3& box_max() const { return hi_; }
    HAIRSCATTER_HD const glm::ivec3& resolution() const { return res_; }
    HAIRSCATTER_HD T fiber_diameter() const { return diameter_; }
    HAIRSCATTER_HD T march_step() const { return step_; }
    HAIRSCATTER_HD FiberOrientation orientation() const { return orientation_; }
    HAIRSCATTER_HD const Cell* cells() const { return cells_; }

  private:
    friend class DensityGrid<T>;

    HAIRSCATTER_HD const Cell& cell(int i, int j, int k) const {
        return cells_[std::size_t(i) + std::size_t(res_.x) * (std::size_t(j) + std::size_t(res_.y) * std::size_t(k))];
    }

    // Trilinear over cell-centred samples with the coordinates clamped into the box, so
    // faces, edges and corners read the boundary cells (never an out-of-range index).
    HAIRSCATTER_HD Cell interpolate(const V3& p) const {
        int i0[3], i1[3];
        T f[3];
        for (int a = 0; a < 3; ++a) {
            const int n = res_[a];
            const T u = clamp((p[a] - lo_[a]) * inv_cell_[a] - T(0.5), T(0), T(n - 1));
            int c = int(u);                       // u ≥ 0: truncation is floor
            if (c > n - 2) c = n > 1 ? n - 2 : 0;  // the last interval is closed
            i0[a] = c;
            i1[a] = c + 1 < n ? c + 1 : c;
            f[a] = u - T(c);
        }
        Cell m;
        for (int corner = 0; corner < 8; ++corner) {
            const int bx = corner & 1, by = (corner >> 1) & 1, bz = (corner >> 2) & 1;
            const T w = (bx ? f[0] : T(1) - f[0]) * (by ? f[1] : T(1) - f[1]) * (bz ? f[2] : T(1) - f[2]);
            m.add_scaled(w * inv_volume_, cell(bx ? i1[0] : i0[0], by ? i1[1] : i0[1], bz ? i1[2] : i0[2]));
        }
        return m;
    }

    HAIRSCATTER_HD T crossing(const Cell& m, const V3& d) const {
        const T lv = m.length();
        if (orientation_ == FiberOrientation::kIsotropic) return diameter_ * (kPi<T> / T(4)) * lv;
        // L_v·sqrt(1 - dᵀMd/L_v) written as sqrt(L_v (L_v - dᵀMd)): no division for empty
        // cells. For hair along d, rounding can put dᵀMd a few ulps above L_v: clamp at 0.
        using std::sqrt;
        const T x = lv * (lv - m.along(d));
        return diameter_ * sqrt(x > T(0) ? x : T(0));
    }

    V3 lo_{T(0)}, hi_{T(1)};
    glm::ivec3 res_{1};
    V3 inv_cell_{T(1)};
    T inv_volume_ = T(1);
    T diameter_ = T(0);
    T step_ = T(1);
    FiberOrientation orientation_ = FiberOrientation::kTracked;
    const Cell* cells_ = nullptr;
};

}  // namespace hairscatter
