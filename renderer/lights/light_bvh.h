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

#include "renderer/lights/alias_table.h"
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
  // nullopt when no light in the tree can reach ctx (every importance 0). u in double: each
  // level rescales it, so a subtree of probability p gets p times u's resolution; from a 24-bit
  // float a far cluster of 16384 dim lights (p about 2e-6) could choose only 17 of them
  // (LightBvhSampler.LightsOfTinyTotalProbabilityAreAllReachable).
  std::optional<std::pair<int, float>> sample(const LightSampleContext& ctx, double u) const {
    int light;
    float pmf;
    if (!choose(ctx, u, light, pmf)) return std::nullopt;
    return std::make_pair(light, pmf);
  }
  // sample() with plain results (false: no light), as AliasTable::choose.
  bool choose(const LightSampleContext& ctx, double u, int& light, float& pmf) const {
    if (!flat_.empty()) return flat_.choose(u, light, pmf);
    return descend(ctx, u, light, pmf);
  }
  // The probability sample(ctx, .) returns `light` (bit for bit the one it reports); 0 for
  // lights not in the tree.
  float pmf(const LightSampleContext& ctx, int light) const {
    if (light < 0 || size_t(light) >= inTree_.size() || !inTree_[size_t(light)]) return 0.0f;
    if (!flat_.empty()) return flat_.pmf(int(trail_[size_t(light)]));
    return retrace(ctx, light);
  }
  int nodeCount() const { return int(nodes_.size()); }
  int depth() const { return depth_; }
  // Whether the lights are one planar emitter (see kFlatMax), chosen by power without a descent.
  bool flat() const { return !flat_.empty(); }
  // Up to this many lights with one normal in one plane (a quad or a small polygon light split
  // into triangles: the Cornell box's) are chosen by power: the importance would differ between
  // them only by the distance to each, and its cost was 13 % of a Cornell render.
  static constexpr size_t kFlatMax = 8;

  // 48 bytes: what the importance reads, precomputed (the box's bounding sphere, the cone's
  // sine), so that a level of the descent costs two evaluations and little else.
  struct Node {
    Vec3 center{0.0f};
    float radius = 0;
    Vec3 w{0.0f, 0.0f, 1.0f};
    float phi = 0;
    float cosThetaO = 1, sinThetaO = 0, cosThetaE = 0;
    uint32_t childOrLight : 30;  // interior: the second child's index (the first is next); leaf: the light
    uint32_t leaf : 1;
    uint32_t twoSided : 1;
  };

 private:
  static bool onePlane(const std::vector<Entry>& entries);
  int build(std::vector<Entry>& entries, size_t begin, size_t end, uint64_t trail, int depth);
  bool descend(const LightSampleContext& ctx, double u, int& light, float& pmf) const;
  float retrace(const LightSampleContext& ctx, int light) const;

  // The importances of an interior node's two children at ctx (one function for sample() and
  // pmf(), so that both compute the same numbers).
  void childImportances(const LightSampleContext& ctx, int node, float c[2]) const;

  std::vector<Node> nodes_;
  int heuristicDepth_ = 40;  // levels split by the cost heuristic before halving (light_bvh.cpp)
  std::vector<uint64_t> trail_;  // per light: bit k = which child it lies in at depth k (flat: its entry)
  AliasTable flat_;  // flat lights: the power distribution over them, labelled by light (else empty)
  std::vector<uint8_t> inTree_;  // per light
  int depth_ = 0;
};

}  // namespace tex::render
