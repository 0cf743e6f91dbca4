// What Embree's ray queries cost on the benchmark scene (scenes/cornell-box-mitsuba.json, its 36
// world triangles in one Embree scene of our own), for each choice the renderer could make:
// robust (RTC_SCENE_FLAG_ROBUST, watertight: what SceneGeometry uses) or fast (Embree's default,
// what Mitsuba 3 uses), single rays or packets of 4, 8 and 16 with every lane busy, closest hits
// and shadow rays. The rays are bench_renderer's incoherent pool (points inside the box, uniform
// directions; shadow rays from their hits to the light), so items are rays and ns/ray compares
// directly with bench_renderer's BM_ClosestHit / BM_ShadowRay (which add our hit geometry).
// docs/renderer.md, "Round 8", quotes these figures.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <vector>

#include "renderer/color/wavelengths.h"
#include "renderer/core/warp.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/sampling/pcg.h"
#include "renderer/scene/load_scene.h"

namespace {

using namespace tex;
using namespace tex::render;

constexpr int kPool = 4096;

[[noreturn]] void fail(const std::string& error) {
  std::fprintf(stderr, "bench_embree: %s\n", error.c_str());
  std::exit(1);
}

struct Scenes {
  RTCDevice device = nullptr;
  RTCScene robust = nullptr, fast = nullptr;
  std::vector<Ray> rays, shadowRays;

  Scenes() {
    std::string error;
    std::optional<SceneDescription> description = loadScene(TEX_SOURCE_DIR "/scenes/cornell-box-mitsuba.json", error);
    if (!description) fail(error);
    RenderSceneOptions options;
    options.width = options.height = 256;
    const std::unique_ptr<RenderScene> scene = RenderScene::build(*description, options, error);
    if (!scene) fail(error);
    const SceneGeometry& geometry = scene->geometry();
    std::vector<Vec3> world;
    for (size_t i = 0; i < description->instances.size(); ++i) {
      if (!geometry.hasInstance(int(i))) continue;
      const MeshPrimitive& prim = description->primitives[size_t(description->instances[i].primitive)];
      for (uint32_t t = 0; t < prim.indices.size() / 3; ++t) {
        Vec3 p[3];
        Vec2 uv[3];
        Vec3 ng;
        geometry.triangleWorld(int(i), t, p, uv, ng);
        world.insert(world.end(), p, p + 3);
      }
    }
    device = rtcNewDevice(nullptr);
    robust = build(world, RTC_SCENE_FLAG_ROBUST);
    fast = build(world, RTC_SCENE_FLAG_NONE);

    // The same pool as bench_renderer's.
    const Bounds3& b = geometry.bounds();
    const Light& light = *scene->lights().front();
    const Wavelengths lambda = color::sampleWavelengthGroup(0.5f, 4);
    const auto draw = [](uint64_t i, int d) { return sampling::randomUniform(11, i, d); };
    for (uint64_t i = 0; rays.size() < size_t(kPool); ++i) {
      Ray r;
      const Vec3 t(0.1f + 0.8f * draw(i, 0), 0.1f + 0.8f * draw(i, 1), 0.1f + 0.8f * draw(i, 2));
      r.origin = b.lower + (b.upper - b.lower) * t;
      r.direction = sampleUniformSphere(Vec2(draw(i, 3), draw(i, 4)));
      SurfaceHit hit;
      if (!geometry.intersect(r, hit)) continue;
      rays.push_back(r);
      const std::optional<LightLiSample> ls = light.sampleLi(hit.p, Vec2(draw(i, 5), draw(i, 6)), lambda);
      if (!ls || !(ls->pdfW > 0.0f)) continue;
      Ray s;
      s.origin = offsetRayOrigin(hit.p, hit.ng, ls->wi);
      s.direction = ls->wi;
      s.tMax = ls->distance * 0.999f;
      shadowRays.push_back(s);
    }
  }
  ~Scenes() {
    rtcReleaseScene(robust);
    rtcReleaseScene(fast);
    rtcReleaseDevice(device);
  }

  RTCScene build(const std::vector<Vec3>& world, RTCSceneFlags flags) const {
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, flags);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), world.size()));
    auto* idx = static_cast<uint32_t*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), world.size() / 3));
    for (size_t k = 0; k < world.size(); ++k) {
      v[3 * k] = world[k].x;
      v[3 * k + 1] = world[k].y;
      v[3 * k + 2] = world[k].z;
      idx[k] = uint32_t(k);
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    return scene;
  }
};

const Scenes& scenes() {
  static const Scenes s;
  return s;
}

// One packet type's fields, lane j from ray r (tfar: the ray's tMax).
template <typename Packet>
void setLane(Packet& p, int j, const Ray& r) {
  p.org_x[j] = r.origin.x;
  p.org_y[j] = r.origin.y;
  p.org_z[j] = r.origin.z;
  p.tnear[j] = 0.0f;
  p.dir_x[j] = r.direction.x;
  p.dir_y[j] = r.direction.y;
  p.dir_z[j] = r.direction.z;
  p.time[j] = 0.0f;
  p.tfar[j] = r.tMax;
  p.mask[j] = ~0u;
  p.id[j] = 0;
  p.flags[j] = 0;
}

void setSingle(RTCRay& p, const Ray& r) {
  p.org_x = r.origin.x;
  p.org_y = r.origin.y;
  p.org_z = r.origin.z;
  p.tnear = 0.0f;
  p.dir_x = r.direction.x;
  p.dir_y = r.direction.y;
  p.dir_z = r.direction.z;
  p.time = 0.0f;
  p.tfar = r.tMax;
  p.mask = ~0u;
  p.id = 0;
  p.flags = 0;
}

template <int W>
struct PacketTypes;
template <>
struct PacketTypes<4> {
  using Hit = RTCRayHit4;
  using Shadow = RTCRay4;
  static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, Hit* h) { rtcIntersect4(v, s, c, h); }
  static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Shadow* r) { rtcOccluded4(v, s, c, r); }
};
template <>
struct PacketTypes<8> {
  using Hit = RTCRayHit8;
  using Shadow = RTCRay8;
  static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, Hit* h) { rtcIntersect8(v, s, c, h); }
  static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Shadow* r) { rtcOccluded8(v, s, c, r); }
};
template <>
struct PacketTypes<16> {
  using Hit = RTCRayHit16;
  using Shadow = RTCRay16;
  static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, Hit* h) { rtcIntersect16(v, s, c, h); }
  static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Shadow* r) { rtcOccluded16(v, s, c, r); }
};

// state.range(0): 1 robust, 0 fast. Width 1 is rtcIntersect1 / rtcOccluded1.
template <int W, bool Shadow>
void BM_Embree(benchmark::State& state) {
  const Scenes& s = scenes();
  const RTCScene scene = state.range(0) ? s.robust : s.fast;
  const std::vector<Ray>& pool = Shadow ? s.shadowRays : s.rays;
  const size_t usable = pool.size() / 16 * 16;
  size_t i = 0;
  for (auto _ : state) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    if constexpr (W == 1) {
      if constexpr (Shadow) {
        RTCRay r;
        setSingle(r, pool[i]);
        rtcOccluded1(scene, &context, &r);
        benchmark::DoNotOptimize(r.tfar);
      } else {
        RTCRayHit rh;
        setSingle(rh.ray, pool[i]);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &context, &rh);
        benchmark::DoNotOptimize(rh.hit.geomID);
      }
    } else {
      alignas(64) int valid[W];
      if constexpr (Shadow) {
        alignas(64) typename PacketTypes<W>::Shadow r;
        for (int j = 0; j < W; ++j) {
          valid[j] = -1;
          setLane(r, j, pool[i + size_t(j)]);
        }
        PacketTypes<W>::occluded(valid, scene, &context, &r);
        benchmark::DoNotOptimize(r.tfar[0]);
      } else {
        alignas(64) typename PacketTypes<W>::Hit rh;
        for (int j = 0; j < W; ++j) {
          valid[j] = -1;
          setLane(rh.ray, j, pool[i + size_t(j)]);
          rh.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
        }
        PacketTypes<W>::intersect(valid, scene, &context, &rh);
        benchmark::DoNotOptimize(rh.hit.geomID[0]);
      }
    }
    i = (i + size_t(W)) % usable;
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * W);
}

#define TEX_EMBREE_BENCH(W, SHADOW) BENCHMARK_TEMPLATE(BM_Embree, W, SHADOW)->ArgName("robust")->Arg(1)->Arg(0)
TEX_EMBREE_BENCH(1, false);
TEX_EMBREE_BENCH(4, false);
TEX_EMBREE_BENCH(8, false);
TEX_EMBREE_BENCH(16, false);
TEX_EMBREE_BENCH(1, true);
TEX_EMBREE_BENCH(4, true);
TEX_EMBREE_BENCH(8, true);
TEX_EMBREE_BENCH(16, true);

}  // namespace

BENCHMARK_MAIN();
