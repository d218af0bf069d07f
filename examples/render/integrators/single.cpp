// render — single scattering: at the camera ray's first hair hit, one light sample
// through the chosen fiber model; hair shadows are opaque (no multiple scattering).
#include "integrator.hpp"

namespace render {

namespace {

template <class MakeFiber> class SingleIntegrator final : public PixelIntegrator {
  public:
    SingleIntegrator(const RenderContext& c, MakeFiber make) : c_(c), make_(make) {}

    glm::vec3 radiance(const glm::vec3& o, const glm::vec3& d, Sampler& rng) const override {
        return first_hit_direct(c_, o, d, rng, [this](const ShadingPoint& sp, Sampler& r) { return hair(sp, r); });
    }

  private:
    glm::vec3 hair(const ShadingPoint& sp, Sampler& rng) const {
        const Lights& lights = c_.lights;
        if (!lights.any()) return glm::vec3(0);
        const float u0 = rng.u(), u1 = rng.u(), u2 = rng.u();
        const Lights::Sample ls = lights.sample(sp.p, u0, u1, u2);
        if (!(ls.pdf > 0)) return glm::vec3(0);
        if (c_.scene.occluded(sp.p, ls.wi, ls.dist * kShadowShorten, sp.strand)) return glm::vec3(0);
        const auto fiber = hairscatter_examples::bind_fiber(make_(sp.h(), sp.strand), sp.wo());
        return fiber.eval(sp.to_local(ls.wi)) * ls.Le / ls.pdf;
    }

    const RenderContext& c_;
    MakeFiber make_;
};

}  // namespace

std::unique_ptr<PixelIntegrator> make_single_integrator(const RenderContext& c) { return make_for_model<SingleIntegrator>(c); }

}  // namespace render
