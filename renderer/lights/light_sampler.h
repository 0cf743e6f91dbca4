// Which light next-event estimation samples. Two distributions over the scene's lights:
//  - by power alone (an alias table, O(1)): what emission sampling needs (light tracing and
//    bidirectional methods choose where light starts without a reference point), and the
//    `power` light selection;
//  - by context (the `bvh` selection, the default): lights without bounds (directional and
//    environment lights) are chosen uniformly with a fixed total probability pInfinite =
//    n / (n + 1) (n of them; the tree counts as one, as pbrt-v4's BVHLightSampler), and the
//    bounded ones (triangles, point and spot lights) through the light BVH (light_bvh.h) in
//    proportion to their estimated contribution at the shading point.
// Both report with the chosen index its probability, and pmf() gives exactly that probability
// for a light (multiple importance sampling at emitters hit by BSDF sampling relies on it).
#pragma once
#include <algorithm>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "renderer/lights/alias_table.h"
#include "renderer/lights/light.h"
#include "renderer/lights/light_bvh.h"

namespace tex::render {

enum class LightSelection : uint8_t {
  Bvh,    // by estimated contribution at the shading point (light BVH)
  Power,  // by power alone
};
const char* lightSelectionName(LightSelection selection);
std::optional<LightSelection> parseLightSelection(const std::string& name);

class LightSampler {
 public:
  explicit LightSampler(std::span<const Light* const> lights);

  // By context: a light and its probability; nullopt when none can be chosen (no light with
  // power, or no bounded light can reach ctx and there is no infinite light). u in [0, 1).
  // Inline, as the power choice was, so that the optional pair can stay in registers. u in
  // double, as the tree needs (LightBvh::sample).
  std::optional<std::pair<int, float>> sample(const LightSampleContext& ctx, double u) const {
    // One pair built at the end: pairs copied between branches went through memory.
    int light = -1;
    float pmf = 0.0f;
    bool chosen = false;
    if (u < double(pInfinite_)) {
      const int k = std::min(int(u / double(pInfinite_) * double(infinite_.size())), int(infinite_.size()) - 1);
      light = infinite_[size_t(k)];
      pmf = pEachInfinite_;
      chosen = true;
    } else {
      const double uTree =
          pInfinite_ > 0.0f ? std::min((u - double(pInfinite_)) / (1.0 - double(pInfinite_)), 0x1.fffffffffffffp-1) : u;
      chosen = bvh_.choose(ctx, uTree, light, pmf);
      pmf *= 1.0f - pInfinite_;
    }
    if (!chosen) return std::nullopt;
    return std::make_pair(light, pmf);
  }
  float pmf(const LightSampleContext& ctx, int lightIndex) const {
    if (lightIndex < 0 || lightIndex >= lightCount_) return 0.0f;
    if (isInfinite_[size_t(lightIndex)]) return pEachInfinite_;
    return bvh_.pmf(ctx, lightIndex) * (1.0f - pInfinite_);
  }

  // By power (zero-power lights are never chosen).
  // u in double: see AliasTable::sample.
  std::optional<std::pair<int, float>> samplePower(double u) const { return power_.sample(u); }
  float pmfPower(int lightIndex) const { return power_.pmf(lightIndex); }

  // Either, as the path tracer's setting says.
  std::optional<std::pair<int, float>> sample(LightSelection selection, const LightSampleContext& ctx, double u) const {
    return selection == LightSelection::Power ? samplePower(u) : sample(ctx, u);
  }
  float pmf(LightSelection selection, const LightSampleContext& ctx, int lightIndex) const {
    return selection == LightSelection::Power ? pmfPower(lightIndex) : pmf(ctx, lightIndex);
  }

  int size() const { return lightCount_; }
  const LightBvh& bvh() const { return bvh_; }
  // The probability of choosing among the unbounded lights (0 without any).
  float infiniteProbability() const { return pInfinite_; }

 private:
  int lightCount_ = 0;
  AliasTable power_;
  LightBvh bvh_;
  std::vector<int> infinite_;      // unbounded lights with power, chosen uniformly
  std::vector<uint8_t> isInfinite_;  // per light
  float pInfinite_ = 0;            // total probability of infinite_
  float pEachInfinite_ = 0;        // pInfinite_ / infinite_.size()
};

}  // namespace tex::render
