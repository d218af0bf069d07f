// hairscatter — how much hair lies between a shading point and the light (docs/theory.md §5.2,
// Zinke et al. 2008's global multiple scattering): the density-source interface, the
// forward transmittance and spread computed from its n, and a shipped dense voxel grid.
//
// A density source is any type D with the member
//
//     T fibers_crossed(const glm::vec<3, T>& origin, const glm::vec<3, T>& direction,
//                      T max_distance) const;
//
// that returns the expected number n ≥ 0 of fibers a ray crosses between origin and
// origin + max_distance·direction (direction is a unit vector; max_distance may be
// kUnbounded<T>, meaning "until the ray leaves the hair"). Nothing else is required: a
// renderer with an OpenVDB grid or a deep-opacity map wraps it in such a type and passes
// it to forward_scattering(); DensityGrid below is the one shipped with the library.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/constants.hpp"
#include "../math/functions.hpp"
#include "settings.hpp"

namespace hairscatter {


// ---------------------------------------------------------------------------------------
// The interface
// ---------------------------------------------------------------------------------------

namespace detail {
template <typename D, typename T, typename = void> struct is_density_source_impl : std::false_type {};
template <typename D, typename T>
struct is_density_source_impl<
    D, T,
    std::void_t<decltype(std::declval<const D&>().fibers_crossed(std::declval<const glm::vec<3, T>&>(),
                                                                 std::declval<const glm::vec<3, T>&>(),
                                                                 std::declval<T>()))>>
    : std::is_convertible<decltype(std::declval<const D&>().fibers_crossed(std::declval<const glm::vec<3, T>&>(),
                                                                           std::declval<const glm::vec<3, T>&>(),
                                                                           std::declval<T>())),
                          T> {};
}  // namespace detail

// True when D answers density queries in real type T (see the top of this header).
template <typename D, typename T> struct is_density_source : detail::is_density_source_impl<D, T> {};
template <typename D, typename T> inline constexpr bool is_density_source_v = is_density_source<D, T>::value;

// T_f ≈ a_f(θ)^n per channel (docs/theory.md §5.2): the light left after n forward scatterings.
// The forward density factor d_f is not in here; §5.3 applies it exactly once.
template <typename T>
HAIRSCATTER_HD glm::vec<3, T> forward_transmittance(const glm::vec<3, T>& a_f, T n) {
    using std::pow;
    return glm::vec<3, T>(pow(a_f.x, n), pow(a_f.y, n), pow(a_f.z, n));
}

// σ̄²_f ≈ n·β̄²_f(θ) (docs/theory.md §5.2): the longitudinal variance the n forward scatterings
// add. V is T or glm::vec<3, T> (β̄²_f per channel, as in DualScatteringEntry::beta2_f).
template <typename V, typename T> HAIRSCATTER_HD V forward_spread(const V& beta2_f, T n) { return beta2_f * n; }

// What the global multiple scattering needs from the hair between x and the light.
template <typename T> struct ForwardScattering {
    T n = T(0);                          // expected number of fibers crossed
    glm::vec<3, T> transmittance{T(1)};  // T_f ≈ a_f^n
    glm::vec<3, T> spread{T(0)};         // σ̄²_f ≈ n β̄²_f
};

// Asks any density source for n from x toward the light (wi, unit) and turns it into T_f
// and σ̄²_f; a_f and β̄²_f are the table values at the inclination of wi. Host and device
// when D's fibers_crossed is (nvcc would otherwise warn for a host-only D).
#if defined(__NVCC__)
#pragma nv_exec_check_disable
#endif
template <typename D, typename T>
HAIRSCATTER_HD ForwardScattering<T> forward_scattering(const D& density, const glm::vec<3, T>& x,
                                                       const glm::vec<3, T>& wi, const glm::vec<3, T>& a_f,
                                                       const glm::vec<3, T>& beta2_f,
                                                       T max_distance = kUnbounded<T>) {
    static_assert(is_density_source_v<D, T>,
                  "hairscatter: not a density source: the type needs a member "
                  "T fibers_crossed(const glm::vec<3, T>& origin, const glm::vec<3, T>& direction, "
                  "T max_distance) const (see hairscatter/dual/density.hpp)");
    ForwardScattering<T> r;
    r.n = T(density.fibers_crossed(x, wi, max_distance));
    r.transmittance = forward_transmittance(a_f, r.n);
    r.spread = forward_spread(beta2_f, r.n);
    return r;
}

// ---------------------------------------------------------------------------------------
// The shipped dense grid
// ---------------------------------------------------------------------------------------
//
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
// error is O(step²): at most 0.4 % at the default step across the faces of a block of
// parallel strands, 0 inside it (tests/density_test.cpp). n is the expectation over where
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
    // L_v·D·(mean sinψ), the orientation model at the top of this section.
    HAIRSCATTER_HD T crossing_density(const V3& p, const V3& d) const { return crossing(tensor_density(p), d); }

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

// The shipped density source: a dense grid of hair length (and orientation) per cell over
// an axis-aligned box, built on the host from strands (polylines), queried on the host or,
// through view(), on a GPU. Construction validates every parameter and throws
// std::invalid_argument with a message naming it.
template <typename T> class DensityGrid {
  public:
    using V3 = glm::vec<3, T>;
    using Cell = HairLengthTensor<T>;

    // Limits that keep indices and step counts in int range (and memory sane).
    static constexpr long long kMaxCells = 1LL << 30;
    static constexpr long long kMaxMarchSteps = 1LL << 24;  // per ray, across the diagonal

    // An empty grid of resolution.x × .y × .z cells over [box_min, box_max] for fibers of
    // radius fiber_radius. The march step defaults to half the smallest cell side.
    DensityGrid(const V3& box_min, const V3& box_max, const glm::ivec3& resolution, T fiber_radius,
                FiberOrientation orientation = FiberOrientation::kTracked) {
        using std::isfinite;
        std::ostringstream msg;
        auto bad = [&](const std::string& what) { msg << (msg.tellp() > 0 ? "; " : "") << what; };
        const char* axis[3] = {"x", "y", "z"};
        for (int a = 0; a < 3; ++a) {
            if (!isfinite(box_min[a]) || !isfinite(box_max[a]) || !(box_max[a] > box_min[a]))
                bad(std::string("box_max.") + axis[a] + " = " + num(box_max[a]) + " must be finite and above box_min." +
                    axis[a] + " = " + num(box_min[a]));
            if (resolution[a] < 1)
                bad(std::string("resolution.") + axis[a] + " = " + std::to_string(resolution[a]) + " must be ≥ 1");
        }
        if (!(fiber_radius > T(0)) || !isfinite(fiber_radius))
            bad("fiber_radius = " + num(fiber_radius) + " is outside (0, inf)");
        if (msg.tellp() == 0 &&
            double(resolution.x) * double(resolution.y) * double(resolution.z) > double(kMaxCells))
            bad("resolution " + std::to_string(resolution.x) + " x " + std::to_string(resolution.y) + " x " +
                std::to_string(resolution.z) + " exceeds " + std::to_string(kMaxCells) + " cells");
        if (msg.tellp() > 0) HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DensityGrid: " + msg.str()));

        g_.lo_ = box_min;
        g_.hi_ = box_max;
        g_.res_ = resolution;
        const V3 cell = (box_max - box_min) / V3(resolution);
        g_.inv_cell_ = T(1) / cell;
        g_.inv_volume_ = T(1) / (cell.x * cell.y * cell.z);
        g_.diameter_ = T(2) * fiber_radius;
        g_.orientation_ = orientation;
        cells_.assign(std::size_t(resolution.x) * std::size_t(resolution.y) * std::size_t(resolution.z), Cell{});
        const T smallest = cell.x < cell.y ? (cell.x < cell.z ? cell.x : cell.z) : (cell.y < cell.z ? cell.y : cell.z);
        set_march_step(T(0.5) * smallest);
    }

    // A grid of cubic cells of side cell_size around the strands: their bounds (finite
    // points only) padded by one cell on every side; then every strand is added.
    static DensityGrid from_strands(const std::vector<std::vector<V3>>& strands, T cell_size, T fiber_radius,
                                    FiberOrientation orientation = FiberOrientation::kTracked) {
        using std::ceil;
        using std::isfinite;
        if (!(cell_size > T(0)) || !isfinite(cell_size))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DensityGrid::from_strands: cell_size = " + num(cell_size) +
                                        " is outside (0, inf)"));
        V3 lo(std::numeric_limits<T>::max()), hi(std::numeric_limits<T>::lowest());
        bool any = false;
        for (const auto& strand : strands)
            for (const V3& p : strand)
                if (detail::finite3(p)) {
                    lo = glm::min(lo, p);
                    hi = glm::max(hi, p);
                    any = true;
                }
        if (!any) HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DensityGrid::from_strands: strands has no finite point"));
        glm::ivec3 res;
        for (int a = 0; a < 3; ++a) {
            const T inner = ceil((hi[a] - lo[a]) / cell_size);
            if (!(inner <= T(kMaxCells)))
                HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DensityGrid::from_strands: cell_size = " + num(cell_size) +
                                            " gives more than " + std::to_string(kMaxCells) + " cells"));
            res[a] = int(inner) + 2;  // one padding cell either side
        }
        const V3 box_min = lo - V3(cell_size);
        DensityGrid grid(box_min, box_min + V3(res) * cell_size, res, fiber_radius, orientation);
        for (const auto& strand : strands) grid.add_strand(strand);
        return grid;
    }

    // Adds the polyline through points[0 .. count); returns the length deposited.
    T add_strand(const V3* points, std::size_t count) {
        T sum = T(0);
        for (std::size_t i = 1; i < count; ++i) sum += add_segment(points[i - 1], points[i]);
        return sum;
    }
    T add_strand(const std::vector<V3>& points) { return add_strand(points.data(), points.size()); }

    // Adds the segment a–b: it is split at every cell face it crosses and each piece's
    // length goes to the cell that holds it, so the deposit is exact. Parts outside the box
    // and segments with a non-finite end are skipped. Returns the length deposited.
    T add_segment(const V3& a, const V3& b) {
        using std::ceil;
        using std::floor;
        const V3 d = b - a;
        const T length = glm::length(d);
        if (!(length > T(0)) || !detail::finite3(a) || !detail::finite3(b)) return T(0);
        const detail::Span<T> s = detail::clip_to_box(g_.lo_, g_.hi_, a, d, T(1));
        if (!(s.t1 > s.t0)) return T(0);
        const Cell unit = Cell::piece(T(1), d / length);
        const V3 cell = cell_size();
        // Per axis: the index k of the next cell face the segment reaches and its parameter t.
        int k[3] = {0, 0, 0}, dk[3] = {1, 1, 1};
        T next[3];
        auto face_t = [&](int ax) { return (g_.lo_[ax] + T(k[ax]) * cell[ax] - a[ax]) / d[ax]; };
        for (int ax = 0; ax < 3; ++ax) {
            const T u = (a[ax] + s.t0 * d[ax] - g_.lo_[ax]) * g_.inv_cell_[ax];
            if (d[ax] == T(0)) {
                next[ax] = kUnbounded<T>;
                continue;
            }
            dk[ax] = d[ax] > T(0) ? 1 : -1;
            k[ax] = d[ax] > T(0) ? int(floor(u)) + 1 : int(ceil(u)) - 1;
            next[ax] = face_t(ax);
        }
        T t = s.t0, deposited = T(0);
        while (t < s.t1) {
            T tn = s.t1;
            for (int ax = 0; ax < 3; ++ax) tn = next[ax] < tn ? next[ax] : tn;
            if (tn > t) {
                // The piece [t, tn] lies in one cell; its midpoint names the cell robustly.
                const V3 mid = a + (T(0.5) * (t + tn)) * d;
                int c[3];
                for (int ax = 0; ax < 3; ++ax)
                    c[ax] = clamp(int(floor((mid[ax] - g_.lo_[ax]) * g_.inv_cell_[ax])), 0, g_.res_[ax] - 1);
                const T l = (tn - t) * length;
                cells_[index(c[0], c[1], c[2])].add_scaled(l, unit);
                deposited += l;
            }
            // Each pass moves past at least one face or ends at t1, so the loop terminates.
            for (int ax = 0; ax < 3; ++ax)
                if (next[ax] <= tn) {
                    k[ax] += dk[ax];
                    next[ax] = face_t(ax);
                }
            t = tn;
        }
        return deposited;
    }

    // The march step of fibers_crossed: in (0, inf) and no finer than diagonal / kMaxMarchSteps.
    void set_march_step(T step) {
        using std::isfinite;
        const T diagonal = glm::length(g_.hi_ - g_.lo_);
        if (!(step > T(0)) || !isfinite(step) || !(diagonal / step <= T(kMaxMarchSteps)))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DensityGrid: march step = " + num(step) +
                                        " is outside [box diagonal / " + std::to_string(kMaxMarchSteps) + " = " +
                                        num(diagonal / T(kMaxMarchSteps)) + ", inf)"));
        g_.step_ = step;
    }

    // The queries over this grid's cells (valid while the grid lives and is not modified
    // in size), or over a copy of cells() elsewhere, e.g. device memory.
    DensityGridView<T> view() const { return g_.with_cells(cells_.data()); }
    DensityGridView<T> view(const Cell* cells) const { return g_.with_cells(cells); }

    T length_density(const V3& p) const { return view().length_density(p); }
    T crossing_density(const V3& p, const V3& d) const { return view().crossing_density(p, d); }
    T fibers_crossed(const V3& origin, const V3& direction, T max_distance) const {
        return view().fibers_crossed(origin, direction, max_distance);
    }

    // Hair length held by the grid (the sum over cells).
    T total_length() const {
        T sum = T(0);
        for (const Cell& c : cells_) sum += c.length();
        return sum;
    }

    const V3& box_min() const { return g_.lo_; }
    const V3& box_max() const { return g_.hi_; }
    const glm::ivec3& resolution() const { return g_.res_; }
    V3 cell_size() const { return (g_.hi_ - g_.lo_) / V3(g_.res_); }
    T fiber_radius() const { return T(0.5) * g_.diameter_; }
    T march_step() const { return g_.step_; }
    FiberOrientation orientation() const { return g_.orientation_; }
    const std::vector<Cell>& cells() const { return cells_; }

  private:
    static std::string num(T v) {
        std::ostringstream s;
        s << double(v);
        return s.str();
    }
    std::size_t index(int i, int j, int k) const {
        return std::size_t(i) + std::size_t(g_.res_.x) * (std::size_t(j) + std::size_t(g_.res_.y) * std::size_t(k));
    }

    DensityGridView<T> g_;  // the geometry; view() points it at cells_
    std::vector<Cell> cells_;
};

}  // namespace hairscatter
