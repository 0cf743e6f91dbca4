// The path tracer's radiance estimate over a scene's first samples (for analytic checks): the
// mean over samples of the lane-averaged L(lambda) = record value x wavelength pdf, its
// standard error, and the tracer's counters.
#pragma once
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "renderer/color/wavelengths.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/integrators/render_scene.h"

namespace tex::render::test {

struct Estimate {
  double mean = 0, standardError = 0;
  uint64_t nonFinite = 0;
  uint64_t rays = 0;
};

// Mean over samples and wavelengths of the radiance estimate L(lambda) (= record value x pdf),
// with the tracer's settings as given (their wavelength count builds the scene).
inline Estimate estimateRadiance(const SceneDescription& scene, const PathTracerSettings& settings, uint64_t samples,
                                 sampling::SamplerKind sampler = sampling::SamplerKind::Sobol) {
  RenderSceneOptions o;
  o.width = o.height = 64;
  o.wavelengths = settings.wavelengths;
  o.useCache = false;
  std::string error;
  std::unique_ptr<RenderScene> rs = RenderScene::build(scene, o, error);
  EXPECT_TRUE(rs) << error;
  if (!rs) return {};
  const PathTracer tracer(*rs, sampling::Sampler(sampler, 3), settings);
  double sum = 0, sum2 = 0;
  for (uint64_t i = 0; i < samples; ++i) {
    const SampleRecord r = tracer.record(i);
    double v = 0;
    for (int j = 0; j < r.wavelengthCount; ++j) v += r.values[j] * color::visibleWavelengthPdf(r.lambdaNm[j]);
    v /= r.wavelengthCount;
    sum += v;
    sum2 += v * v;
  }
  Estimate e;
  e.mean = sum / double(samples);
  e.standardError = std::sqrt(std::max(0.0, sum2 / double(samples) - e.mean * e.mean) / double(samples));
  e.nonFinite = tracer.counters().nonFiniteSamples;
  e.rays = tracer.counters().rays;
  return e;
}

inline Estimate estimateRadiance(const SceneDescription& scene, int maxDepth, int wavelengths, uint64_t samples,
                                 sampling::SamplerKind sampler = sampling::SamplerKind::Sobol,
                                 int rouletteDepth = PathTracerSettings().rouletteDepth) {
  PathTracerSettings settings;
  settings.maxDepth = maxDepth;
  settings.rouletteDepth = rouletteDepth;
  settings.wavelengths = wavelengths;
  return estimateRadiance(scene, settings, samples, sampler);
}

}  // namespace tex::render::test
