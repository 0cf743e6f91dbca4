// The benchmark scene (scenes/cornell-box-mitsuba.json, the scene of cornell_vs_mitsuba.sh) built
// once per benchmark program, and a pool of incoherent rays like a path tracer's secondary rays:
// from points inside the box in uniformly distributed directions, with the shadow rays from their
// hits to points on the light. Shared by bench_renderer, bench_embree and wavefront_bound, so
// their ns per ray and per path compare directly.
#pragma once
#include <embree3/rtcore.h>

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
      s.origin = offsetRayOrigin(hit.p, hit.ng, ls->wi, hit.pError);
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

// The scene's world triangles as SceneGeometry places them: three vertices each, with the
// front normal and the glTF material name of each triangle.
struct WorldTriangles {
  std::vector<render::Vec3> vertices;
  std::vector<render::Vec3> normals;
  std::vector<std::string> materials;
};
inline WorldTriangles worldTriangles(const CornellBenchScene& cornell) {
  using namespace tex::render;
  WorldTriangles world;
  const SceneGeometry& geometry = cornell.scene->geometry();
  for (size_t i = 0; i < cornell.description.instances.size(); ++i) {
    if (!geometry.hasInstance(int(i))) continue;
    const MeshPrimitive& prim = cornell.description.primitives[size_t(cornell.description.instances[i].primitive)];
    const std::string material =
        prim.material >= 0 ? cornell.description.materials[size_t(prim.material)].name : std::string();
    for (uint32_t t = 0; t < prim.indices.size() / 3; ++t) {
      Vec3 p[3];
      Vec2 uv[3];
      Vec3 ng;
      geometry.triangleWorld(int(i), t, p, uv, ng);
      world.vertices.insert(world.vertices.end(), p, p + 3);
      world.normals.push_back(ng);
      world.materials.push_back(material);
    }
  }
  return world;
}

// An Embree scene of one triangle geometry over `vertices` (three a triangle), robust
// (RTC_SCENE_FLAG_ROBUST, as SceneGeometry) or fast (RTC_SCENE_FLAG_NONE, as Mitsuba 3).
inline RTCScene buildEmbreeScene(RTCDevice device, const std::vector<render::Vec3>& vertices, RTCSceneFlags flags) {
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneFlags(scene, flags);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices.size()));
  auto* idx = static_cast<uint32_t*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), vertices.size() / 3));
  for (size_t k = 0; k < vertices.size(); ++k) {
    v[3 * k] = vertices[k].x;
    v[3 * k + 1] = vertices[k].y;
    v[3 * k + 2] = vertices[k].z;
    idx[k] = uint32_t(k);
  }
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);
  return scene;
}

}  // namespace tex::bench
