// A GPU renderer's shading with materials built where the hit is (docs/integration.md, GPU).
//
// The host checks the parameter bounds once (FiberParamBounds::checked), builds the groom's
// dual-scattering tables and density grid, and copies the per-strand texels, the tables'
// arrays and the grid's cells to the device. Per hit, the kernel reads its strand's texel
// (melanin concentrations and a roughness, as a textured HairMaterial would), clamps the
// parameters into the bounds, builds the material with ChiangMaterial::unchecked, and
// shades: single scattering, the dual BCSDF with the grid's light state, and a sample that
// continues the path with its weight. The host shades the same hits with the checked
// constructor, and the program fails unless both agree.
//
// scripts/cuda-check.sh compiles it (nvcc -c, no GPU needed) and, where a GPU is present,
// links and runs it. Without a device the program prints so and exits 0.
#include <hairscatter/dual.hpp>

#include <cuda_runtime.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace {

namespace hs = hairscatter;
using vec3 = glm::vec3;
using vec4 = glm::vec4;

// What the renderer's textures give per strand.
struct StrandTexel {
    float eumelanin, pheomelanin;  // concentrations (pbrt-v4's and Mitsuba 3's)
    float beta_m;                  // longitudinal roughness
};

// Everything the kernel reads, passed by value: device pointers and trivially copyable views.
struct Scene {
    hs::FiberParamBounds<float> bounds;  // checked once on the host
    hs::FiberParams<float> base;         // η, βn, α of the groom; σa and βm come per strand
    const StrandTexel* texels;           // [strand]
    hs::DualTablesView<float> tables;    // the groom's dual tables
    hs::DensityGridView<float> grid;     // the groom's density grid
};

// A hit as the renderer's curve intersector reports it.
struct Hit {
    vec3 x, tangent, wo_world, across;  // across: the direction in which v grows
    float v;                            // in [0, 1] across the curve
    int strand;
};

struct Shaded {
    vec3 single, dual, weight;  // f of the fiber and of the dual BCSDF toward wl; the path's weight
    float pdf;
};

// The per-hit parameters: the texel's values on the groom's base, clamped into the bounds.
HAIRSCATTER_HD hs::FiberParams<float> hit_params(const Scene& s, int strand) {
    const StrandTexel t = s.texels[strand];
    hs::FiberParams<float> p = s.base;
    p.sigma_a = hs::sigma_a_from_concentrations(t.eumelanin, t.pheomelanin);
    p.beta_m = t.beta_m;
    return s.bounds.clamp(p);
}

// Shades one hit with a given material (the device passes the unchecked one, the host the
// checked one): the fiber at h, its value toward wl, the dual BCSDF's with the grid's light
// state, and a sample that continues the path.
HAIRSCATTER_HD Shaded shade(const Scene& s, const hs::ChiangMaterial<float>& material, const Hit& hit, const vec3& wl,
                            const vec4& u) {
    const auto fh = hs::FiberHit<float>::from_v(hit.tangent, hit.wo_world, hit.v, hit.across);
    const hs::ChiangFiber<float> fiber(material, fh.h);
    const auto at = hs::DualScatteringBcsdf<hs::ChiangFiber<float>>(fiber, s.tables).at(fh.wo);
    const vec3 wl_local = fh.frame.to_local(wl);
    Shaded r;
    r.single = fiber.eval(fh.wo, wl_local);
    r.dual = at.eval(wl_local, hs::dual_light(s.grid, hit.x, wl, 0.0f));
    const hs::DualSample<float> d =
        at.sample_with(u, [&](const vec3& wi) { return hs::dual_light(s.grid, hit.x, fh.frame.to_world(wi), 0.0f); });
    r.weight = d.weight;
    r.pdf = d.pdf;
    return r;
}

__global__ void shade_hits(Scene s, const Hit* hits, const vec3* wl, const vec4* u, Shaded* out, int n) {
    const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
    if (i >= n) return;
    // The material where the hit is: no validation on the device, the bounds were checked.
    const auto material = hs::ChiangMaterial<float>::unchecked(hit_params(s, hits[i].strand));
    out[i] = shade(s, material, hits[i], wl[i], u[i]);
}

// Device memory for a vector's contents (nullptr on failure; the caller checks).
template <typename E> E* to_device(const std::vector<E>& v) {
    E* d = nullptr;
    if (cudaMalloc(&d, v.size() * sizeof(E)) != cudaSuccess) return nullptr;
    if (cudaMemcpy(d, v.data(), v.size() * sizeof(E), cudaMemcpyHostToDevice) != cudaSuccess) return nullptr;
    return d;
}

bool close(const vec3& a, const vec3& b) {
    for (int c = 0; c < 3; ++c)
        if (!(std::fabs(a[c] - b[c]) <= 1e-3f * std::fabs(b[c]) + 1e-6f)) return false;
    return true;
}

}  // namespace

int main() {
    int devices = 0;
    if (cudaGetDeviceCount(&devices) != cudaSuccess || devices == 0) {
        std::printf("per_hit_shading: no CUDA device, nothing run\n");
        return 0;
    }

    // --- Host, once: the bounds, the groom's strands, tables and grid. ---
    hs::FiberParams<float> lo, hi;  // η, βn, α fixed at pbrt-v4's defaults
    lo.beta_m = 0.1f;
    hi.beta_m = 0.6f;
    lo.sigma_a = hs::sigma_a_from_concentrations(0.0f, 0.0f);
    hi.sigma_a = hs::sigma_a_from_concentrations(8.0f, 2.0f);
    Scene scene{};
    scene.bounds = hs::FiberParamBounds<float>::checked(lo, hi);  // throws naming a bad field
    scene.base = lo;

    const int strands = 64;
    std::vector<StrandTexel> texels(strands);
    std::vector<std::vector<vec3>> curves(strands);
    for (int k = 0; k < strands; ++k) {
        // Melanin and roughness vary per strand; two strands lie outside the bounds on
        // purpose (a texture's stray values), which clamp() repairs.
        texels[k] = {0.1f * float(k % 16), 0.05f * float(k % 5), 0.1f + 0.5f * float(k % 7) / 6.0f};
        if (k == 3) texels[k].beta_m = 2.0f;
        if (k == 5) texels[k].eumelanin = -1.0f;
        const vec3 root(0.02f * float(k % 8), 0.02f * float(k / 8), 0.0f);
        for (int j = 0; j <= 8; ++j) curves[k].push_back(root + vec3(0.01f * float(j), 0.0f, 0.1f * float(j)));
    }
    const hs::DensityGrid<float> grid = hs::DensityGrid<float>::from_strands(curves, 0.02f, 0.004f);
    // One set of tables for the groom, from a representative material (the bounds' middle).
    hs::FiberParams<float> mid = lo;
    mid.beta_m = 0.5f * (lo.beta_m + hi.beta_m);
    mid.sigma_a = 0.5f * (lo.sigma_a + hi.sigma_a);
    const hs::ChiangMaterial<float> representative(mid);
    hs::DualTableOptions<float> opt;
    opt.theta_samples = 32;
    const auto tables = hs::DualScatteringTables<float>::build<hs::ChiangFiber<float>>(representative, opt);

    // The hits and their light directions and sample numbers.
    const int n = 1024;
    std::vector<Hit> hits(n);
    std::vector<vec3> wl(n);
    std::vector<vec4> u(n);
    for (int i = 0; i < n; ++i) {
        const float a = 0.37f * float(i), b = 0.11f * float(i);
        hits[i] = {vec3(0.07f, 0.07f, 0.4f), glm::normalize(vec3(0.1f, 0.0f, 1.0f)),
                   glm::normalize(vec3(std::cos(a), std::sin(a), 0.3f)), vec3(0.0f, 1.0f, 0.0f),
                   (float(i % 97) + 0.5f) / 97.0f, i % strands};
        wl[i] = glm::normalize(vec3(std::cos(b), 0.5f * std::sin(b), std::sin(1.3f * b)));
        u[i] = vec4(std::fmod(0.618034f * float(i), 1.0f), std::fmod(0.414214f * float(i), 1.0f),
                    std::fmod(0.732051f * float(i), 1.0f), std::fmod(0.236068f * float(i), 1.0f));
    }

    // --- Copy to the device: texels, the tables' arrays, the grid's cells, the hits. ---
    Scene dev = scene;
    dev.texels = to_device(texels);
    const auto* entries = to_device(tables.entries());
    const auto* window = to_device(tables.window_data());
    const auto* cdf = to_device(tables.window_cdf_data());
    const auto* cells = to_device(grid.cells());
    const Hit* d_hits = to_device(hits);
    const vec3* d_wl = to_device(wl);
    const vec4* d_u = to_device(u);
    Shaded* d_out = nullptr;
    if (!dev.texels || !entries || !window || !cdf || !cells || !d_hits || !d_wl || !d_u ||
        cudaMalloc(&d_out, n * sizeof(Shaded)) != cudaSuccess) {
        std::fprintf(stderr, "per_hit_shading: device allocation or copy failed\n");
        return 1;
    }
    dev.tables = hs::DualScatteringTables<float>::with_arrays(tables.view(), entries, window, cdf);
    dev.grid = grid.view(cells);

    shade_hits<<<(n + 127) / 128, 128>>>(dev, d_hits, d_wl, d_u, d_out, n);
    std::vector<Shaded> out(n);
    if (cudaGetLastError() != cudaSuccess || cudaDeviceSynchronize() != cudaSuccess ||
        cudaMemcpy(out.data(), d_out, n * sizeof(Shaded), cudaMemcpyDeviceToHost) != cudaSuccess) {
        std::fprintf(stderr, "per_hit_shading: the kernel failed\n");
        return 1;
    }

    // --- The host's answer: the checked constructor on the same clamped parameters. ---
    Scene host = scene;
    host.texels = texels.data();
    host.tables = tables.view();
    host.grid = grid.view();
    int bad = 0, flipped = 0, lit = 0;
    for (int i = 0; i < n; ++i) {
        const hs::ChiangMaterial<float> material(hit_params(host, hits[i].strand));
        const Shaded r = shade(host, material, hits[i], wl[i], u[i]);
        lit += r.single.x > 0.0f && r.dual.x > 0.0f && r.pdf > 0.0f;  // (so that zeros cannot pass)
        // The device's exp, log and sqrt differ from the host's in the last bits (1e-3
        // relative leaves them a wide margin). A sample whose lobe choice sits on a boundary
        // may pick another lobe there: its weight is compared where both drew the same pdf.
        const bool same_pdf = std::fabs(out[i].pdf - r.pdf) <= 1e-3f * r.pdf + 1e-6f;
        flipped += same_pdf ? 0 : 1;
        if (!close(out[i].single, r.single) || !close(out[i].dual, r.dual) || (same_pdf && !close(out[i].weight, r.weight)))
            ++bad;
    }
    std::printf("per_hit_shading: %d hits shaded on the device (%d lit), %d differ from the host, %d samples "
                "drew another lobe\n", n, lit, bad, flipped);
    return bad == 0 && flipped <= n / 100 && lit >= n / 2 ? 0 : 1;
}
