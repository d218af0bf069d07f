// hairscatter — the shipped density source: a dense voxel grid of hair length and
// orientation, built on the host from strands (its queries: dual/density_grid_view.hpp).
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/functions.hpp"
#include "density_grid_view.hpp"
#include "settings.hpp"

namespace hairscatter {

// A read-only view of size elements at data, owned by the caller (C++17 has no std::span):
// how DensityGrid::from_strands reads a renderer's own arrays without copying them.
template <typename E> struct ConstView {
    const E* data = nullptr;
    std::size_t size = 0;

    constexpr ConstView() = default;
    constexpr ConstView(const E* d, std::size_t n) : data(d), size(n) {}
    ConstView(const std::vector<E>& v) : data(v.data()), size(v.size()) {}  // NOLINT: implicit by design
    constexpr const E& operator[](std::size_t i) const { return data[i]; }
    constexpr bool empty() const { return size == 0; }
};
template <typename E> ConstView(const E*, std::size_t) -> ConstView<E>;
template <typename E> ConstView(const std::vector<E>&) -> ConstView<E>;

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
        if (msg.tellp() == 0) check_range(box_min, box_max, resolution, bad);
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
    // points only) padded by one cell on every side; then every strand is added. Points
    // that are not finite are skipped with their segments.
    static DensityGrid from_strands(const std::vector<std::vector<V3>>& strands, T cell_size, T fiber_radius,
                                    FiberOrientation orientation = FiberOrientation::kTracked) {
        V3 lo(std::numeric_limits<T>::max()), hi(std::numeric_limits<T>::lowest());
        bool any = false;
        for (const auto& strand : strands)
            for (const V3& p : strand)
                if (detail::finite3(p)) {
                    lo = glm::min(lo, p);
                    hi = glm::max(hi, p);
                    any = true;
                }
        DensityGrid grid = around(lo, hi, any, cell_size, fiber_radius, orientation);
        for (const auto& strand : strands) grid.add_strand(strand);
        return grid;
    }

    // The same grid from the arrays a renderer already holds (pbrt's and Embree's layout),
    // read in place: all strands' points back to back, and strand_starts[i] the index of
    // strand i's first point (strand i ends where strand i + 1 starts, the last one at
    // points.size). strand_radii, when not empty, holds one radius per strand; strand i
    // then deposits its length times r_i / fiber_radius, so that a count, 2r per unit of
    // length crossed, is Σ 2 r_i ℓ_i (the projected area), and fiber_radius is the grid's
    // reference radius (e.g. the strands' mean). Unlike the nested form, which skips them,
    // every bad input throws std::invalid_argument naming it: a non-finite point, starts
    // that decrease or exceed points.size, a radius count other than the strand count, a
    // radius that is negative or not finite. Index is any integer type (int for pbrt,
    // unsigned for Embree, std::size_t).
    template <typename Index>
    static DensityGrid from_strands(ConstView<V3> points, ConstView<Index> strand_starts, T cell_size, T fiber_radius,
                                    ConstView<T> strand_radii = {},
                                    FiberOrientation orientation = FiberOrientation::kTracked) {
        static_assert(std::is_integral<Index>::value, "hairscatter: strand_starts must hold integers");
        using std::isfinite;
        const char* who = "hairscatter: DensityGrid::from_strands: ";
        const std::size_t strands = strand_starts.size;
        if ((points.size > 0 && points.data == nullptr) || (strands > 0 && strand_starts.data == nullptr) ||
            (strand_radii.size > 0 && strand_radii.data == nullptr))
            HAIRSCATTER_THROW(std::invalid_argument(std::string(who) + "a view has a size but no data"));
        for (std::size_t i = 0; i < strands; ++i) {
            const Index s = strand_starts[i];
            if (negative(s) || static_cast<unsigned long long>(s) > static_cast<unsigned long long>(points.size))
                HAIRSCATTER_THROW(std::invalid_argument(std::string(who) + "strand_starts[" + std::to_string(i) +
                                                        "] = " + std::to_string(s) + " is outside [0, points.size = " +
                                                        std::to_string(points.size) + "]"));
            if (i > 0 && s < strand_starts[i - 1])
                HAIRSCATTER_THROW(std::invalid_argument(std::string(who) + "strand_starts[" + std::to_string(i) +
                                                        "] = " + std::to_string(s) + " is below strand_starts[" +
                                                        std::to_string(i - 1) + "] = " +
                                                        std::to_string(strand_starts[i - 1]) +
                                                        " (starts must not decrease)"));
        }
        if (!strand_radii.empty() && strand_radii.size != strands)
            HAIRSCATTER_THROW(std::invalid_argument(std::string(who) + "strand_radii has " +
                                                    std::to_string(strand_radii.size) + " entries for " +
                                                    std::to_string(strands) + " strands (give one per strand, or none)"));
        for (std::size_t i = 0; i < strand_radii.size; ++i)
            if (!(strand_radii[i] >= T(0)) || !isfinite(strand_radii[i]))
                HAIRSCATTER_THROW(std::invalid_argument(std::string(who) + "strand_radii[" + std::to_string(i) +
                                                        "] = " + num(strand_radii[i]) + " is outside [0, inf)"));
        const std::size_t first = strands > 0 ? std::size_t(strand_starts[0]) : points.size;
        V3 lo(std::numeric_limits<T>::max()), hi(std::numeric_limits<T>::lowest());
        for (std::size_t i = first; i < points.size; ++i) {
            if (!detail::finite3(points[i]))
                HAIRSCATTER_THROW(std::invalid_argument(std::string(who) + "points[" + std::to_string(i) + "] = " +
                                                        num3(points[i]) + " is not finite"));
            lo = glm::min(lo, points[i]);
            hi = glm::max(hi, points[i]);
        }
        DensityGrid grid = around(lo, hi, first < points.size, cell_size, fiber_radius, orientation);
        for (std::size_t i = 0; i < strands; ++i) {
            const std::size_t b = std::size_t(strand_starts[i]);
            const std::size_t e = i + 1 < strands ? std::size_t(strand_starts[i + 1]) : points.size;
            const T w = strand_radii.empty() ? T(1) : strand_radii[i] / fiber_radius;
            for (std::size_t k = b + 1; k < e; ++k) grid.deposit(points[k - 1], points[k], w);
        }
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
    // and segments with a non-finite end are skipped. A segment between finite ends whose
    // length overflows T (an end near the largest float) throws std::invalid_argument: its
    // deposit was +Inf and its direction NaN.
    T add_segment(const V3& a, const V3& b) { return deposit(a, b, T(1)); }
  private:
    // add_segment with each piece's length times w (the strand's radius over the grid's);
    // returns the length deposited, unweighted.
    T deposit(const V3& a, const V3& b, T w) {
        using std::ceil;
        using std::floor;
        if (!detail::finite3(a) || !detail::finite3(b)) return T(0);
        const V3 d = b - a;
        const T length = glm::length(d);
        if (!detail::finite3(d) || !is_finite(length))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DensityGrid::add_segment: a = " + num3(a) + ", b = " +
                                                    num3(b) + ": the segment's length overflows " + type_name()));
        if (!(length > T(0))) return T(0);
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
                cells_[index(c[0], c[1], c[2])].add_scaled(l * w, unit);
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

  public:
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
    // Negative starts are refused before the cast to an unsigned type could wrap them.
    template <typename Index> static bool negative(Index i) {
        if constexpr (std::is_signed<Index>::value) return i < Index(0);
        return false;
    }

    // The empty grid of cubic cells of side cell_size around the points' bounds [lo, hi]
    // (any: there was a finite point), padded by one cell on every side.
    static DensityGrid around(const V3& lo, const V3& hi, bool any, T cell_size, T fiber_radius,
                              FiberOrientation orientation) {
        using std::ceil;
        using std::isfinite;
        if (!(cell_size > T(0)) || !isfinite(cell_size))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DensityGrid::from_strands: cell_size = " + num(cell_size) +
                                                    " is outside (0, inf)"));
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
        return DensityGrid(box_min, box_min + V3(res) * cell_size, res, fiber_radius, orientation);
    }
    static std::string num(T v) {
        std::ostringstream s;
        s << double(v);
        return s.str();
    }
    static std::string num3(const V3& v) { return "(" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ")"; }
    static const char* type_name() { return sizeof(T) == sizeof(float) ? "float" : "double"; }

    // The box's arithmetic in T, given finite, ordered bounds and a resolution ≥ 1: its
    // extent and diagonal finite, each cell side a normal number, and the cell volume within
    // [1/√max, 1/√min] of T, so that a density (length per volume) and its square in the
    // crossing density stay normal and finite. A 1e-38 box in float had subnormal cells and
    // answered NaN; a cell of 1e-12 overflowed the square of one fiber's density.
    template <typename Bad> static void check_range(const V3& lo, const V3& hi, const glm::ivec3& res, Bad&& bad) {
        using std::sqrt;
        const char* axis[3] = {"x", "y", "z"};
        const T smallest = std::numeric_limits<T>::min(), largest = std::numeric_limits<T>::max();
        const V3 extent = hi - lo, cell = extent / V3(res);
        for (int a = 0; a < 3; ++a) {
            if (!is_finite(extent[a]))
                bad(std::string("box_max.") + axis[a] + " - box_min." + axis[a] + " = " + num(hi[a]) + " - " +
                    num(lo[a]) + " overflows " + type_name());
            else if (!(cell[a] >= smallest))
                bad(std::string("the cell size along ") + axis[a] + ", (box_max - box_min)." + axis[a] + " / resolution." +
                    axis[a] + " = " + num(cell[a]) + ", is below the smallest normal " + type_name() + " " + num(smallest));
        }
        if (!detail::finite3(extent) || !(cell.x >= smallest && cell.y >= smallest && cell.z >= smallest)) return;
        if (!is_finite(glm::length(extent)))
            bad("the box diagonal |box_max - box_min| overflows " + std::string(type_name()));
        const T volume = cell.x * cell.y * cell.z, lo_volume = T(1) / sqrt(largest), hi_volume = T(1) / sqrt(smallest);
        if (!(volume >= lo_volume && volume <= hi_volume))
            bad("the cell volume " + num(cell.x) + " x " + num(cell.y) + " x " + num(cell.z) + " = " + num(volume) +
                " is outside [" + num(lo_volume) + ", " + num(hi_volume) + "], where densities and their squares stay "
                "finite in " + type_name());
    }
    std::size_t index(int i, int j, int k) const {
        return std::size_t(i) + std::size_t(g_.res_.x) * (std::size_t(j) + std::size_t(g_.res_.y) * std::size_t(k));
    }

    DensityGridView<T> g_;  // the geometry; view() points it at cells_
    std::vector<Cell> cells_;
};

}  // namespace hairscatter
