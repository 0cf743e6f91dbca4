// glTF normal maps (renderer/material/gltf_material.cpp): the texel (r, g, b) is the tangent-space
// normal (2r - 1, 2g - 1, 2b - 1) scaled by normalScale in x and y, with +x along the tangent
// (increasing u) and +y along the bitangent (glTF: cross(normal, tangent) * w; without tangents,
// decreasing v, since glTF's uv origin is the image's top-left).
#include <gtest/gtest.h>

#include "renderer/material/gltf_material.h"

namespace tex::render {
namespace {

Vec3 mappedNormal(Vec3 texel, float scale, Vec4 tangent) {
  SceneDescription scene;
  ImageData img;
  img.width = img.height = 1;
  img.channels = 3;
  img.pixels = {texel.x, texel.y, texel.z};
  scene.images.push_back(img);
  GltfMaterial m;
  m.normalTexture.image = 0;
  m.normalScale = scale;
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

}  // namespace
}  // namespace tex::render
