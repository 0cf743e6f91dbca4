// A lobe's directional albedo (lane 0) by uniform hemisphere sampling: an estimate independent
// of the lobe's own sampling, to check the albedo its samples give.
#pragma once
#include <cmath>

#include "renderer/bsdf/bsdf.h"
#include "renderer/core/warp.h"
#include "renderer/sampling/pcg.h"

namespace tex::test {

struct AlbedoEstimate {
  double mean = 0, standardError = 0;
};

inline AlbedoEstimate uniformHemisphereAlbedo(const render::Lobe& lobe, const render::Vec3& wo, uint64_t seed, int n) {
  using namespace render;
  sampling::Pcg32 rng(seed, 1);
  double sum = 0, sumSquares = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 wi = sampleUniformHemisphere(Vec2(rng.nextFloat(), rng.nextFloat()));
    const double w = lobeEval(lobe, wo, wi, TransportMode::Radiance)[0] * wi.z / kUniformHemispherePdfW;
    sum += w;
    sumSquares += w * w;
  }
  AlbedoEstimate e;
  e.mean = sum / n;
  e.standardError = std::sqrt((sumSquares / n - e.mean * e.mean) / n);
  return e;
}

}  // namespace tex::test
