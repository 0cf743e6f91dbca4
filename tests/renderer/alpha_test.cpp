// glTF alpha during traversal (renderer/geometry/alpha_test.cpp): MASK cut-outs let every ray
// through where alpha < cutoff (closest-hit and shadow rays alike); BLEND stops a share alpha of
// rays, and the same ray always decides the same way.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

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

// Two BLEND layers of alpha 0.5, one above the other: a ray stops at the upper with
// probability 0.5 and at the lower with 0.25, and passes both with 0.25. Until round 18 a ray's
// choice hashed only the ray (the primitive index was mixed into bits the choice never read):
// every BLEND surface along a ray decided the same way, so no ray passed the upper and stopped
// at the lower (a BLEND lamp behind a BLEND sheet lost the light paths that hit it). Layers as
// two primitives, as one primitive used twice (baked copies), and as instances of it.
TEST(Alpha, BlendLayersAlongARayDecideIndependently) {
  for (const int layout : {0, 1, 2}) {
    SceneDescription s;
    GltfMaterial m;
    m.alphaMode = GltfMaterial::AlphaMode::Blend;
    m.baseColorFactor = Vec4(1, 1, 1, 0.5f);
    s.materials.push_back(m);
    MeshPrimitive quad = makeQuad(Vec3(-1, -1, 0), Vec3(2, 0, 0), Vec3(0, 2, 0));
    quad.material = 0;
    const Mat4 lower = glm::translate(Mat4(1.0f), Vec3(0.0f, 0.0f, -0.5f));
    s.primitives.push_back(quad);
    s.instances.push_back(MeshInstance{0, Mat4(1.0f), "upper"});
    if (layout == 0) {
      s.primitives.push_back(quad);
      s.instances.push_back(MeshInstance{1, lower, "lower"});
    } else {
      s.instances.push_back(MeshInstance{0, lower, "lower"});
    }
    GeometryBuildOptions options;
    if (layout == 2) options.maxBakedCopyTriangles = 0;  // instance every reuse
    std::string error;
    const auto geometry = SceneGeometry::build(s, error, options);
    ASSERT_TRUE(geometry) << error;
    sampling::Pcg32 rng(5, 3);
    const int n = 40000;
    int upper = 0, lowerHits = 0, through = 0, occluded = 0;
    for (int i = 0; i < n; ++i) {
      Ray r;
      r.origin = Vec3(rng.nextFloat() * 1.6f - 0.8f, rng.nextFloat() * 1.6f - 0.8f, 1.0f);
      r.direction = Vec3(0, 0, -1);
      SurfaceHit h;
      if (!geometry->intersect(r, h)) ++through;
      else if (h.p.z > -0.25f) ++upper;
      else ++lowerHits;
      occluded += geometry->occluded(r);
    }
    const auto near = [&](int count, double p) {
      return std::fabs(double(count) / n - p) < 4.5 * std::sqrt(p * (1.0 - p) / n);
    };
    EXPECT_TRUE(near(upper, 0.5)) << "layout " << layout << ": upper " << upper;
    EXPECT_TRUE(near(lowerHits, 0.25)) << "layout " << layout << ": lower " << lowerHits;
    EXPECT_TRUE(near(through, 0.25)) << "layout " << layout << ": through " << through;
    EXPECT_EQ(occluded, n - through) << "layout " << layout;  // shadow rays decide as closest-hit rays
  }
}

}  // namespace
}  // namespace tex::render
