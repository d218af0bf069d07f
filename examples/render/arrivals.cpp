// render — the light arriving at hair points, by the dual estimator and by the path tracer,
// direction by direction (render::arrival_profile): where the two-stream estimator's
// arrivals differ from the truth, binned by how much hair lies along the arrival direction.
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "camera.hpp"
#include "integrators/integrator.hpp"
#include "render.hpp"

namespace render {

std::vector<ArrivalRecord> arrival_profile(const Scene& scene, const ShadingSetup& shading, const RenderOptions& o,
                                           int points, int dual_samples, int path_samples) {
    if (shading.models().fur() || !shading.options().two_stream)
        throw std::invalid_argument("arrival_profile: the two-stream estimator over Chiang's fiber only");
    const CameraRays cam(scene.description().camera, o.width, o.height);
    const RenderContext context(scene, shading, o);
    const std::unique_ptr<PixelIntegrator> dual = make_dual_integrator(context);
    const std::unique_ptr<PixelIntegrator> path = make_path_integrator(context);
    std::vector<ArrivalRecord> out(static_cast<std::size_t>(points));
    tbb::parallel_for(tbb::blocked_range<int>(0, points), [&](const tbb::blocked_range<int>& r) {
        for (int i = r.begin(); i < r.end(); ++i) {
            Pcg32 gen = pixel_rng(o.seed, i, 0x51);
            Sampler rng{gen};
            ArrivalRecord& rec = out[std::size_t(i)];
            for (int tries = 0; tries < 1000; ++tries) {
                const glm::vec3 d = cam.direction(rng.u() * float(o.width), rng.u() * float(o.height));
                const Hit hit = scene.intersect(cam.eye(), d, kInf);
                if (hit.kind != Hit::kHair) continue;
                const ShadingPoint sp(hit, -d);
                const hairscatter::HairSample<float> s =
                    hairscatter::ChiangFiber<float>(shading.models().chiang(sp.strand), sp.h()).at(sp.wo()).sample(rng.u4());
                if (!(s.pdf > 0)) continue;
                const glm::vec3 a = sp.to_world(s.wi);
                rec.weight = (s.weight.x + s.weight.y + s.weight.z) / 3;
                rec.cos_view = glm::dot(a, d);
                if (const AreaLight* light = context.lights.area)
                    rec.cos_light = glm::dot(a, glm::normalize(light->corner + 0.5f * (light->edge_u + light->edge_v) - hit.p));
                rec.count = float(scene.count_hair(hit.p, a, kInf, hit.strand));
                rec.behind = float(scene.count_hair(hit.p, -a, kInf, hit.strand));
                glm::vec3 Ld(0), Lp(0);
                for (int k = 0; k < dual_samples; ++k) Ld += dual->arrival(hit, -d, a, rng);
                for (int k = 0; k < path_samples; ++k) Lp += path->arrival(hit, -d, a, rng);
                Ld /= float(dual_samples), Lp /= float(path_samples);
                rec.dual = (Ld.x + Ld.y + Ld.z) / 3;
                rec.path = (Lp.x + Lp.y + Lp.z) / 3;
                break;
            }
        }
    });
    return out;
}

}  // namespace render
