// render — how the hair scatters light: the shading setup (the fiber model's material,
// the dual-scattering tables and the hair density grid, built once per render) and the
// shading point (the frame, h and wo of one hit, made once per hit).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include <common/fiber_models.hpp>
#include <glm/glm.hpp>
#include <hairscatter/dual.hpp>
#include <hairscatter/fiber/hit.hpp>

#include "scene.hpp"

namespace render {

using hairscatter_examples::FiberModel;

// How the two-stream estimator counts the fibers along a direction: exactly on the hair
// (Embree: one ray per count, a sample of the count's distribution), from the density grid
// (a march, and a hair ray for whether any fiber is in the way), or from the directional
// count field (hairscatter/dual/count_field.hpp: a lookup, no ray).
enum class DualCounts { kExact, kGrid, kField };
const char* to_string(DualCounts c);

// Where the two-stream estimator reads the light its stacks pass on (docs/theory.md §5.7):
// beyond each stack's last fiber, through the hair that lies there along the source's
// direction (hairscatter::dual_source_gain; the default), or at the shading point with the
// hair ignored (the estimator as first written; brighter wherever hair shields a stack's end).
enum class DualSource { kBeyondExit, kPoint };
const char* to_string(DualSource s);

struct ShadingOptions {
    FiberModel model = FiberModel::kChiang;
    unsigned lobes = hairscatter_examples::LobeBits::kAll;  // Chiang only
    hairscatter::FiberParams<float> fiber;
    // Chiang's lobe controls and per-strand fibers (docs/controls.md). The dual-scattering
    // tables are built from the base fiber (with the controls); each hit uses its strand's.
    hairscatter_examples::FiberExtras<float> fiber_extras;
    hairscatter_examples::SectionShape section;  // --model huang's cross-section
    hairscatter_examples::MedullaShape medulla;  // --model fur's medulla
    bool dual_scattering = true;  // build the dual-scattering tables and the density grid
    // How the dual integrator shades hair: the two-stream estimator at the arrival direction
    // (hairscatter/dual/two_stream.hpp, the default) or the dual-scattering BCSDF with the
    // tables' formulation (improved or Zinke 2008).
    bool two_stream = true;
    // Two-stream: how the fibers along a direction are counted (DualCounts). The grid is
    // built only where something reads it (grid and field counts), the field for field counts.
    DualCounts counts = DualCounts::kField;
    DualSource source = DualSource::kBeyondExit;
    // Two-stream: the stacks' diffusivity from the hair's shape (hs::dual_turn_limit on the
    // field or the grid; exact counts build the grid for it) rather than a slab's 2/π; with
    // grid or field counts, the glow volume (the hair's mean radiance, from this many random
    // rays per grid cell; 0: none), through which hair along a source direction is read as
    // lit hair (docs/theory.md §5.7).
    bool shape_depth = true;
    // Two-stream: stacks inclined to their fibers return only the backscatter that travels
    // back along them (the tables' rho_b, hs::dual_stack_entry; the default); false: every
    // backward event returns, the 1D stack of Zinke et al. 2008. Inclined stacks bring dense
    // white fur from +9…+12 % to within 1 % of the path tracer (docs/dual.md).
    bool inclined_stacks = true;
    // Two-stream: how light crosses a stack where it has spread over its half-circle
    // (hs::DualStackTransport, docs/theory.md §5.7, "Spread light in the stacks").
    hairscatter::DualStackTransport transport = hairscatter::DualStackTransport::kTurned;
    // Two-stream: the kernels widen in θ by the misalignment of the hair around the point
    // (hs::dual_misalignment from the density grid's length tensor; curly hair), or not.
    bool misaligned_kernels = false;
    int glow_points = 4;
    // Two-stream: a path's first vertices traced as the path tracer traces them (next-event
    // estimation and the fiber's own sample to the next hit) before the estimator takes over:
    // 0 (the default) shades the camera's hit with it. More vertices: smaller bias, more
    // variance and cost (docs/dual.md, "Traced vertices").
    int traced_vertices = 0;
    // Field counts: the octahedral map's side (side² directions, docs/dual.md) and the
    // lattice spacing in grid cells.
    int field_side = 12;
    float field_spacing = 1.0f;
    // Dual scattering's formulation and density factors: the tables are built with them
    // (their one owner); the integrator reads them back from the tables.
    hairscatter::DualScatteringSettings<float> dual{};
    float grid_cell = 0.0f;       // density-grid cell size; 0: 1/32 of the hair's largest extent
    // The density grid is refused above this many bytes: it is dense (every cell of the
    // hair's bounding box is stored), so a small cell grows it with the cube of 1/cell.
    std::size_t max_grid_bytes = std::size_t(1) << 30;
};

struct ShadingStats {
    std::size_t table_bytes = 0, grid_bytes = 0, field_bytes = 0;
    glm::ivec3 grid_resolution{0};
    double seconds = 0, table_seconds = 0, grid_seconds = 0, field_seconds = 0;
};

class ShadingSetup {
  public:
    // Builds the material (throws std::invalid_argument naming a bad parameter) and, with
    // dual_scattering and hair in the scene, the tables and the grid (throws
    // std::invalid_argument when the grid would exceed max_grid_bytes).
    ShadingSetup(const Scene& scene, const ShadingOptions& options);
    ~ShadingSetup();
    ShadingSetup(const ShadingSetup&) = delete;
    ShadingSetup& operator=(const ShadingSetup&) = delete;

    const ShadingOptions& options() const { return o_; }
    const hairscatter_examples::FiberModels<float>& models() const { return *models_; }
    // The Chiang material (the dual-scattering integrator's for every model but fur, whose
    // tables and local scattering are the fur fibre's: models().fur()).
    const hairscatter::ChiangMaterial<float>& chiang() const { return models_->chiang(); }
    const hairscatter::DualScatteringTables<float>& tables() const { return tables_; }
    // The density grid, or null when nothing reads it (no dual scattering, or the two-stream
    // estimator with exact counts).
    const hairscatter::DensityGrid<float>* grid() const { return grid_.get(); }
    // The directional count field, or null unless the two-stream estimator reads field counts.
    const hairscatter::DirectionalCountField<float>* field() const { return field_.get(); }
    // Exact counts read the grid only for the stacks' turn limits (shape_depth).
    bool needs_grid() const {
        return o_.dual_scattering && !(o_.two_stream && o_.counts == DualCounts::kExact && !o_.shape_depth);
    }
    bool needs_field() const { return o_.dual_scattering && o_.two_stream && o_.counts == DualCounts::kField; }
    const ShadingStats& stats() const { return stats_; }

  private:
    ShadingOptions o_;
    std::unique_ptr<hairscatter_examples::FiberModels<float>> models_;
    hairscatter::DualScatteringTables<float> tables_;
    std::unique_ptr<hairscatter::DensityGrid<float>> grid_;
    std::unique_ptr<hairscatter::DirectionalCountField<float>> field_;
    ShadingStats stats_;
};

// Throws std::invalid_argument (naming --grid-cell, with the reason and the smallest cell
// that fits) when the dual-scattering density grid over this hair would exceed
// options.max_grid_bytes, and as check_field for field counts; does nothing without
// dual_scattering. Returns the cell size.
float check_grid(const Hair& hair, const ShadingOptions& options);

// The density grid's resolution for a cell size over the hair (one padding cell either
// side, as DensityGrid::from_strands), and the cell the renderer picks for cell = 0.
glm::ivec3 grid_resolution(const Hair& hair, float cell);
// The check check_grid makes for field counts (the field's lattice is
// DirectionalCountField::points_over_grid): std::invalid_argument naming --field-spacing
// (with the spacing that fits) when the field would exceed options.max_grid_bytes, or naming
// --field-side or --field-spacing when outside their ranges.
void check_field(const glm::ivec3& grid_resolution, const ShadingOptions& options);
float automatic_grid_cell(const Hair& hair);

// One shading point on a fiber: the frame, wo in it and h (hairscatter::FiberHit), the
// hit point and its strand. Made once per hit; every model and integrator reads it.
struct ShadingPoint {
    hairscatter::FiberHit<float> fiber;
    glm::vec3 p{0};
    std::uint32_t strand = 0;

    ShadingPoint(const Hit& hit, const glm::vec3& wo_world)
        : fiber(hit.p, hit.axis, hit.tangent, wo_world, hit.radius), p(hit.p), strand(hit.strand) {}
    const glm::vec3& wo() const { return fiber.wo; }
    float h() const { return fiber.h; }
    glm::vec3 to_local(const glm::vec3& w) const { return fiber.frame.to_local(w); }
    glm::vec3 to_world(const glm::vec3& w) const { return glm::normalize(fiber.frame.to_world(w)); }
};

}  // namespace render
