// Shading hot paths of general scenes (glTF models, image-based lighting), one thread: a
// coated BSDF (std.gltf's plastic: Lambertian under a GGX dielectric coat) evaluated and
// sampled, the glossy model's reflection lobe evaluated, image texture lookups (bilinear, sRGB, from an 8-bit image kept as bytes and the
// same image as floats), and an image environment's light samples and radiance lookups
// (a 512x256 and a 4096x2048 map with a small bright sun). Items are evaluations, samples or
// lookups; compare items_per_second between builds (docs/renderer.md, round 10).
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

#include "renderer/bsdf/bsdf.h"
#include "renderer/color/wavelengths.h"
#include "renderer/core/warp.h"
#include "renderer/lights/image_environment.h"
#include "renderer/material/texture_lookup.h"
#include "renderer/sampling/pcg.h"

namespace {

using namespace tex;
using namespace tex::render;

constexpr int kPool = 4096;  // directions and uvs cycled through by each benchmark

std::vector<Vec2> uniformPairs(uint64_t seed) {
  sampling::Pcg32 rng(seed, 1);
  std::vector<Vec2> u(kPool);
  for (Vec2& v : u) v = Vec2(rng.nextFloat(), rng.nextFloat());
  return u;
}

Bsdf coatedPlastic() {
  Bsdf bsdf(Frame(), Vec3(0, 0, 1));
  Lobe base;
  base.kind = LobeKind::Lambertian;
  for (int i = 0; i < 4; ++i) base.weight.v[i] = 0.6f;
  base.underCoat = true;
  bsdf.add(base);
  Lobe coat;
  coat.kind = LobeKind::RoughDielectric;
  coat.roughness = 0.25f;
  for (int i = 0; i < 4; ++i) coat.weight.v[i] = 1.0f, coat.a.v[i] = 1.5f;
  bsdf.setCoat(coat);
  return bsdf;
}

// evalWithPdf of `bsdf` at pairs of uniform hemisphere directions from two pools.
void evalWithPdfLoop(benchmark::State& state, const Bsdf& bsdf, uint64_t seedA, uint64_t seedB) {
  const std::vector<Vec2> a = uniformPairs(seedA), b = uniformPairs(seedB);
  size_t i = 0;
  for (auto _ : state) {
    const Vec3 wo = sampleUniformHemisphere(a[i % kPool]), wi = sampleUniformHemisphere(b[i % kPool]);
    float pdfW = 0.0f;
    benchmark::DoNotOptimize(bsdf.evalWithPdf(wo, wi, TransportMode::Radiance, pdfW));
    benchmark::DoNotOptimize(pdfW);
    ++i;
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
}

void BM_CoatedBsdfEvalWithPdf(benchmark::State& state) { evalWithPdfLoop(state, coatedPlastic(), 1, 2); }
BENCHMARK(BM_CoatedBsdfEvalWithPdf);

void BM_CoatedBsdfSample(benchmark::State& state) {
  const Bsdf bsdf = coatedPlastic();
  const std::vector<Vec2> a = uniformPairs(3), b = uniformPairs(4);
  size_t i = 0;
  for (auto _ : state) {
    const Vec3 wo = sampleUniformHemisphere(a[i % kPool]);
    benchmark::DoNotOptimize(bsdf.sample(wo, b[i % kPool].x, b[(i + 7) % kPool], TransportMode::Radiance));
    ++i;
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_CoatedBsdfSample);

// The glossy model's reflection lobe (glossy(0.7, n), docs/glossy-model.md) evaluated with its
// density at random direction pairs: its disk masses come from the mass table since round 16.
void BM_GlossyReflectionEvalWithPdf(benchmark::State& state) {
  Bsdf bsdf(Frame(), Vec3(0, 0, 1));
  Lobe glossy;
  glossy.kind = LobeKind::GlossyReflection;
  glossy.exponent = float(state.range(0));
  for (int i = 0; i < 4; ++i) glossy.weight.v[i] = 0.7f;
  bsdf.add(glossy);
  evalWithPdfLoop(state, bsdf, 5, 6);
}
BENCHMARK(BM_GlossyReflectionEvalWithPdf)->Arg(10)->Arg(100);

// Arg 0: an 8-bit RGBA image kept as bytes; 1: the same values as floats (16-bit sources).
void BM_TextureLookupSrgbBilinear(benchmark::State& state) {
  constexpr int kSize = 2048;
  SceneDescription scene;
  ImageData image;
  image.width = image.height = kSize;
  image.channels = 4;
  sampling::Pcg32 rng(5, 5);
  image.bytes.resize(size_t(kSize) * kSize * 4);
  for (uint8_t& v : image.bytes) v = uint8_t(rng.nextBits() & 0xFF);
  if (state.range(0) == 1) {
    for (uint8_t v : image.bytes) image.pixels.push_back(float(v) / 255.0f);
    image.bytes.clear();
  }
  scene.images.push_back(std::move(image));
  TextureRef ref;
  ref.image = 0;
  const std::vector<Vec2> uv = uniformPairs(6);
  size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(lookupTexture(scene, ref, uv[i++ % kPool], Vec2(0.0f), true));
  state.SetItemsProcessed(int64_t(state.iterations()));
  state.SetLabel(state.range(0) == 0 ? "bytes" : "floats");
}
BENCHMARK(BM_TextureLookupSrgbBilinear)->Arg(0)->Arg(1);

// A sky: a blue gradient, a darker ground and a sun 2.5 degrees wide (as scenes/sky.tex).
std::unique_ptr<ImageEnvironment> skyEnvironment(int width) {
  RgbImage sky;
  sky.width = width;
  sky.height = width / 2;
  sky.rgb.resize(size_t(sky.width) * size_t(sky.height) * 3);
  for (int y = 0; y < sky.height; ++y)
    for (int x = 0; x < sky.width; ++x) {
      const float u = (float(x) + 0.5f) / float(sky.width), v = (float(y) + 0.5f) / float(sky.height);
      const float up = std::cos(v * kPi);
      Vec3 c = up > 0.0f ? Vec3(0.85f, 0.88f, 0.95f) * (1.0f - up) + Vec3(0.18f, 0.32f, 0.75f) * up : Vec3(0.25f, 0.22f, 0.18f);
      const float du = (u - 0.3f) * 2.0f * kPi * std::sin(v * kPi), dv = (v - 0.3056f) * kPi;
      if (du * du + dv * dv < 0.0005f) c += Vec3(4000.0f, 3800.0f, 3400.0f);
      for (int k = 0; k < 3; ++k) sky.rgb[(size_t(y) * size_t(sky.width) + size_t(x)) * 3 + size_t(k)] = c[k];
    }
  auto env = std::make_unique<ImageEnvironment>(sky, Mat4(1.0f));
  env->preprocess(SceneSphere{Vec3(0.0f), 10.0f});
  return env;
}

void BM_EnvironmentSampleLi(benchmark::State& state) {
  const std::unique_ptr<ImageEnvironment> env = skyEnvironment(int(state.range(0)));
  const Wavelengths lambda = color::sampleWavelengthGroup(0.37f, 4);
  const std::vector<Vec2> u = uniformPairs(8);
  size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(env->sampleLi(Vec3(0.0f), u[i++ % kPool], lambda));
  state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_EnvironmentSampleLi)->Arg(512)->Arg(4096);

// What a path that escapes pays: the radiance and the light-sampling density of its direction.
void BM_EnvironmentLeAndPdf(benchmark::State& state) {
  const std::unique_ptr<ImageEnvironment> env = skyEnvironment(int(state.range(0)));
  const Wavelengths lambda = color::sampleWavelengthGroup(0.37f, 4);
  const std::vector<Vec2> u = uniformPairs(9);
  size_t i = 0;
  for (auto _ : state) {
    Ray ray;
    ray.direction = sampleUniformSphere(u[i++ % kPool]);
    benchmark::DoNotOptimize(env->Le(ray, lambda));
    benchmark::DoNotOptimize(env->pdfLi(Vec3(0.0f), ray.direction, nullptr));
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_EnvironmentLeAndPdf)->Arg(512)->Arg(4096);

}  // namespace

BENCHMARK_MAIN();
