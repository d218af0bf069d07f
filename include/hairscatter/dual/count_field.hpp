// hairscatter — a directional count field: the expected number of fibers between any point
// and the edge of the hair along any direction, precomputed so that a renderer's count is a
// lookup instead of a ray (docs/dual.md, "Counts as lookups"; docs/theory.md §5.8).
//
// Deep opacity maps (Kim & Neumann 2001; Yuksel & Keyser 2008) store, per light, the
// amount of hair between the light and every point; Zinke et al. 2008 read the forward
// count n from them. The two-stream estimator (two_stream.hpp) asks for counts along
// directions sampled from the fiber, not toward a light, so this field stores the same
// quantity for a fixed set of directions covering the sphere:
//
//     C(x, d) = expected fibers crossed from x to where the ray x + t d leaves the box,
//
// at the points of a regular lattice over a box and the directions at the texel centres of
// an octahedral map (Engelhardt & Dachsbacher 2008; side S: S² directions, about 180°/S
// apart). A query interpolates trilinearly in space and bilinearly in the octahedral map:
// 32 reads, no march. Counts along a segment follow by differencing, exactly for the line:
//
//     n(x → x + t d) = C(x, d) − C(x + t d, d),
//
// so the field is itself a density source (density_source.hpp) and plugs in wherever the
// grid does. It is light-independent: an area light, an environment or a light that moves
// reads the same field; only moving hair makes it stale (rebuild it from the new source).
//
// Build. Per direction d, with A the axis where |d_A| is largest, the lattice's planes
// normal to A are swept from the side where rays along d leave the box: a point p takes
// the count of the segment from p to the next plane, q = p + (h_A/|d_A|) d, from the
// source, plus C(q, d) interpolated bilinearly on that plane (already done); a segment that
// leaves the box through a side face first ends there. One short source query per point
// and direction: a 35³ lattice and 144 directions build in a fraction of a second per
// core over the shipped grid. Interpolating the plane blurs C sideways by about a lattice
// spacing over the box: finer than the grid it reads, whose cells already average the hair.
//
// Any density source can feed the build (the shipped DensityGrid, an OpenVDB wrapper, a
// deep-opacity map); its answers are sanitised: NaN and negative counts read as 0, +Inf and
// counts above kMaxSegmentCount as that cap, so the field holds only finite counts ≥ 0.
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
#include "../math/functions.hpp"
#include "density_grid.hpp"
#include "density_grid_view.hpp"
#include "density_source.hpp"
#include "settings.hpp"

namespace hairscatter {

namespace detail {

// The octahedral map (Engelhardt & Dachsbacher 2008, "Octahedron environment maps"): a unit
// direction to [0, 1]², and back. The lower hemisphere folds onto the square's corners.
template <typename T> HAIRSCATTER_HD glm::vec<2, T> octahedral_encode(const glm::vec<3, T>& d) {
    const T l1 = abs_value(d.x) + abs_value(d.y) + abs_value(d.z);
    T x = d.x / l1, y = d.y / l1;
    if (d.z < T(0)) {
        const T fx = (T(1) - abs_value(y)) * (x >= T(0) ? T(1) : T(-1));
        const T fy = (T(1) - abs_value(x)) * (y >= T(0) ? T(1) : T(-1));
        x = fx, y = fy;
    }
    return glm::vec<2, T>(T(0.5) * (x + T(1)), T(0.5) * (y + T(1)));
}
template <typename T> HAIRSCATTER_HD glm::vec<3, T> octahedral_decode(const glm::vec<2, T>& uv) {
    T x = T(2) * uv.x - T(1), y = T(2) * uv.y - T(1);
    const T z = T(1) - abs_value(x) - abs_value(y);
    if (z < T(0)) {
        const T fx = (T(1) - abs_value(y)) * (x >= T(0) ? T(1) : T(-1));
        const T fy = (T(1) - abs_value(x)) * (y >= T(0) ? T(1) : T(-1));
        x = fx, y = fy;
    }
    return glm::normalize(glm::vec<3, T>(x, y, z));
}

// Whether D has T crossing_density(const vec3&, const vec3&) const (fibers per unit length
// at a point along a direction, as DensityGridView has).
template <typename D, typename T, typename = void> struct has_crossing_density : std::false_type {};
template <typename D, typename T>
struct has_crossing_density<D, T,
                            std::void_t<decltype(T(std::declval<const D&>().crossing_density(
                                std::declval<const glm::vec<3, T>&>(), std::declval<const glm::vec<3, T>&>())))>>
    : std::true_type {};

}  // namespace detail

// The queries of a DirectionalCountField over counts it does not own: trivially copyable,
// device-callable and check-free (pass it to a GPU kernel with field.view(device_counts)).
template <typename T> class DirectionalCountFieldView {
  public:
    using V3 = glm::vec<3, T>;

    DirectionalCountFieldView() = default;  // no field: every query answers 0

    HAIRSCATTER_HD DirectionalCountFieldView with_counts(const T* counts) const {
        DirectionalCountFieldView v = *this;
        v.counts_ = counts;
        return v;
    }

    // C(origin, direction): expected fibers from origin to where the ray leaves the box (a
    // ray from outside that enters counts from its entry; one that misses the box, 0).
    // direction need not be unit. A zero, NaN or infinite direction or origin gives 0.
    HAIRSCATTER_HD T fibers_to_exit(const V3& origin, const V3& direction) const {
        using std::sqrt;
        if (counts_ == nullptr) return T(0);
        const T len2 = glm::dot(direction, direction);
        if (!(len2 > T(0)) || !is_finite(len2) || !is_finite(origin)) return T(0);
        const V3 d = direction / sqrt(len2);
        return to_exit(origin, d, lookup_direction(d));
    }

    // The density-source query (density_source.hpp): expected fibers between origin and
    // origin + max_distance·direction (a distance along the normalised direction; kUnbounded
    // or beyond the box: to the box's edge). max_distance ≤ 0 or NaN gives 0.
    HAIRSCATTER_HD T fibers_crossed(const V3& origin, const V3& direction, T max_distance) const {
        using std::sqrt;
        if (counts_ == nullptr || !(max_distance > T(0))) return T(0);
        const T len2 = glm::dot(direction, direction);
        if (!(len2 > T(0)) || !is_finite(len2) || !is_finite(origin)) return T(0);
        const V3 d = direction / sqrt(len2);
        const Texels dir = lookup_direction(d);
        const T all = to_exit(origin, d, dir);
        if (!is_finite(max_distance)) return all;
        const V3 end = origin + max_distance * d;
        if (!is_finite(end)) return all;
        const T rest = to_exit(end, d, dir);
        return all > rest ? all - rest : T(0);
    }

    // Where the fibers along the ray end: the distance t in [0, max_distance] past which less
    // than min(1/2, C/2) of the C fibers expected on the segment remain, by bisection to 1/64
    // of the segment's length within the box. For speed the counts come from the stored
    // direction nearest to d (8 values a query, not 32). max_distance must be finite (or
    // kUnbounded: to the box's edge); non-finite or non-positive input gives 0.
    HAIRSCATTER_HD T stack_end(const V3& origin, const V3& direction, T max_distance) const {
        using std::sqrt;
        if (counts_ == nullptr || !(max_distance > T(0))) return T(0);
        const T len2 = glm::dot(direction, direction);
        if (!(len2 > T(0)) || !is_finite(len2) || !is_finite(origin)) return T(0);
        const V3 d = direction / sqrt(len2);
        const detail::Span<T> span = detail::clip_to_box(lo_, hi_, origin, d, max_distance);
        if (!(span.t1 > span.t0) || !is_finite(span.t1)) return T(0);
        const Texels dir = lookup_direction(d);
        int best = 0;
        for (int t = 1; t < 4; ++t) best = dir.w[t] > dir.w[best] ? t : best;
        const T* counts = counts_ + std::size_t(dir.k[best]);
        const auto C = [&](T t) {  // C at origin + t d, t within the span (corner() clamps rounding)
            std::size_t base;
            std::size_t stride[3];
            T f[3];
            corner(origin + t * d, base, stride, f);
            return trilinear(counts + base, stride, f);
        };
        const T first = C(span.t0), beyond = C(span.t1);
        const T inside = first - beyond;
        if (!(inside > T(0))) return span.t0;
        const T rest = beyond + (inside * T(0.5) < T(0.5) ? inside * T(0.5) : T(0.5));
        T lo = span.t0, hi = span.t1;
        for (int i = 0; i < 6; ++i) {
            const T mid = T(0.5) * (lo + hi);
            if (C(mid) > rest) lo = mid;
            else hi = mid;
        }
        return hi;
    }

    HAIRSCATTER_HD const V3& box_min() const { return lo_; }
    HAIRSCATTER_HD const V3& box_max() const { return hi_; }
    HAIRSCATTER_HD const glm::ivec3& points() const { return points_; }
    HAIRSCATTER_HD int octahedral_side() const { return side_; }
    HAIRSCATTER_HD int direction_count() const { return side_ * side_; }
    // The k-th stored direction (texel k % side, k / side of the octahedral map).
    HAIRSCATTER_HD V3 direction(int k) const {
        const int i = k % side_, j = k / side_;
        return detail::octahedral_decode(glm::vec<2, T>((T(i) + T(0.5)) / T(side_), (T(j) + T(0.5)) / T(side_)));
    }
    HAIRSCATTER_HD const T* counts() const { return counts_; }

  private:
    template <typename> friend class DirectionalCountField;

    // The four octahedral texels around a direction and their bilinear weights.
    struct Texels {
        int k[4];
        T w[4];
    };
    HAIRSCATTER_HD Texels lookup_direction(const V3& d) const {
        const glm::vec<2, T> uv = detail::octahedral_encode(d);
        int i0[2];
        T f[2];
        for (int a = 0; a < 2; ++a) {
            const T u = clamp(uv[a] * T(side_) - T(0.5), T(0), T(side_ - 1));
            int c = int(u);
            if (c > side_ - 2) c = side_ - 2;
            i0[a] = c;
            f[a] = u - T(c);
        }
        Texels t;
        t.k[0] = i0[0] + side_ * i0[1];
        t.k[1] = t.k[0] + 1;
        t.k[2] = t.k[0] + side_;
        t.k[3] = t.k[2] + 1;
        t.w[0] = (T(1) - f[0]) * (T(1) - f[1]);
        t.w[1] = f[0] * (T(1) - f[1]);
        t.w[2] = (T(1) - f[0]) * f[1];
        t.w[3] = f[0] * f[1];
        return t;
    }

    // The trilinear interpolation of one direction's counts c (at a cell's first corner).
    HAIRSCATTER_HD static T trilinear(const T* c, const std::size_t stride[3], const T f[3]) {
        const T x00 = c[0] + f[0] * (c[stride[0]] - c[0]);
        const T x10 = c[stride[1]] + f[0] * (c[stride[1] + stride[0]] - c[stride[1]]);
        const T x01 = c[stride[2]] + f[0] * (c[stride[2] + stride[0]] - c[stride[2]]);
        const T x11 = c[stride[2] + stride[1]] + f[0] * (c[stride[2] + stride[1] + stride[0]] - c[stride[2] + stride[1]]);
        const T y0 = x00 + f[1] * (x10 - x00), y1 = x01 + f[1] * (x11 - x01);
        return y0 + f[2] * (y1 - y0);
    }

    // C at origin along the unit d, with d's texels.
    HAIRSCATTER_HD T to_exit(const V3& origin, const V3& d, const Texels& dir) const {
        const detail::Span<T> s = detail::clip_to_box(lo_, hi_, origin, d, kUnbounded<T>);
        if (!(s.t1 > s.t0)) return T(0);
        const V3 p = origin + s.t0 * d;
        std::size_t base;
        std::size_t stride[3];
        T f[3];
        corner(p, base, stride, f);
        T sum = T(0);
        for (int t = 0; t < 4; ++t) sum += dir.w[t] * trilinear(counts_ + std::size_t(dir.k[t]) + base, stride, f);
        return sum > T(0) ? sum : T(0);
    }

    // The lattice cell holding p (clamped into the box): the offset of its first point's
    // counts, the offset strides of its corners per axis and p's fractions within it. The
    // counts are stored point by point, every direction of a point together (a point's
    // counts are one block of direction_count() values): the lookups of one shading point
    // (its stacks, the turned directions of the shape's limit) read the same few blocks.
    HAIRSCATTER_HD void corner(const V3& p, std::size_t& base, std::size_t stride[3], T f[3]) const {
        int c[3];
        const std::size_t dirs = std::size_t(side_) * std::size_t(side_);
        const std::size_t unit[3] = {dirs, dirs * std::size_t(points_.x),
                                     dirs * std::size_t(points_.x) * std::size_t(points_.y)};
        for (int a = 0; a < 3; ++a) {
            const int n = points_[a];
            const T u = clamp((p[a] - lo_[a]) * inv_spacing_[a], T(0), T(n - 1));
            int i = int(u);
            if (i > n - 2) i = n - 2;
            c[a] = i;
            f[a] = u - T(i);
            stride[a] = unit[a];
        }
        base = unit[0] * std::size_t(c[0]) + unit[1] * std::size_t(c[1]) + unit[2] * std::size_t(c[2]);
    }

    V3 lo_{T(0)}, hi_{T(1)}, inv_spacing_{T(1)};
    glm::ivec3 points_{2};
    int side_ = 2;
    std::size_t per_direction_ = 8;  // lattice points: the counts of one direction
    const T* counts_ = nullptr;      // per point, its direction_count() counts (point-major)
};

// The field itself: owns the counts, built on the host from any density source.
// Construction validates every parameter and throws std::invalid_argument naming it.
template <typename T> class DirectionalCountField {
  public:
    using V3 = glm::vec<3, T>;

    // Limits on the octahedral side and on the stored counts (memory: 4 or 8 bytes each).
    static constexpr int kMaxSide = 64;
    static constexpr long long kMaxCounts = 1LL << 31;
    // The largest count one source query may add (larger, +Inf and NaN are sanitised).
    static constexpr T kMaxSegmentCount = T(1e4);

    // An unbuilt field (all counts 0) over [box_min, box_max] with points.x × .y × .z
    // lattice points (≥ 2 per axis, corners on the box's corners) and side² directions.
    DirectionalCountField(const V3& box_min, const V3& box_max, const glm::ivec3& points, int octahedral_side) {
        std::ostringstream msg;
        auto bad = [&](const std::string& what) { msg << (msg.tellp() > 0 ? "; " : "") << what; };
        const char* axis[3] = {"x", "y", "z"};
        for (int a = 0; a < 3; ++a) {
            if (!is_finite(box_min[a]) || !is_finite(box_max[a]) || !(box_max[a] > box_min[a]) ||
                !is_finite(box_max[a] - box_min[a]))
                bad(std::string("box_max.") + axis[a] + " = " + num(box_max[a]) + " must be finite and above box_min." +
                    axis[a] + " = " + num(box_min[a]));
            if (points[a] < 2) bad(std::string("points.") + axis[a] + " = " + std::to_string(points[a]) + " must be ≥ 2");
        }
        if (octahedral_side < 2 || octahedral_side > kMaxSide)
            bad("octahedral_side = " + std::to_string(octahedral_side) + " is outside [2, " + std::to_string(kMaxSide) +
                "]");
        if (msg.tellp() == 0 && double(points.x) * double(points.y) * double(points.z) * double(octahedral_side) *
                                        double(octahedral_side) >
                                    double(kMaxCounts))
            bad(std::to_string(points.x) + " x " + std::to_string(points.y) + " x " + std::to_string(points.z) +
                " points and " + std::to_string(octahedral_side * octahedral_side) + " directions exceed " +
                std::to_string(kMaxCounts) + " counts");
        if (msg.tellp() == 0) {
            for (int a = 0; a < 3; ++a) {
                const T spacing = (box_max[a] - box_min[a]) / T(points[a] - 1);
                if (!(spacing >= std::numeric_limits<T>::min()))
                    bad(std::string("the lattice spacing along ") + axis[a] + " = " + num(spacing) +
                        " is below the smallest normal number");
            }
        }
        if (msg.tellp() > 0) HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DirectionalCountField: " + msg.str()));
        v_.lo_ = box_min;
        v_.hi_ = box_max;
        v_.points_ = points;
        v_.side_ = octahedral_side;
        spacing_ = (box_max - box_min) / V3(points - glm::ivec3(1));
        v_.inv_spacing_ = T(1) / spacing_;
        v_.per_direction_ = std::size_t(points.x) * std::size_t(points.y) * std::size_t(points.z);
        counts_.assign(v_.per_direction_ * std::size_t(octahedral_side) * std::size_t(octahedral_side), T(0));
    }

    // The lattice over a grid of that resolution whose spacing is spacing_in_cells (≥ 1)
    // of its cells: ceil(cells / spacing) + 1 points per axis, corners on the box's.
    static glm::ivec3 points_over_grid(const glm::ivec3& grid_resolution, T spacing_in_cells) {
        glm::ivec3 pts;
        for (int a = 0; a < 3; ++a) {
            const T n = std::ceil(T(grid_resolution[a]) / spacing_in_cells);
            pts[a] = int(n > T(1) ? n : T(1)) + 1;
        }
        return pts;
    }

    // The field over a grid's box on points_over_grid's lattice, built from the grid.
    // Throws as the constructor, and for spacing_in_cells outside [1, inf).
    static DirectionalCountField from_grid(const DensityGrid<T>& grid, int octahedral_side = 12,
                                           T spacing_in_cells = T(1)) {
        if (!(spacing_in_cells >= T(1)) || !is_finite(spacing_in_cells))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DirectionalCountField::from_grid: spacing_in_cells = " +
                                                    num(spacing_in_cells) + " is outside [1, inf)"));
        DirectionalCountField f(grid.box_min(), grid.box_max(), points_over_grid(grid.resolution(), spacing_in_cells),
                                octahedral_side);
        f.build(grid.view());
        return f;
    }

    // The shipped grid's tensor density at every lattice point, read once for all directions
    // (build_direction(k, tensors) then skips the grid's trilinear reads, which are the same
    // for every direction: the counts are bit for bit those of build_direction(k, grid)).
    struct LatticeTensors {
        DensityGridView<T> grid;
        std::vector<HairLengthTensor<T>> tensors;  // x fastest, as the counts of one direction
    };
    LatticeTensors lattice_tensors(const DensityGridView<T>& grid) const {
        LatticeTensors out{grid, {}};
        const glm::ivec3 n = v_.points_;
        out.tensors.resize(v_.per_direction_);
        for (int z = 0; z < n.z; ++z)
            for (int y = 0; y < n.y; ++y)
                for (int x = 0; x < n.x; ++x)
                    out.tensors[std::size_t(x) + std::size_t(n.x) * (std::size_t(y) + std::size_t(n.y) * std::size_t(z))] =
                        grid.tensor_density(lattice_point(x, y, z));
        return out;
    }

    // Fills every direction from the source (see the top of this header).
    template <typename D> void build(const D& source) {
        if constexpr (std::is_same_v<D, DensityGridView<T>>) {
            const LatticeTensors pre = lattice_tensors(source);
            for (int k = 0; k < direction_count(); k += kBuildBlock) build_directions(k, k + kBuildBlock, pre);
        } else {
            for (int k = 0; k < direction_count(); k += kBuildBlock) build_directions(k, k + kBuildBlock, source);
        }
    }

    // Directions per block of build_directions that keeps parallel builds off each other's
    // cache lines (a point's counts are stored together: 16 floats are one 64-byte line).
    static constexpr int kBuildBlock = 16;

    // Fills directions [k_begin, k_end) only (k_end is clamped to direction_count()): distinct
    // ranges write disjoint counts, so a renderer may build them in parallel (the source
    // must then answer concurrent const queries). Ranges of kBuildBlock directions starting
    // at multiples of it are the fastest: each point's counts of the range are written at once.
    template <typename D> void build_directions(int k_begin, int k_end, const D& source) {
        static_assert(is_density_source_v<D, T>,
                      "hairscatter: DirectionalCountField::build: not a density source (see "
                      "hairscatter/dual/density_source.hpp)");
        build_range(k_begin, k_end, source,
                    [&](const glm::ivec3&, const V3& p, const V3& d) { return rate(source, p, d); });
    }
    // The same from the grid's tensors at the lattice points (lattice_tensors(grid)).
    void build_directions(int k_begin, int k_end, const LatticeTensors& pre) {
        if (pre.tensors.size() != v_.per_direction_)
            HAIRSCATTER_THROW(std::invalid_argument(
                "hairscatter: DirectionalCountField::build_direction: the lattice tensors are not this field's"));
        const glm::ivec3 n = v_.points_;
        build_range(k_begin, k_end, pre.grid, [&](const glm::ivec3& ijk, const V3&, const V3& d) {
            const std::size_t i =
                std::size_t(ijk.x) + std::size_t(n.x) * (std::size_t(ijk.y) + std::size_t(n.y) * std::size_t(ijk.z));
            return sanitise(pre.grid.crossing_density_of(pre.tensors[i], d));
        });
    }
    // Direction k alone (build_directions(k, k + 1, source)).
    template <typename D> void build_direction(int k, const D& source) { build_directions(k, k + 1, source); }

  private:
    // Each direction of the range swept on its own (build_direction_from), then the range's
    // counts moved into the point-major store point by point.
    template <typename D, typename Rate>
    void build_range(int k_begin, int k_end, const D& source, const Rate& rate_of) {
        if (k_begin < 0 || k_begin >= direction_count())
            HAIRSCATTER_THROW(std::out_of_range("hairscatter: DirectionalCountField::build_directions: k = " +
                                                std::to_string(k_begin) + " is outside [0, " +
                                                std::to_string(direction_count()) + ")"));
        if (!(k_end > k_begin))
            HAIRSCATTER_THROW(std::out_of_range("hairscatter: DirectionalCountField::build_directions: the range [" +
                                                std::to_string(k_begin) + ", " + std::to_string(k_end) + ") is empty"));
        const int end = k_end < direction_count() ? k_end : direction_count();
        const std::size_t count = std::size_t(end - k_begin), points = v_.per_direction_;
        std::vector<T> swept(count * points);
        for (std::size_t j = 0; j < count; ++j)
            build_direction_from(k_begin + int(j), source, rate_of, swept.data() + j * points);
        const std::size_t dirs = std::size_t(direction_count());
        for (std::size_t i = 0; i < points; ++i) {
            T* dst = counts_.data() + i * dirs + std::size_t(k_begin);
            for (std::size_t j = 0; j < count; ++j) dst[j] = swept[j * points + i];
        }
    }

    // The lattice point (x, y, z), as build_direction places it.
    V3 lattice_point(int x, int y, int z) const {
        return V3(v_.lo_.x + T(x) * spacing_.x, v_.lo_.y + T(y) * spacing_.y, v_.lo_.z + T(z) * spacing_.z);
    }

    // build_direction's sweep; rate_of(ijk, p, d): the crossing density at lattice point ijk (at p).
    // out: the direction's counts per lattice point, x fastest.
    template <typename D, typename Rate>
    void build_direction_from(int k, const D& source, const Rate& rate_of, T* out) {
        const V3 d = v_.direction(k);
        const glm::ivec3 n = v_.points_;
        // A: the axis d travels along fastest; B, C the plane's axes.
        const V3 ad = glm::abs(d);
        const int A = ad.x >= ad.y ? (ad.x >= ad.z ? 0 : 2) : (ad.y >= ad.z ? 1 : 2);
        const int B = (A + 1) % 3, C = (A + 2) % 3;
        const int step = d[A] > T(0) ? 1 : -1;       // from a plane to the next one along d
        const int exit = step > 0 ? n[A] - 1 : 0;    // the plane rays along d leave by
        const T t_next = spacing_[A] / ad[A];        // the distance from one plane to the next
        auto at = [&](int a_index, int b_index, int c_index) -> T& {
            int ijk[3];
            ijk[A] = a_index, ijk[B] = b_index, ijk[C] = c_index;
            return out[std::size_t(ijk[0]) + std::size_t(n.x) * (std::size_t(ijk[1]) + std::size_t(n.y) * std::size_t(ijk[2]))];
        };
        auto lattice_index = [&](int a_index, int b_index, int c_index) {
            glm::ivec3 ijk;
            ijk[A] = a_index, ijk[B] = b_index, ijk[C] = c_index;
            return ijk;
        };
        auto point = [&](int a_index, int b_index, int c_index) {
            V3 p;
            p[A] = v_.lo_[A] + T(a_index) * spacing_[A];
            p[B] = v_.lo_[B] + T(b_index) * spacing_[B];
            p[C] = v_.lo_[C] + T(c_index) * spacing_[C];
            return p;
        };
        // A source with a crossing density (the shipped grid) is read once per point: the
        // segment to the next plane by the trapezoid rule between the density at p and at q
        // (bilinear on that plane's densities, kept from the previous plane). Any other
        // source answers one short fibers_crossed per point.
        constexpr bool kRate = detail::has_crossing_density<D, T>::value;
        std::vector<T> rate_next, rate_here;
        if (kRate) {
            rate_next.resize(std::size_t(n[B]) * std::size_t(n[C]));
            rate_here.resize(rate_next.size());
        }
        auto rate_at = [&](std::vector<T>& plane, int b_index, int c_index) -> T& {
            return plane[std::size_t(b_index) + std::size_t(n[B]) * std::size_t(c_index)];
        };
        for (int b = 0; b < n[B]; ++b)
            for (int c = 0; c < n[C]; ++c) {
                at(exit, b, c) = T(0);
                if (kRate) rate_at(rate_next, b, c) = rate_of(lattice_index(exit, b, c), point(exit, b, c), d);
            }
        const T tol = T(1e-4);
        for (int a = exit - step; a >= 0 && a < n[A]; a -= step) {
            for (int b = 0; b < n[B]; ++b) {
                for (int c = 0; c < n[C]; ++c) {
                    const V3 p = point(a, b, c);
                    const T rho_p = kRate ? rate_of(lattice_index(a, b, c), p, d) : T(0);
                    if (kRate) rate_at(rate_here, b, c) = rho_p;
                    // Where the segment to the next plane lands, in lattice units of that plane.
                    const T gb = T(b) + t_next * d[B] * v_.inv_spacing_[B];
                    const T gc = T(c) + t_next * d[C] * v_.inv_spacing_[C];
                    T value;
                    if (gb >= -tol && gb <= T(n[B] - 1) + tol && gc >= -tol && gc <= T(n[C] - 1) + tol) {
                        const T rest = bilinear(at, a + step, gb, gc, n[B], n[C]);
                        if (kRate) {
                            auto next = [&](int, int bb, int cc) -> T& { return rate_at(rate_next, bb, cc); };
                            const T rho_q = bilinear(next, 0, gb, gc, n[B], n[C]);
                            value = sanitise(T(0.5) * (rho_p + rho_q) * t_next) + rest;
                        } else {
                            value = segment(source, p, d, t_next) + rest;
                        }
                    } else {
                        const detail::Span<T> s = detail::clip_to_box(v_.lo_, v_.hi_, p, d, t_next);
                        value = s.t1 > T(0) ? segment(source, p, d, s.t1) : T(0);
                    }
                    at(a, b, c) = value;
                }
            }
            if (kRate) rate_next.swap(rate_here);
        }
    }

  public:
    DirectionalCountFieldView<T> view() const { return v_.with_counts(counts_.data()); }
    // The same queries over a copy of counts() elsewhere (e.g. device memory).
    DirectionalCountFieldView<T> view(const T* counts) const { return v_.with_counts(counts); }

    T fibers_to_exit(const V3& origin, const V3& direction) const { return view().fibers_to_exit(origin, direction); }
    T fibers_crossed(const V3& origin, const V3& direction, T max_distance) const {
        return view().fibers_crossed(origin, direction, max_distance);
    }

    int direction_count() const { return v_.direction_count(); }
    V3 direction(int k) const { return v_.direction(k); }
    int octahedral_side() const { return v_.side_; }
    const glm::ivec3& points() const { return v_.points_; }
    const V3& box_min() const { return v_.lo_; }
    const V3& box_max() const { return v_.hi_; }
    const std::vector<T>& counts() const { return counts_; }
    std::size_t bytes() const { return counts_.size() * sizeof(T); }

  private:
    static T sanitise(T v) { return v > T(0) ? (v < kMaxSegmentCount ? v : kMaxSegmentCount) : T(0); }  // NaN → 0
    template <typename D> static T segment(const D& source, const V3& p, const V3& d, T t) {
        return sanitise(T(source.fibers_crossed(p, d, t)));
    }
    template <typename D> static T rate(const D& source, const V3& p, const V3& d) {
        if constexpr (detail::has_crossing_density<D, T>::value) return sanitise(T(source.crossing_density(p, d)));
        else return T(0);
    }
    template <typename At>
    static T bilinear(At& at, int a, T gb, T gc, int nb, int nc) {
        const T ub = clamp(gb, T(0), T(nb - 1)), uc = clamp(gc, T(0), T(nc - 1));
        int b0 = int(ub), c0 = int(uc);
        if (b0 > nb - 2) b0 = nb - 2;
        if (c0 > nc - 2) c0 = nc - 2;
        const T fb = ub - T(b0), fc = uc - T(c0);
        const T v0 = at(a, b0, c0) + fb * (at(a, b0 + 1, c0) - at(a, b0, c0));
        const T v1 = at(a, b0, c0 + 1) + fb * (at(a, b0 + 1, c0 + 1) - at(a, b0, c0 + 1));
        return v0 + fc * (v1 - v0);
    }
    static std::string num(T v) {
        std::ostringstream s;
        s << double(v);
        return s.str();
    }

    DirectionalCountFieldView<T> v_;
    V3 spacing_{T(1)};
    std::vector<T> counts_;
};

}  // namespace hairscatter
