// glTF normal maps (renderer/material/gltf_material.cpp): the texel (r, g, b) is the tangent-space
// normal (2r - 1, 2g - 1, 2b - 1) scaled by normalScale in x and y, with +x along the tangent
// (increasing u) and +y along the bitangent (glTF: cross(normal, tangent) * w; without tangents,
// decreasing v, since glTF's uv origin is the image's top-left).
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/material/gltf_material.h"

namespace tex::render {
namespace {

struct UvTransform {
  float rotation = 0;
  Vec2 scale{1.0f}, offset{0.0f};
};

Vec3 mappedNormal(Vec3 texel, float scale, Vec4 tangent, UvTransform transform = {}) {
  SceneDescription scene;
  ImageData img;
  img.width = img.height = 1;
  img.channels = 3;
  img.pixels = {texel.x, texel.y, texel.z};
  scene.images.push_back(img);
  GltfMaterial m;
  m.normalTexture.image = 0;
  m.normalScale = scale;
  m.normalTexture.rotation = transform.rotation;
  m.normalTexture.scale = transform.scale;
  m.normalTexture.offset = transform.offset;
  ShadingPoint p;
  p.p = Vec3(0.0f);
  p.ng = p.ns = Vec3(0, 0, 1);
  p.uv = Vec2(0.5f);
  p.dpdu = Vec3(1, 0, 0);
  p.dpdv = Vec3(0, -1, 0);  // v grows downwards in the image and -y in the world here
  p.tangent = tangent;
  Bsdf bsdf(Frame::fromNormal(p.ns), p.ng);
  applyGltfNormalMap(scene, m, p, bsdf);
  return bsdf.frame().n;
}

void expectNear(Vec3 a, Vec3 b) {
  EXPECT_NEAR(a.x, b.x, 1e-5f);
  EXPECT_NEAR(a.y, b.y, 1e-5f);
  EXPECT_NEAR(a.z, b.z, 1e-5f);
}

TEST(NormalMap, FlatTexelKeepsTheNormal) { expectNear(mappedNormal(Vec3(0.5f, 0.5f, 1.0f), 1.0f, Vec4(0.0f)), Vec3(0, 0, 1)); }

TEST(NormalMap, RedTiltsTowardTheTangentAndGreenTowardTheBitangent) {
  expectNear(mappedNormal(Vec3(0.75f, 0.5f, 1.0f), 1.0f, Vec4(0.0f)), glm::normalize(Vec3(0.5f, 0.0f, 1.0f)));
  expectNear(mappedNormal(Vec3(0.5f, 0.75f, 1.0f), 1.0f, Vec4(0.0f)), glm::normalize(Vec3(0.0f, 0.5f, 1.0f)));
  expectNear(mappedNormal(Vec3(0.75f, 0.5f, 1.0f), 2.0f, Vec4(0.0f)), glm::normalize(Vec3(1.0f, 0.0f, 1.0f)));
}

TEST(NormalMap, TangentAttributeAndHandednessWin) {
  // Tangent along +y, w = -1: bitangent = -(n x t) = +x.
  expectNear(mappedNormal(Vec3(0.75f, 0.5f, 1.0f), 1.0f, Vec4(0, 1, 0, -1)), glm::normalize(Vec3(0.0f, 0.5f, 1.0f)));
  expectNear(mappedNormal(Vec3(0.5f, 0.75f, 1.0f), 1.0f, Vec4(0, 1, 0, -1)), glm::normalize(Vec3(0.5f, 0.0f, 1.0f)));
}

// KHR_texture_transform: the map's +x follows increasing u' (the transformed coordinate) on the
// surface, whatever the rotation, scale and mirroring, i.e. along dp/du' = dp/du du/du' +
// dp/dv dv/du' from the inverse of uv' = R S uv + offset. Here dp/du = +x and dp/dv = -y.
Vec3 surfaceDirectionOfIncreasingU(UvTransform tf) {
  const float c = std::cos(tf.rotation), r = std::sin(tf.rotation);
  // uv' = A uv + offset with A = [[c sx, r sy], [-r sx, c sy]]; column 1 of A^-1 is (du/du', dv/du').
  const float det = tf.scale.x * tf.scale.y;
  const float dudU = c * tf.scale.y / det, dvdU = r * tf.scale.x / det;
  return glm::normalize(Vec3(1, 0, 0) * dudU + Vec3(0, -1, 0) * dvdU);
}

TEST(NormalMap, TextureTransformTurnsTheTangentFrameWithTheTexture) {
  const Vec3 n(0, 0, 1);
  const UvTransform cases[] = {{1.5707964f, Vec2(1.0f), Vec2(0.0f)},   {0.7f, Vec2(2.0f), Vec2(0.3f, -0.2f)},
                               {-2.1f, Vec2(0.5f), Vec2(0.0f)},       {0.0f, Vec2(-1.0f, 1.0f), Vec2(0.0f)},
                               {0.4f, Vec2(3.0f, 0.5f), Vec2(0.0f)},  {2.5f, Vec2(1.0f, -2.0f), Vec2(0.1f)}};
  for (const UvTransform& tf : cases) {
    SCOPED_TRACE(testing::Message() << "rotation " << tf.rotation << " scale " << tf.scale.x << "," << tf.scale.y);
    const Vec3 tangent = surfaceDirectionOfIncreasingU(tf);
    // Red tilts toward the surface direction of increasing u'.
    expectNear(mappedNormal(Vec3(0.75f, 0.5f, 1.0f), 1.0f, Vec4(0.0f), tf), glm::normalize(tangent * 0.5f + n));
    // The same with a TANGENT attribute that agrees with the uvs (+x, w = +1 here).
    expectNear(mappedNormal(Vec3(0.75f, 0.5f, 1.0f), 1.0f, Vec4(1, 0, 0, 1), tf), glm::normalize(tangent * 0.5f + n));
    // Green tilts toward decreasing v', which is the frame's bitangent when the scale is
    // uniform (for unequal scales the transformed axes are not orthogonal on the surface).
    if (std::abs(tf.scale.x) == std::abs(tf.scale.y)) {
      const float c = std::cos(tf.rotation), r = std::sin(tf.rotation), det = tf.scale.x * tf.scale.y;
      const Vec3 dpdV = Vec3(1, 0, 0) * (-r * tf.scale.y / det) + Vec3(0, -1, 0) * (c * tf.scale.x / det);
      expectNear(mappedNormal(Vec3(0.5f, 0.75f, 1.0f), 1.0f, Vec4(0.0f), tf),
                 glm::normalize(-glm::normalize(dpdV) * 0.5f + n));
    }
  }
}

TEST(NormalMap, OffsetAloneLeavesTheFrame) {
  expectNear(mappedNormal(Vec3(0.75f, 0.5f, 1.0f), 1.0f, Vec4(0.0f), {0.0f, Vec2(1.0f), Vec2(0.25f, 0.5f)}),
             glm::normalize(Vec3(0.5f, 0.0f, 1.0f)));
}

}  // namespace
}  // namespace tex::render
