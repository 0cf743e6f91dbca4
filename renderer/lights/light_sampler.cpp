// LightSampler (light_sampler.h): the power alias table, and the light BVH with the unbounded
// lights beside it.
#include "renderer/lights/light_sampler.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tex::render {

namespace {
// Broken (NaN) or dark lights are never chosen. A power that overflowed (a sun over a scene of
// huge bounds, pi R^2 E) still counts, as the largest float: any positive choice probability
// is unbiased, and the light is no longer left out (a black image).
float usablePower(float p) {
  if (p == std::numeric_limits<float>::infinity()) return std::numeric_limits<float>::max();
  return std::isfinite(p) && p > 0.0f ? p : 0.0f;
}
}  // namespace

const char* lightSelectionName(LightSelection selection) { return selection == LightSelection::Power ? "power" : "bvh"; }

std::optional<LightSelection> parseLightSelection(const std::string& name) {
  if (name == "bvh") return LightSelection::Bvh;
  if (name == "power") return LightSelection::Power;
  return std::nullopt;
}

LightSampler::LightSampler(std::span<const Light* const> lights) : lightCount_(int(lights.size())) {
  std::vector<float> powers(lights.size(), 0.0f);
  std::vector<LightBvh::Entry> bounded;
  isInfinite_.assign(lights.size(), 0);
  for (size_t i = 0; i < lights.size(); ++i) {
    if (!lights[i]) continue;
    powers[i] = usablePower(lights[i]->power());
    if (!(powers[i] > 0.0f)) continue;
    std::optional<LightBounds> b = lights[i]->isInfinite() ? std::nullopt : lights[i]->bounds();
    if (b && b->phi > 0.0f) {
      b->phi = usablePower(b->phi);
      bounded.push_back({int(i), *b});
    } else {
      infinite_.push_back(int(i));
      isInfinite_[i] = 1;
    }
  }
  power_ = AliasTable(powers);
  bvh_ = LightBvh(std::move(bounded), lightCount_);
  const size_t choices = infinite_.size() + (bvh_.empty() ? 0 : 1);
  pInfinite_ = choices > 0 ? float(infinite_.size()) / float(choices) : 0.0f;
  pEachInfinite_ = infinite_.empty() ? 0.0f : pInfinite_ / float(infinite_.size());
}

}  // namespace tex::render
