// The benchmark scene (scenes/cornell-box-mitsuba.json, the scene of cornell_vs_mitsuba.sh) built
// once per benchmark program, and a pool of incoherent rays like a path tracer's secondary rays:
// from points inside the box in uniformly distributed directions, with the shadow rays from their
// hits to points on the light. Shared by bench_renderer and bench_embree, so their ns per ray
// compare directly.
#pragma once
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renderer/color/wavelengths.h"
#include "renderer/core/warp.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/sampling/pcg.h"
#include "renderer/scene/load_scene.h"

namespace tex::bench {

inline constexpr int kRayPool = 4096;

struct CornellBenchScene {
  render::SceneDescription description;
  std::unique_ptr<render::RenderScene> scene;
  std::vector<render::Ray> rays;        // kRayPool rays that hit
  std::vector<render::Ray> shadowRays;  // from those hits to the light (where it is visible from the front)
  std::vector<render::Vec3> hitPoints;  // the hits of `rays`

  CornellBenchScene() {
    using namespace tex::render;
    std::string error;
    std::optional<SceneDescription> loaded = loadScene(TEX_SOURCE_DIR "/scenes/cornell-box-mitsuba.json", error);
    if (!loaded) fail(error);
    description = std::move(*loaded);
    RenderSceneOptions options;
    options.width = options.height = 256;
    scene = RenderScene::build(description, options, error);
    if (!scene) fail(error);
    const Bounds3& b = scene->geometry().bounds();
    const Light& light = *scene->lights().front();
    const Wavelengths lambda = color::sampleWavelengthGroup(0.5f, 4);
    const auto draw = [](uint64_t i, int d) { return sampling::randomUniform(11, i, d); };
    for (uint64_t i = 0; rays.size() < size_t(kRayPool); ++i) {
      Ray r;
      const Vec3 t(0.1f + 0.8f * draw(i, 0), 0.1f + 0.8f * draw(i, 1), 0.1f + 0.8f * draw(i, 2));
      r.origin = b.lower + (b.upper - b.lower) * t;
      r.direction = sampleUniformSphere(Vec2(draw(i, 3), draw(i, 4)));
      SurfaceHit hit;
      if (!scene->geometry().intersect(r, hit)) continue;
      rays.push_back(r);
      hitPoints.push_back(hit.p);
      const std::optional<LightLiSample> ls = light.sampleLi(hit.p, Vec2(draw(i, 5), draw(i, 6)), lambda);
      if (!ls || !(ls->pdfW > 0.0f)) continue;
      Ray s;
      s.origin = offsetRayOrigin(hit.p, hit.ng, ls->wi);
      s.direction = ls->wi;
      s.tMax = ls->distance * 0.999f;
      shadowRays.push_back(s);
    }
  }
  [[noreturn]] static void fail(const std::string& error) {
    std::fprintf(stderr, "benchmark scene: %s\n", error.c_str());
    std::exit(1);
  }
};

// Built on first use.
inline const CornellBenchScene& cornellBenchScene() {
  static const CornellBenchScene s;
  return s;
}

}  // namespace tex::bench
