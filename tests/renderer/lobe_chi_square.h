// Chi-square goodness of fit of one lobe's sampling (lobeSample) against its density
// (lobePdf), radiance transport, over the sphere of directions (chi_square.h).
#pragma once
#include <optional>

#include "renderer/bsdf/bsdf.h"
#include "tests/renderer/chi_square.h"

namespace tex::test {

inline ChiSquareResult chiSquareLobe(const render::Lobe& lobe, const render::Vec3& wo, const DirectionTestOptions& o) {
  using namespace render;
  return chiSquareDirections(
      [&](Vec2 u, float uc) -> std::optional<Vec3> {
        const auto s = lobeSample(lobe, wo, uc, u, TransportMode::Radiance);
        if (!s) return std::nullopt;
        return s->wi;
      },
      [&](const Vec3& wi) { return double(lobePdf(lobe, wo, wi, TransportMode::Radiance)); }, o);
}

}  // namespace tex::test
