// LightBvh (light_bvh.h): built top-down with pbrt-v4's surface-area-orientation heuristic
// (Conty Estevez and Kulla 2018, section 4.4), 12 buckets per axis.
#include "renderer/lights/light_bvh.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace tex::render {

namespace {

constexpr int kBuckets = 12;
// Past this depth splits halve the count, so that every light's path fits 64 bits (a
// degenerate heuristic split peels one light at a time).
constexpr int kHeuristicDepth = 40;  // at most; fewer for huge light counts (heuristicDepth_)
constexpr double kOneMinusEpsilon = 0x1.fffffffffffffp-1;

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

// The bounds of many lights in two cheap passes instead of a chain of cone unions (each an
// acos, an asin and a rotation: most of the build at 200 k lights): the first gathers box,
// power, spread and the sum of the cone axes, the second the widest angle of any light's cone
// from the mean axis, as cos(angle + theta_o) without trigonometry.
struct Cluster {
  LightBounds bounds;
  Vec3 axisSum{0.0f};
  bool everyDirection = false;
  bool empty() const { return !(bounds.phi > 0.0f); }

  void addFirst(const LightBounds& b) {
    if (empty()) {
      bounds = b;
      bounds.normals.cosTheta = 1.0f;
    } else {
      bounds.box.lower = glm::min(bounds.box.lower, b.box.lower);
      bounds.box.upper = glm::max(bounds.box.upper, b.box.upper);
      bounds.phi = std::min(bounds.phi + b.phi, FLT_MAX);
      bounds.cosThetaE = std::min(bounds.cosThetaE, b.cosThetaE);
      bounds.twoSided = bounds.twoSided || b.twoSided;
    }
    axisSum += b.normals.w;
    everyDirection = everyDirection || b.normals.cosTheta <= -1.0f;
  }
  // After every addFirst: the axis, then addSecond for each light again.
  void chooseAxis() {
    const float length = std::sqrt(dot3(axisSum, axisSum));
    if (!(length > 1e-6f)) everyDirection = true;
    else bounds.normals.w = axisSum / length;
    bounds.normals.cosTheta = everyDirection ? -1.0f : 1.0f;
  }
  void addSecond(const LightBounds& b) {
    if (everyDirection) return;
    const Vec3& axis = bounds.normals.w;
    const float c = std::clamp(dot3(axis, b.normals.w), -1.0f, 1.0f), s = std::sqrt(std::max(0.0f, 1.0f - c * c));
    const float cosO = b.normals.cosTheta, sinO = std::sqrt(std::max(0.0f, 1.0f - cosO * cosO));
    // angle(axis, w) + theta_o past pi: the cone is the whole sphere.
    const float cosSum = c < -cosO ? -1.0f : c * cosO - s * sinO;
    // Slightly wider than computed, against rounding.
    bounds.normals.cosTheta = std::max(-1.0f, std::min(bounds.normals.cosTheta, cosSum - 2e-6f));
  }
};

}  // namespace

LightBvh::LightBvh(std::vector<Entry> entries, int lightCount) {
  trail_.assign(size_t(std::max(lightCount, 0)), 0);
  inTree_.assign(size_t(std::max(lightCount, 0)), 0);
  std::erase_if(entries, [&](const Entry& e) { return !(e.bounds.phi > 0.0f) || e.light < 0 || e.light >= lightCount; });
  if (entries.empty()) return;
  if (onePlane(entries)) {
    std::vector<float> phi;
    std::vector<int> lights;
    for (size_t i = 0; i < entries.size(); ++i) {
      phi.push_back(entries[i].bounds.phi);
      lights.push_back(entries[i].light);
      trail_[size_t(entries[i].light)] = i;
      inTree_[size_t(entries[i].light)] = 1;
    }
    flat_ = AliasTable(phi, lights);
  }
  // The tree is built either way (its nodes describe the lights); a flat set does not descend it.
  nodes_.reserve(2 * entries.size() - 1);
  // Past the heuristic's depth nodes halve their count, so the deepest leaf is at most
  // heuristicDepth_ + ceil(log2 n): kept within the 64-bit trail (beyond 2^24 lights, 40 levels
  // of heuristic had let it overflow).
  int log2Count = 0;
  while (log2Count < 63 && (uint64_t(1) << log2Count) < uint64_t(entries.size())) ++log2Count;
  heuristicDepth_ = std::max(0, std::min(kHeuristicDepth, 63 - log2Count));
  build(entries, 0, entries.size(), flat_.empty() ? 0 : ~uint64_t(0), 0);
}

// Few single-sided lights with one normal whose boxes all meet one plane along it.
bool LightBvh::onePlane(const std::vector<Entry>& entries) {
  if (entries.size() > kFlatMax) return false;
  const LightBounds& first = entries[0].bounds;
  float planeLow = -INFINITY, planeHigh = INFINITY;
  for (const Entry& e : entries) {
    const LightBounds& b = e.bounds;
    // (The triangles of one quad have normals equal up to rounding; the choice by power is a
    // strategy, right for any set, so a tolerance costs nothing but a little efficiency.)
    if (dot3(b.normals.w, first.normals.w) < 1.0f - 1e-5f || b.normals.cosTheta < 1.0f || b.twoSided ||
        b.cosThetaE != first.cosThetaE)
      return false;
    // The box's extent along the normal (its corners' projections).
    float low = INFINITY, high = -INFINITY;
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 c((corner & 1) ? b.box.upper.x : b.box.lower.x, (corner & 2) ? b.box.upper.y : b.box.lower.y,
                   (corner & 4) ? b.box.upper.z : b.box.lower.z);
      low = std::min(low, dot3(c, b.normals.w));
      high = std::max(high, dot3(c, b.normals.w));
    }
    const float tolerance = 1e-5f * (1.0f + std::fabs(low) + std::fabs(high));
    planeLow = std::max(planeLow, low - tolerance);
    planeHigh = std::min(planeHigh, high + tolerance);
  }
  return planeLow <= planeHigh;
}

int LightBvh::build(std::vector<Entry>& entries, size_t begin, size_t end, uint64_t trail, int depth) {
  depth_ = std::max(depth_, depth);
  LightBounds all = entries[begin].bounds;
  Bounds3 centroids;
  if (end - begin > 1) {
    Cluster cluster;
    for (size_t i = begin; i < end; ++i) cluster.addFirst(entries[i].bounds);
    cluster.chooseAxis();
    for (size_t i = begin; i < end; ++i) cluster.addSecond(entries[i].bounds);
    all = cluster.bounds;
  }
  for (size_t i = begin; i < end; ++i) centroids.extend(centroid(entries[i].bounds));
  const int index = int(nodes_.size());
  Node node;
  boundingSphere(all.box, node.center, node.radius);
  node.w = all.normals.w;
  node.phi = all.phi;
  node.cosThetaO = std::clamp(all.normals.cosTheta, -1.0f, 1.0f);
  node.sinThetaO = std::sqrt(std::max(0.0f, 1.0f - node.cosThetaO * node.cosThetaO));
  node.cosThetaE = all.cosThetaE;
  node.twoSided = all.twoSided ? 1 : 0;
  node.leaf = 0;
  node.childOrLight = 0;
  nodes_.push_back(node);
  if (end - begin == 1) {
    nodes_[size_t(index)].leaf = 1;
    nodes_[size_t(index)].childOrLight = uint32_t(entries[begin].light);
    if (trail != ~uint64_t(0)) trail_[size_t(entries[begin].light)] = trail;
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
  if (depth < heuristicDepth_) {
    for (int axis = 0; axis < 3; ++axis) {
      if (!(extent[axis] > 0.0f)) continue;
      Cluster bucket[kBuckets];
      for (size_t i = begin; i < end; ++i) bucket[bucketOf(entries[i], axis)].addFirst(entries[i].bounds);
      for (Cluster& b : bucket)
        if (!b.empty()) b.chooseAxis();
      for (size_t i = begin; i < end; ++i) bucket[bucketOf(entries[i], axis)].addSecond(entries[i].bounds);
      // Bounds of the buckets below and above each boundary.
      LightBounds below[kBuckets], above[kBuckets];
      for (int k = 0; k < kBuckets; ++k) below[k] = unionBounds(k > 0 ? below[k - 1] : LightBounds(), bucket[k].bounds);
      for (int k = kBuckets - 1; k >= 0; --k)
        above[k] = unionBounds(k + 1 < kBuckets ? above[k + 1] : LightBounds(), bucket[k].bounds);
      for (int split = 0; split + 1 < kBuckets; ++split) {
        if (!(below[split].phi > 0.0f) || !(above[split + 1].phi > 0.0f)) continue;
        const double cost = clusterCost(below[split], nodeDiagonal, axis) + clusterCost(above[split + 1], nodeDiagonal, axis);
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
  const int second = build(entries, mid, end, trail == ~uint64_t(0) ? trail : trail | (uint64_t(1) << depth), depth + 1);
  nodes_[size_t(index)].childOrLight = uint32_t(second);
  return index;
}

// Not inlined: sample() and pmf() must get the same numbers bit for bit, and two inlined copies
// may be contracted (FMA) differently when the build allows it.
[[gnu::noinline]] void LightBvh::childImportances(const LightSampleContext& ctx, int node, float c[2]) const {
  const Node& a = nodes_[size_t(node) + 1];
  const Node& b = nodes_[nodes_[size_t(node)].childOrLight];
  c[0] = lightImportance(ctx, a.center, a.radius, a.w, a.phi, a.cosThetaO, a.sinThetaO, a.cosThetaE, a.twoSided != 0);
  c[1] = lightImportance(ctx, b.center, b.radius, b.w, b.phi, b.cosThetaO, b.sinThetaO, b.cosThetaE, b.twoSided != 0);
}

bool LightBvh::descend(const LightSampleContext& ctx, double u, int& light, float& pmf) const {
  if (nodes_.empty()) return false;
  int node = 0;
  pmf = 1.0f;
  // A lone light is returned without judging it (its sample is empty where it cannot reach):
  // scenes with one bounded light pay nothing for the tree.
  while (!nodes_[size_t(node)].leaf) {
    float c[2];
    childImportances(ctx, node, c);
    const float total = c[0] + c[1];
    if (!(total > 0.0f)) return false;
    // u scaled to [0, c0 + c1): one division on the chain from one level's u to the next (the
    // probabilities below are off it). A child of importance 0 is never chosen, also when
    // u x total rounds up to total. In double, and the sum too: a child of 1e-6 of its
    // sibling's importance spans only about 13 ulps of a float total, whose rounding had given
    // it an interval of u 3 % narrower than the pmf it reports.
    const double scaled = u * (double(c[0]) + double(c[1]));
    if (scaled < double(c[0]) || c[1] == 0.0f) {
      u = std::min(scaled / double(c[0]), kOneMinusEpsilon);
      pmf *= c[0] / total;
      node = node + 1;
    } else {
      u = std::min((scaled - double(c[0])) / double(c[1]), kOneMinusEpsilon);
      pmf *= c[1] / total;
      node = int(nodes_[size_t(node)].childOrLight);
    }
  }
  light = int(nodes_[size_t(node)].childOrLight);
  return true;
}

float LightBvh::retrace(const LightSampleContext& ctx, int light) const {
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
