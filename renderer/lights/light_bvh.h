// A bounding volume hierarchy over the lights that have bounds (triangles, point and spot
// lights), for choosing a light in proportion to an estimate of its contribution at a shading
// point instead of its power alone (Conty Estevez and Kulla 2018, "Importance Sampling of Many
// Lights with Adaptive Tree Splitting"; pbrt-v4's BVHLightSampler). Sampling descends from the
// root choosing each child with probability proportional to its importance (light_bounds.h)
// at the context; the light's probability is the product of those choices. pmf() retraces the
// same choices from the light's recorded path (a bit per level), so it is exactly the
// probability sample() has of returning that light: path tracing's MIS at emitters hit by BSDF
// sampling depends on it.
#pragma once
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "renderer/lights/light_bounds.h"

namespace tex::render {

class LightBvh {
 public:
  struct Entry {
    int light = -1;  // index in the scene's light list
    LightBounds bounds;
  };
  LightBvh() = default;
  // Entries of phi <= 0 are left out (never chosen). lightCount: the size of the scene's list.
  LightBvh(std::vector<Entry> entries, int lightCount);

  bool empty() const { return nodes_.empty(); }
  // A light chosen at ctx with u in [0, 1), and its probability among the tree's lights;
  // nullopt when no light in the tree can reach ctx (every importance 0).
  std::optional<std::pair<int, float>> sample(const LightSampleContext& ctx, float u) const;
  // The probability sample(ctx, .) returns `light` (bit for bit the one it reports); 0 for
  // lights not in the tree.
  float pmf(const LightSampleContext& ctx, int light) const;
  int nodeCount() const { return int(nodes_.size()); }
  int depth() const { return depth_; }

  // 48 bytes: the bounds with the cone's cosines quantised to 16 bits, rounded toward wider.
  struct Node {
    Vec3 lower{0.0f}, upper{0.0f};
    Vec3 w{0.0f, 0.0f, 1.0f};
    float phi = 0;
    uint16_t qCosThetaO = 0, qCosThetaE = 0;
    uint32_t childOrLight : 30;  // interior: the second child's index (the first is next); leaf: the light
    uint32_t leaf : 1;
    uint32_t twoSided : 1;
  };

 private:
  int build(std::vector<Entry>& entries, size_t begin, size_t end, uint64_t trail, int depth);
  // Importance of the node at ctx (lightImportance on its dequantised bounds).
  float importance(const LightSampleContext& ctx, const Node& node) const;
  // The importances of an interior node's two children.
  void childImportances(const LightSampleContext& ctx, int node, float c[2]) const;

  std::vector<Node> nodes_;
  std::vector<uint64_t> trail_;  // per light: bit k = which child it lies in at depth k
  std::vector<uint8_t> inTree_;  // per light
  int depth_ = 0;
};

}  // namespace tex::render
