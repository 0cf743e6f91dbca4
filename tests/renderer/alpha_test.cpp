// glTF alpha during traversal (renderer/geometry/alpha_test.cpp): MASK cut-outs let every ray
// through where alpha < cutoff (closest-hit and shadow rays alike); BLEND stops a share alpha of
// rays, and the same ray always decides the same way.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/geometry/scene_geometry.h"
#include "renderer/sampling/pcg.h"
#include "renderer/scene/shapes.h"

namespace tex::render {
namespace {

SceneDescription quadScene(GltfMaterial::AlphaMode mode, float alpha) {
  SceneDescription s;
  MeshPrimitive quad = makeQuad(Vec3(-1, -1, 0), Vec3(2, 0, 0), Vec3(0, 2, 0));
  quad.material = 0;
  s.primitives.push_back(quad);
  s.instances.push_back(MeshInstance{0, Mat4(1.0f), "quad"});
  GltfMaterial m;
  m.alphaMode = mode;
  m.baseColorFactor = Vec4(1, 1, 1, alpha);
  m.alphaCutoff = 0.5f;
  s.materials.push_back(m);
  return s;
}

double hitShare(const SceneDescription& scene, bool shadowRays, uint64_t seed) {
  std::string error;
  auto geometry = SceneGeometry::build(scene, error);
  EXPECT_TRUE(geometry) << error;
  if (!geometry) return -1;
  sampling::Pcg32 rng(seed, 7);
  int hits = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    Ray r;
    r.origin = Vec3(rng.nextFloat() * 1.6f - 0.8f, rng.nextFloat() * 1.6f - 0.8f, 1.0f);
    r.direction = Vec3(0, 0, -1);
    SurfaceHit h;
    if (shadowRays ? geometry->occluded(r) : geometry->intersect(r, h)) ++hits;
  }
  return double(hits) / n;
}

TEST(Alpha, MaskCutsOutBelowTheCutoff) {
  for (bool shadow : {false, true}) {
    EXPECT_EQ(hitShare(quadScene(GltfMaterial::AlphaMode::Mask, 0.4f), shadow, 1), 0.0);
    EXPECT_EQ(hitShare(quadScene(GltfMaterial::AlphaMode::Mask, 0.6f), shadow, 1), 1.0);
    EXPECT_EQ(hitShare(quadScene(GltfMaterial::AlphaMode::Opaque, 0.1f), shadow, 1), 1.0);
  }
}

TEST(Alpha, BlendStopsAShareAlphaOfRaysDeterministically) {
  for (bool shadow : {false, true}) {
    const double share = hitShare(quadScene(GltfMaterial::AlphaMode::Blend, 0.3f), shadow, 2);
    EXPECT_NEAR(share, 0.3, 4 * std::sqrt(0.3 * 0.7 / 20000));
    EXPECT_EQ(share, hitShare(quadScene(GltfMaterial::AlphaMode::Blend, 0.3f), shadow, 2));
  }
}

}  // namespace
}  // namespace tex::render
