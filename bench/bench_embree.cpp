// What Embree's ray queries cost on the benchmark scene (scenes/cornell-box-mitsuba.json, its 36
// world triangles in one Embree scene of our own), for each choice the renderer could make:
// robust (RTC_SCENE_FLAG_ROBUST, watertight: what SceneGeometry uses) or fast (Embree's default,
// what Mitsuba 3 uses), single rays or packets of 4, 8 and 16 with every lane busy, closest hits
// and shadow rays. The rays are bench_renderer's incoherent pool (bench/cornell_bench_scene.h:
// points inside the box, uniform directions; shadow rays from their hits to the light), so items
// are rays and ns/ray compares directly with bench_renderer's BM_ClosestHit / BM_ShadowRay
// (which add our hit geometry).
// docs/renderer.md, "Round 8", quotes these figures.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <type_traits>
#include <vector>

#include "bench/cornell_bench_scene.h"

namespace {

using namespace tex;
using namespace tex::render;

// Robust and fast Embree scenes of the benchmark scene's world triangles, and its ray pools.
struct Scenes {
  RTCDevice device = nullptr;
  RTCScene robust = nullptr, fast = nullptr;
  const std::vector<Ray>& rays = bench::cornellBenchScene().rays;
  const std::vector<Ray>& shadowRays = bench::cornellBenchScene().shadowRays;

  Scenes() {
    const std::vector<Vec3> world = bench::worldTriangles(bench::cornellBenchScene()).vertices;
    device = rtcNewDevice(nullptr);
    robust = bench::buildEmbreeScene(device, world, RTC_SCENE_FLAG_ROBUST);
    fast = bench::buildEmbreeScene(device, world, RTC_SCENE_FLAG_NONE);
  }
  ~Scenes() {
    rtcReleaseScene(robust);
    rtcReleaseScene(fast);
    rtcReleaseDevice(device);
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

// Embree's W-wide packet types and queries.
template <int W>
using HitPacket = std::conditional_t<W == 4, RTCRayHit4, std::conditional_t<W == 8, RTCRayHit8, RTCRayHit16>>;
template <int W>
using ShadowPacket = std::conditional_t<W == 4, RTCRay4, std::conditional_t<W == 8, RTCRay8, RTCRay16>>;
template <int W>
void intersectPacket(const int* valid, RTCScene scene, RTCIntersectContext* context, HitPacket<W>* packet) {
  if constexpr (W == 4) rtcIntersect4(valid, scene, context, packet);
  else if constexpr (W == 8) rtcIntersect8(valid, scene, context, packet);
  else rtcIntersect16(valid, scene, context, packet);
}
template <int W>
void occludedPacket(const int* valid, RTCScene scene, RTCIntersectContext* context, ShadowPacket<W>* packet) {
  if constexpr (W == 4) rtcOccluded4(valid, scene, context, packet);
  else if constexpr (W == 8) rtcOccluded8(valid, scene, context, packet);
  else rtcOccluded16(valid, scene, context, packet);
}

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
        alignas(64) ShadowPacket<W> r;
        for (int j = 0; j < W; ++j) {
          valid[j] = -1;
          setLane(r, j, pool[i + size_t(j)]);
        }
        occludedPacket<W>(valid, scene, &context, &r);
        benchmark::DoNotOptimize(r.tfar[0]);
      } else {
        alignas(64) HitPacket<W> rh;
        for (int j = 0; j < W; ++j) {
          valid[j] = -1;
          setLane(rh.ray, j, pool[i + size_t(j)]);
          rh.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
        }
        intersectPacket<W>(valid, scene, &context, &rh);
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
