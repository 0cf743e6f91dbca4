// LightBvh (light_bvh.h): built top-down with pbrt-v4's surface-area-orientation heuristic
// (Conty Estevez and Kulla 2018, section 4.4), 12 buckets per axis.
#include "renderer/lights/light_bvh.h"

#include <algorithm>
#include <cmath>

namespace tex::render {

namespace {

constexpr int kBuckets = 12;
// Past this depth splits halve the count, so that every light's path fits 64 bits (a
// degenerate heuristic split peels one light at a time).
constexpr int kHeuristicDepth = 40;
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

// Quantised cosines: rounded down (a wider cone), so the quantised bounds stay conservative.
uint16_t quantiseCos(float c) {
  const float q = std::floor((std::clamp(c, -1.0f, 1.0f) + 1.0f) * 0.5f * 65535.0f);
  return uint16_t(std::clamp(q, 0.0f, 65535.0f));
}
float dequantiseCos(uint16_t q) { return std::max(-1.0f, float(q) * (2.0f / 65535.0f) - 1.0f); }

// The heuristic's cost of a cluster: power x the solid-angle measure of its emission cone
// (M_Omega, Conty Estevez and Kulla eq. 1) x its box's area, x a penalty for splitting a
// thin axis (K_r).
double clusterCost(const LightBounds& b, const Vec3& nodeDiagonal, int axis) {
  const float cosO = std::clamp(b.normals.cosTheta, -1.0f, 1.0f);
  const float thetaO = std::acos(cosO), thetaE = std::acos(std::clamp(b.cosThetaE, -1.0f, 1.0f));
  const float thetaW = std::min(thetaO + thetaE, kPi);
  const float sinO = std::sqrt(std::max(0.0f, 1.0f - cosO * cosO));
  const double mOmega = 2.0 * kPi * (1.0 - cosO) +
                        kPi / 2.0 * (2.0 * thetaW * sinO - std::cos(thetaO - 2.0 * thetaW) - 2.0 * thetaO * sinO + cosO);
  const Vec3 d = b.box.upper - b.box.lower;
  const double area = 2.0 * (double(d.x) * d.y + double(d.y) * d.z + double(d.z) * d.x);
  const float maxExtent = std::max({nodeDiagonal.x, nodeDiagonal.y, nodeDiagonal.z});
  const double kr = nodeDiagonal[axis] > 0.0f ? maxExtent / nodeDiagonal[axis] : 1.0;
  return double(b.phi) * mOmega * kr * area;
}

Vec3 centroid(const LightBounds& b) { return (b.box.lower + b.box.upper) * 0.5f; }

}  // namespace

LightBvh::LightBvh(std::vector<Entry> entries, int lightCount) {
  trail_.assign(size_t(std::max(lightCount, 0)), 0);
  inTree_.assign(size_t(std::max(lightCount, 0)), 0);
  std::erase_if(entries, [&](const Entry& e) { return !(e.bounds.phi > 0.0f) || e.light < 0 || e.light >= lightCount; });
  if (entries.empty()) return;
  nodes_.reserve(2 * entries.size() - 1);
  build(entries, 0, entries.size(), 0, 0);
}

int LightBvh::build(std::vector<Entry>& entries, size_t begin, size_t end, uint64_t trail, int depth) {
  depth_ = std::max(depth_, depth);
  LightBounds all = entries[begin].bounds;
  Bounds3 centroids;
  for (size_t i = begin; i < end; ++i) {
    if (i > begin) all = unionBounds(all, entries[i].bounds);
    centroids.extend(centroid(entries[i].bounds));
  }
  const int index = int(nodes_.size());
  Node node;
  node.lower = all.box.lower;
  node.upper = all.box.upper;
  node.w = all.normals.w;
  node.phi = all.phi;
  node.qCosThetaO = quantiseCos(all.normals.cosTheta);
  node.qCosThetaE = quantiseCos(all.cosThetaE);
  node.twoSided = all.twoSided ? 1 : 0;
  node.leaf = 0;
  node.childOrLight = 0;
  nodes_.push_back(node);
  if (end - begin == 1) {
    nodes_[size_t(index)].leaf = 1;
    nodes_[size_t(index)].childOrLight = uint32_t(entries[begin].light);
    trail_[size_t(entries[begin].light)] = trail;
    inTree_[size_t(entries[begin].light)] = 1;
    return index;
  }

  // The split: the cheapest bucket boundary over the three axes, else half the count.
  size_t mid = begin + (end - begin) / 2;
  const Vec3 nodeDiagonal = all.box.upper - all.box.lower;
  const Vec3 extent = centroids.upper - centroids.lower;
  int bestAxis = -1, bestBucket = -1;
  double bestCost = INFINITY;
  const auto bucketOf = [&](const Entry& e, int axis) {
    const float t = (centroid(e.bounds)[axis] - centroids.lower[axis]) / extent[axis];
    return std::clamp(int(t * kBuckets), 0, kBuckets - 1);
  };
  if (depth < kHeuristicDepth) {
    for (int axis = 0; axis < 3; ++axis) {
      if (!(extent[axis] > 0.0f)) continue;
      LightBounds bucket[kBuckets];
      for (size_t i = begin; i < end; ++i) {
        LightBounds& b = bucket[bucketOf(entries[i], axis)];
        b = b.phi > 0.0f ? unionBounds(b, entries[i].bounds) : entries[i].bounds;
      }
      for (int split = 0; split + 1 < kBuckets; ++split) {
        LightBounds below, above;
        for (int k = 0; k <= split; ++k) below = unionBounds(below, bucket[k]);
        for (int k = split + 1; k < kBuckets; ++k) above = unionBounds(above, bucket[k]);
        if (!(below.phi > 0.0f) || !(above.phi > 0.0f)) continue;
        const double cost = clusterCost(below, nodeDiagonal, axis) + clusterCost(above, nodeDiagonal, axis);
        if (cost < bestCost) {
          bestCost = cost;
          bestAxis = axis;
          bestBucket = split;
        }
      }
    }
  }
  if (bestAxis >= 0) {
    const auto it = std::partition(entries.begin() + std::ptrdiff_t(begin), entries.begin() + std::ptrdiff_t(end),
                                   [&](const Entry& e) { return bucketOf(e, bestAxis) <= bestBucket; });
    mid = size_t(it - entries.begin());
  }
  if (mid == begin || mid == end) mid = begin + (end - begin) / 2;
  build(entries, begin, mid, trail, depth + 1);
  const int second = build(entries, mid, end, trail | (uint64_t(1) << depth), depth + 1);
  nodes_[size_t(index)].childOrLight = uint32_t(second);
  return index;
}

float LightBvh::importance(const LightSampleContext& ctx, const Node& node) const {
  return lightImportance(ctx, node.lower, node.upper, node.phi, node.w, dequantiseCos(node.qCosThetaO),
                         dequantiseCos(node.qCosThetaE), node.twoSided != 0);
}

void LightBvh::childImportances(const LightSampleContext& ctx, int node, float c[2]) const {
  c[0] = importance(ctx, nodes_[size_t(node) + 1]);
  c[1] = importance(ctx, nodes_[nodes_[size_t(node)].childOrLight]);
}

std::optional<std::pair<int, float>> LightBvh::sample(const LightSampleContext& ctx, float u) const {
  if (nodes_.empty()) return std::nullopt;
  int node = 0;
  float pmf = 1.0f;
  // A lone light is returned without judging it (its sample is empty where it cannot reach):
  // scenes with one bounded light pay nothing for the tree.
  while (!nodes_[size_t(node)].leaf) {
    float c[2];
    childImportances(ctx, node, c);
    const float total = c[0] + c[1];
    if (!(total > 0.0f)) return std::nullopt;
    const float p0 = c[0] / total;
    if (u < p0) {
      u = std::min(u / p0, kOneMinusEpsilon);
      pmf *= p0;
      node = node + 1;
    } else {
      u = std::min((u - p0) / (1.0f - p0), kOneMinusEpsilon);
      pmf *= c[1] / total;
      node = int(nodes_[size_t(node)].childOrLight);
    }
  }
  return std::make_pair(int(nodes_[size_t(node)].childOrLight), pmf);
}

float LightBvh::pmf(const LightSampleContext& ctx, int light) const {
  if (light < 0 || size_t(light) >= inTree_.size() || !inTree_[size_t(light)]) return 0.0f;
  uint64_t trail = trail_[size_t(light)];
  int node = 0;
  float pmf = 1.0f;
  while (!nodes_[size_t(node)].leaf) {
    float c[2];
    childImportances(ctx, node, c);
    const float total = c[0] + c[1];
    if (!(total > 0.0f)) return 0.0f;
    const bool second = (trail & 1) != 0;
    pmf *= (second ? c[1] : c[0]) / total;
    node = second ? int(nodes_[size_t(node)].childOrLight) : node + 1;
    trail >>= 1;
  }
  return pmf;
}

}  // namespace tex::render
