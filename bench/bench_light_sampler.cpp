// Light selection cost (renderer/lights/light_sampler.h): one light chosen and its pmf
// re-evaluated (what a path vertex pays: sample at next-event estimation, pmf at the emitter a
// BSDF sample hits), by power (alias table) and by the light BVH, for 1, 16, 1 k and 200 k
// triangle lights scattered over a 20 m cube. Also the BVH's build time. Items are
// sample+pmf pairs; one thread.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <vector>

#include "renderer/lights/light_sampler.h"
#include "renderer/lights/triangle_light.h"
#include "renderer/sampling/pcg.h"

namespace {

using namespace tex;
using namespace tex::render;

constexpr int kPool = 4096;  // contexts and random numbers cycled through

class ConstantEmission final : public EmissionSource {
 public:
  explicit ConstantEmission(float L) : L_(L) {}
  Spectrum radiance(const EmitterPoint&, const Wavelengths&) const override { return Spectrum(); }
  float averageRadiance() const override { return L_; }

 private:
  float L_;
};

struct Lights {
  std::vector<std::unique_ptr<EmissionSource>> emissions;
  std::vector<std::unique_ptr<Light>> owned;
  std::vector<const Light*> pointers;
  std::unique_ptr<LightSampler> sampler;
  std::vector<LightSampleContext> contexts;
  std::vector<float> u;
  double buildSeconds = 0;
};

Vec3 randomUnit(sampling::Pcg32& rng) {
  const float z = 1.0f - 2.0f * rng.nextFloat(), phi = 2.0f * kPi * rng.nextFloat();
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// n small triangles of random orientation and brightness in [-10, 10]^3; shading points in the
// same cube with random normals.
const Lights& lights(int n) {
  static std::vector<std::unique_ptr<Lights>> cache(4);
  const int slot = n == 1 ? 0 : n == 16 ? 1 : n == 1000 ? 2 : 3;
  if (!cache[size_t(slot)]) {
    auto l = std::make_unique<Lights>();
    sampling::Pcg32 rng(uint64_t(n), 1);
    for (int i = 0; i < n; ++i) {
      const Vec3 c = Vec3(rng.nextFloat(), rng.nextFloat(), rng.nextFloat()) * 20.0f - 10.0f;
      TriangleLightDesc d;
      d.p0 = c + randomUnit(rng) * 0.1f;
      d.p1 = c + randomUnit(rng) * 0.1f;
      d.p2 = c + randomUnit(rng) * 0.1f;
      l->emissions.push_back(std::make_unique<ConstantEmission>(0.5f + rng.nextFloat()));
      l->owned.push_back(makeTriangleLight(d, l->emissions.back().get()));
      l->pointers.push_back(l->owned.back().get());
    }
    const auto start = std::chrono::steady_clock::now();
    l->sampler = std::make_unique<LightSampler>(std::span<const Light* const>(l->pointers));
    l->buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (int i = 0; i < kPool; ++i) {
      l->contexts.push_back({Vec3(rng.nextFloat(), rng.nextFloat(), rng.nextFloat()) * 20.0f - 10.0f, randomUnit(rng)});
      l->u.push_back(rng.nextFloat());
    }
    cache[size_t(slot)] = std::move(l);
  }
  return *cache[size_t(slot)];
}

void BM_PowerSampleAndPmf(benchmark::State& state) {
  const Lights& l = lights(int(state.range(0)));
  size_t i = 0;
  for (auto _ : state) {
    const auto pick = l.sampler->samplePower(l.u[i % kPool]);
    float pmf = pick ? l.sampler->pmfPower(pick->first) : 0.0f;
    benchmark::DoNotOptimize(pmf);
    ++i;
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_PowerSampleAndPmf)->Arg(1)->Arg(16)->Arg(1000)->Arg(200000);

void BM_BvhSampleAndPmf(benchmark::State& state) {
  const Lights& l = lights(int(state.range(0)));
  size_t i = 0;
  for (auto _ : state) {
    const LightSampleContext& ctx = l.contexts[i % kPool];
    const auto pick = l.sampler->sample(ctx, l.u[i % kPool]);
    float pmf = pick ? l.sampler->pmf(ctx, pick->first) : 0.0f;
    benchmark::DoNotOptimize(pmf);
    ++i;
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
  state.counters["nodes"] = double(l.sampler->bvh().nodeCount());
  state.counters["depth"] = double(l.sampler->bvh().depth());
  state.counters["build_ms"] = l.buildSeconds * 1e3;
}
BENCHMARK(BM_BvhSampleAndPmf)->Arg(1)->Arg(16)->Arg(1000)->Arg(200000);

}  // namespace

BENCHMARK_MAIN();
