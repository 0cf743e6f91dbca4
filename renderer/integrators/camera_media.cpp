#include "renderer/integrators/camera_media.h"

#include <algorithm>
#include <map>
#include <vector>

namespace tex::render {

namespace {

struct FirstCrossing {
  bool leaving = false;  // through the back of the surface (the ray was inside)
  float t = 0;           // distance along the ray
};

// The first crossing of each volume's surfaces along the ray from p in `direction`.
std::map<int, FirstCrossing> firstCrossingsAlong(const SceneGeometry& geometry, const MaterialSystem& materials, const Vec3& p,
                                                 const Vec3& direction) {
  constexpr int kMaxSurfaces = 4096;  // a ray through more is not worth following
  std::map<int, FirstCrossing> out;
  Ray ray;
  ray.origin = p;
  ray.direction = direction;
  ray.tMax = kInfinity;
  float travelled = 0;
  SurfaceHit hit;
  for (int k = 0; k < kMaxSurfaces && geometry.intersect(ray, hit); ++k) {
    travelled += hit.t;
    const int material = materials.materialOfPrimitive(hit.primitive);
    if (materials.transmitsIntoAVolume(material) && !out.count(material))
      out[material] = FirstCrossing{dot3(direction, hit.ng) > 0.0f, travelled};
    const Vec3 next = offsetRayOrigin(hit.p, hit.ng, direction, hit.pError);
    travelled += length(next - hit.p);
    ray.origin = next;
  }
  return out;
}

}  // namespace

MediumStack mediaAroundPoint(const SceneGeometry& geometry, const MaterialSystem& materials, const Vec3& p, const Vec3& forward) {
  // Directions unlikely to run along a modelled edge or face.
  const Vec3 directions[3] = {normalize(Vec3(0.2718f, 0.9311f, 0.1414f)), normalize(Vec3(-0.5772f, -0.1618f, 0.8007f)),
                              normalize(Vec3(0.6931f, -0.3010f, -0.6543f))};
  struct Votes {
    int inside = 0, outside = 0;
    float t = 0;  // distance to the surface, from the first ray that voted inside
  };
  std::map<int, Votes> votes;
  // Along `forward` (where the camera's own rays go) the first crossing decides: a camera
  // exactly on a surface then starts on whichever side its rays cross it from (a ray that
  // reports the surface at distance 0 enters or leaves it; one that does not is past it).
  if (forward != Vec3(0.0f))
    for (const auto& [material, first] : firstCrossingsAlong(geometry, materials, p, normalize(forward))) {
      Votes& v = votes[material];
      (first.leaving ? v.inside : v.outside) = 100;  // outvotes the three rays below
      v.t = first.t;
    }
  for (const Vec3& d : directions)
    for (const auto& [material, first] : firstCrossingsAlong(geometry, materials, p, d)) {
      Votes& v = votes[material];
      if (!first.leaving) ++v.outside;
      else if (v.inside++ == 0 && v.outside < 100) v.t = first.t;
    }
  std::vector<std::pair<float, int>> enclosing;  // (distance to its surface, material)
  for (const auto& [material, v] : votes)
    if (v.inside > v.outside) enclosing.push_back({v.t, material});
  std::sort(enclosing.begin(), enclosing.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  MediumStack media;
  for (const auto& [t, material] : enclosing) media.enter(material);  // outermost (farthest surface) first
  return media;
}

}  // namespace tex::render
