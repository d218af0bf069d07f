// render — building the shading setup.
#include "shading.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace render {
namespace hs = hairscatter;

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

void bounds(const Hair& hair, glm::vec3& lo, glm::vec3& hi) {
    lo = glm::vec3(std::numeric_limits<float>::max());
    hi = glm::vec3(std::numeric_limits<float>::lowest());
    for (const auto& s : hair.strands)
        for (const glm::vec3& p : s)
            if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) lo = glm::min(lo, p), hi = glm::max(hi, p);
}

double cells_of(const glm::ivec3& r) { return double(r.x) * double(r.y) * double(r.z); }
}  // namespace

float automatic_grid_cell(const Hair& hair) {
    glm::vec3 lo, hi;
    bounds(hair, lo, hi);
    const glm::vec3 e = hi - lo;
    const float cell = std::max({e.x, e.y, e.z}) / 32.0f;  // 32 cells across the hair's largest side
    return std::max(cell, 4.0f * hair.radius);
}

glm::ivec3 grid_resolution(const Hair& hair, float cell) {
    glm::vec3 lo, hi;
    bounds(hair, lo, hi);
    glm::ivec3 r;
    for (int a = 0; a < 3; ++a) {
        const double n = std::ceil(double(hi[a] - lo[a]) / double(cell)) + 2;
        r[a] = n < 1e9 ? int(n) : 1000000000;
    }
    return r;
}

float check_grid(const Hair& hair, const ShadingOptions& o) {
    if (o.traced_vertices < 0 || o.traced_vertices > 8)
        throw std::invalid_argument("--dual-vertices: " + std::to_string(o.traced_vertices) + " is outside [0, 8]");
    if (!o.dual_scattering || (o.two_stream && o.counts == DualCounts::kExact && !o.shape_depth) ||
        hair.segment_count() == 0)
        return 0.0f;
    if (!(o.grid_cell >= 0) || !std::isfinite(o.grid_cell))
        throw std::invalid_argument("--grid-cell: " + std::to_string(o.grid_cell) + " is not a size >= 0");
    // A cell above the automatic one's largest (the hair's extent, or 4 radii) holds all
    // the hair; far above, the grid's box overflowed float.
    glm::vec3 lo, hi;
    bounds(hair, lo, hi);
    const float largest = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 4.0f * hair.radius});
    if (!(o.grid_cell <= largest)) {
        char msg[256];
        std::snprintf(msg, sizeof(msg), "--grid-cell: %g is larger than the hair (%g; 0: automatic)",
                      double(o.grid_cell), double(largest));
        throw std::invalid_argument(msg);
    }
    const float cell = o.grid_cell > 0 ? o.grid_cell : automatic_grid_cell(hair);
    const glm::ivec3 res = grid_resolution(hair, cell);
    const double bytes = cells_of(res) * double(sizeof(hs::HairLengthTensor<float>));
    if (bytes > double(o.max_grid_bytes)) {
        // The smallest cell that fits: the resolution falls as 1/cell per axis.
        float ok = cell;
        for (int k = 0; k < 2000 && cells_of(grid_resolution(hair, ok)) * double(sizeof(hs::HairLengthTensor<float>)) >
                                        double(o.max_grid_bytes);
             ++k)
            ok *= 1.05f;
        char msg[512];
        std::snprintf(msg, sizeof(msg),
                      "--grid-cell %g: the density grid would be %d x %d x %d cells (%.1f GiB), above the "
                      "%.1f GiB limit (the grid stores every cell of the hair's bounding box, so it grows with "
                      "the cube of 1/cell); use --grid-cell %.3g or larger, or 0 for %.3g",
                      double(cell), res.x, res.y, res.z, bytes / 1073741824.0,
                      double(o.max_grid_bytes) / 1073741824.0, double(ok),
                      double(automatic_grid_cell(hair)));
        throw std::invalid_argument(msg);
    }
    if (o.two_stream && o.counts == DualCounts::kField) check_field(res, o);
    return cell;
}

void check_field(const glm::ivec3& grid_res, const ShadingOptions& o) {
    if (!(o.field_spacing >= 1.0f && o.field_spacing <= 64.0f))
        throw std::invalid_argument("--field-spacing: " + std::to_string(o.field_spacing) + " is outside [1, 64]");
    if (o.field_side < 2 || o.field_side > 64)
        throw std::invalid_argument("--field-side: " + std::to_string(o.field_side) + " is outside [2, 64]");
    const double per_point = double(o.field_side) * double(o.field_side) * double(sizeof(float));
    const glm::ivec3 p = hs::DirectionalCountField<float>::points_over_grid(grid_res, o.field_spacing);
    const double bytes = cells_of(p) * per_point;
    if (bytes <= double(o.max_grid_bytes)) return;
    float ok = o.field_spacing;
    while (ok < 64.0f &&
           cells_of(hs::DirectionalCountField<float>::points_over_grid(grid_res, ok)) * per_point > double(o.max_grid_bytes))
        ok *= 1.1f;
    char msg[512];
    std::snprintf(msg, sizeof(msg),
                  "--field-spacing %g: the count field would be %d x %d x %d points x %d directions (%.1f GiB), above "
                  "the %.1f GiB limit; use --field-spacing %.3g or larger, a smaller --field-side, or a larger "
                  "--grid-cell",
                  double(o.field_spacing), p.x, p.y, p.z, o.field_side * o.field_side, bytes / 1073741824.0,
                  double(o.max_grid_bytes) / 1073741824.0, double(std::min(ok, 64.0f)));
    throw std::invalid_argument(msg);
}

ShadingSetup::ShadingSetup(const Scene& scene, const ShadingOptions& options) : o_(options) {
    const auto t0 = Clock::now();
    models_ = std::make_unique<hairscatter_examples::FiberModels<float>>(o_.model, o_.lobes, o_.fiber,
                                                                          o_.fiber_extras, o_.section, o_.medulla);
    const Hair& hair = scene.description().hair;
    if (o_.dual_scattering && scene.has_hair()) {
        const auto t_tables = Clock::now();
        hs::DualTableOptions<float> topt;
        topt.settings = o_.dual;
        // Fur scatters between fibres as fur (its medulla's lobe in the tables); every other
        // model's dual scattering is Chiang's fiber's.
        if (const hs::FurMaterial<float>* fur = models_->fur())
            tables_ = hs::DualScatteringTables<float>::build<hs::FurFiber<float>>(*fur, topt);
        else
            tables_ = hs::DualScatteringTables<float>::build<hs::ChiangFiber<float>>(chiang(), topt);
        stats_.table_seconds = seconds_since(t_tables);
        stats_.table_bytes = tables_.entries().size() * sizeof(hs::DualScatteringEntry<float>) +
                             tables_.window_data().size() * sizeof(glm::vec3) + tables_.window_cdf_data().size() * sizeof(float);

    }
    if (needs_grid() && scene.has_hair()) {
        const float cell = check_grid(hair, o_);
        const auto t_grid = Clock::now();
        grid_ = std::make_unique<hs::DensityGrid<float>>(
            hs::DensityGrid<float>::from_strands(hair.strands, cell, hair.radius));
        stats_.grid_seconds = seconds_since(t_grid);
        stats_.grid_bytes = grid_->cells().size() * sizeof(hs::HairLengthTensor<float>);
        stats_.grid_resolution = grid_->resolution();
    }
    if (needs_field() && grid_) {
        // The field's directions are independent: built in parallel, each from the grid.
        const auto t_field = Clock::now();
        field_ = std::make_unique<hs::DirectionalCountField<float>>(
            grid_->box_min(), grid_->box_max(),
            hs::DirectionalCountField<float>::points_over_grid(grid_->resolution(), o_.field_spacing), o_.field_side);
        // The grid's tensors at the lattice points are read once, for every direction; blocks
        // of kBuildBlock directions keep the threads off each other's cache lines.
        const auto tensors = field_->lattice_tensors(grid_->view());
        constexpr int kBlock = hs::DirectionalCountField<float>::kBuildBlock;
        tbb::parallel_for(0, (field_->direction_count() + kBlock - 1) / kBlock,
                          [&](int b) { field_->build_directions(b * kBlock, (b + 1) * kBlock, tensors); });
        stats_.field_seconds = seconds_since(t_field);
        stats_.field_bytes = field_->bytes();
    }
    stats_.seconds = seconds_since(t0);
}

ShadingSetup::~ShadingSetup() = default;

const char* to_string(DualCounts c) {
    switch (c) {
        case DualCounts::kExact: return "exact";
        case DualCounts::kGrid: return "grid";
        case DualCounts::kField: return "field";
    }
    return "?";
}

const char* to_string(DualSource s) { return s == DualSource::kPoint ? "point" : "beyond-exit"; }

}  // namespace render
