#include "renderer/integrators/camera_media.h"

#include <algorithm>
#include <map>
#include <vector>

namespace tex::render {

namespace {

struct Crossings {
  int count = 0;
  float firstT = 0;  // distance along the ray to the first of them
};

// Every crossing of a volume's surface along the ray from p in `direction`, per material.
std::map<int, Crossings> crossingsAlong(const SceneGeometry& geometry, const MaterialSystem& materials, const Vec3& p,
                                        const Vec3& direction) {
  constexpr int kMaxSurfaces = 4096;  // a ray through more is not worth following
  std::map<int, Crossings> out;
  Ray ray;
  ray.origin = p;
  ray.direction = direction;
  ray.tMax = kInfinity;
  float travelled = 0;
  SurfaceHit hit;
  for (int k = 0; k < kMaxSurfaces && geometry.intersect(ray, hit); ++k) {
    travelled += hit.t;
    const int material = materials.materialOfPrimitive(hit.primitive);
    if (materials.transmitsIntoAVolume(material)) {
      Crossings& c = out[material];
      if (c.count++ == 0) c.firstT = travelled;
    }
    const Vec3 next = offsetRayOrigin(hit.p, hit.ng, direction, hit.pError);
    travelled += length(next - hit.p);
    ray.origin = next;
  }
  return out;
}

}  // namespace

MediumStack mediaAroundPoint(const SceneGeometry& geometry, const MaterialSystem& materials, const Vec3& p) {
  // Directions unlikely to run along a modelled edge or face.
  const Vec3 directions[3] = {normalize(Vec3(0.2718f, 0.9311f, 0.1414f)), normalize(Vec3(-0.5772f, -0.1618f, 0.8007f)),
                              normalize(Vec3(0.6931f, -0.3010f, -0.6543f))};
  std::map<int, int> insideVotes;
  std::map<int, float> firstT;  // from the first ray that voted inside
  for (const Vec3& d : directions)
    for (const auto& [material, c] : crossingsAlong(geometry, materials, p, d)) {
      if (c.count % 2 == 0) continue;
      if (insideVotes[material]++ == 0) firstT[material] = c.firstT;
    }
  std::vector<std::pair<float, int>> enclosing;  // (distance to its surface, material)
  for (const auto& [material, votes] : insideVotes)
    if (votes >= 2) enclosing.push_back({firstT[material], material});
  std::sort(enclosing.begin(), enclosing.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  MediumStack media;
  for (const auto& [t, material] : enclosing) media.enter(material);  // outermost (farthest surface) first
  return media;
}

}  // namespace tex::render
