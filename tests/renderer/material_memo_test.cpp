// The Hit-dependence analysis (renderer/material/hit_dependence.h) and the per-thread memo it
// enables (material_memo.h): materials whose closure tree cannot depend on the Hit are
// recognised through lets, calls, folds and captures, anything reading the Hit is not, and
// replayed evaluations equal fresh ones bit for bit, per wavelength group and per system.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "renderer/material/closure_lobes.h"
#include "renderer/material/gltf_material.h"
#include "renderer/material/material_system.h"
#include "renderer/material/tex_binding.h"
#include "tests/renderer/scene_fixtures.h"

namespace tex::render {
namespace {

const char* kMaterials =
    "fn ignore(h: Hit, c: Color) -> Color = c\n"
    "fn shade_of(h: Hit) -> Color = rgb(h.uv.y, 0.2, 0.2)\n"
    // Hit-independent:
    "export fn plain(h: Hit) -> Material = diffuse(rgb(0.8, 0.5, 0.2))\n"
    "export fn helper(h: Hit) -> Material = diffuse(ignore(h, rgb(0.3, 0.4, 0.5)))\n"
    "export fn folded(h: Hit) -> Material = diffuse(rgb(fold(4, 0.1, |acc, i| acc + 0.1), 0.5, 0.5))\n"
    "export fn spectral(h: Hit) -> Material = diffuse(lambda_nm * 0.001)\n"
    "export fn light(h: Hit) -> Material = add_material(diffuse(rgb(0.5)), emission(rgb(2.0, 1.0, 0.5)))\n"
    // Hit-dependent:
    "export fn by_uv(h: Hit) -> Material = diffuse(rgb(h.uv.x, 0.5, 0.5))\n"
    "export fn by_let(h: Hit) -> Material {\n  let u = h.p.x;\n  diffuse(rgb(0.5, u, 0.5))\n}\n"
    "export fn by_call(h: Hit) -> Material = diffuse(shade_of(h))\n"
    "export fn by_if(h: Hit) -> Material = if h.uv.x > 0.5 { diffuse(rgb(0.9)) } else { diffuse(rgb(0.1)) }\n"
    "export fn by_fold(h: Hit) -> Material = diffuse(rgb(fold(3, h.uv.x, |acc, i| acc * 0.5), 0.5, 0.5))\n"
    "export fn by_capture(h: Hit) -> Material = diffuse(rgb(fold(3, 0.0, |acc, i| acc + h.uv.y), 0.5, 0.5))\n"
    "export fn glowing_uv(h: Hit) -> Material = emission(rgb(h.uv.x, 1.0, 1.0))\n";

const std::vector<std::string> kIndependent = {"plain", "helper", "folded", "spectral", "light"};
const std::vector<std::string> kDependent = {"by_uv", "by_let", "by_call", "by_if", "by_fold", "by_capture", "glowing_uv"};

// A scene whose material i is bound to entry i of a module (kMaterials unless given; no
// geometry: only the material system is used).
SceneDescription sceneWith(const std::vector<std::string>& entries, const std::string& moduleName = "memo_mats",
                           const std::string& source = kMaterials) {
  const std::string file = test::writeTexModule(moduleName, source);
  SceneDescription scene;
  for (const std::string& e : entries) {
    GltfMaterial m;
    m.name = e;
    scene.materials.push_back(m);
  }
  test::bindEntriesByMaterialName(scene, file, entries);
  return scene;
}

std::vector<std::string> allEntries() {
  std::vector<std::string> all = kIndependent;
  all.insert(all.end(), kDependent.begin(), kDependent.end());
  return all;
}

ShadingPoint pointAt(float u, float v, float x) {
  ShadingPoint p;
  p.p = Vec3(x, 0.2f, 0.3f);
  p.ng = p.ns = Vec3(0, 0, 1);
  p.uv = Vec2(u, v);
  return p;
}

bool sameBits(const Spectrum& a, const Spectrum& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A 2x1 sRGB image: red on the left half, blue on the right.
ImageData redThenBlue() {
  ImageData image;
  image.width = 2;
  image.height = 1;
  image.channels = 3;
  image.bytes = {230, 40, 20, 20, 60, 220};
  return image;
}

bool sameLobes(const Bsdf& a, const Bsdf& b) {
  if (a.lobeCount() != b.lobeCount() || a.hasCoat() != b.hasCoat()) return false;
  for (int i = 0; i < a.lobeCount(); ++i)
    if (a.lobe(i).kind != b.lobe(i).kind || !sameBits(a.lobe(i).weight, b.lobe(i).weight)) return false;
  return true;
}

TEST(HitDependence, ClassifiesMaterialsThroughLetsCallsFoldsAndCaptures) {
  const SceneDescription scene = sceneWith(allEntries());
  CompiledBindings compiled;
  std::string error;
  ASSERT_TRUE(compileBindings(scene, 4, false, false, compiled, error)) << error;
  ASSERT_EQ(compiled.bindings.size(), kIndependent.size() + kDependent.size());
  for (size_t i = 0; i < compiled.bindings.size(); ++i) {
    const bool expected = i < kIndependent.size();
    EXPECT_EQ(compiled.bindings[i].hitIndependent, expected) << compiled.bindings[i].name;
  }
}

TEST(MaterialMemo, ReplaysEqualFreshEvaluationsPerWavelengthGroup) {
  const SceneDescription scene = sceneWith(allEntries());
  std::string error;
  const std::unique_ptr<MaterialSystem> materials = MaterialSystem::create(scene, MaterialOptions{}, error);
  ASSERT_TRUE(materials) << error;
  CompiledBindings direct;  // the same materials, evaluated without the memo
  ASSERT_TRUE(compileBindings(scene, 4, false, false, direct, error)) << error;
  const Wavelengths groups[2] = {color::sampleWavelengthGroup(0.3f, 4), color::sampleWavelengthGroup(0.7f, 4)};
  const ShadingPoint points[3] = {pointAt(0.2f, 0.3f, 0.1f), pointAt(0.8f, 0.6f, 0.9f), pointAt(0.4f, 0.9f, -0.5f)};
  int dependentDifferences = 0;
  // Groups alternate (A, B, A) and points change within a group, as along paths.
  for (int round = 0; round < 3; ++round) {
    const Wavelengths& lambda = groups[round % 2];
    for (size_t m = 0; m < direct.bindings.size(); ++m) {
      Bsdf first;
      for (const ShadingPoint& p : points) {
        Bsdf viaSystem(Frame(), Vec3(0, 0, 1)), fresh(Frame(), Vec3(0, 0, 1));
        Spectrum eSystem, eFresh;
        ASSERT_TRUE(materials->shade(int(m), p, lambda, viaSystem, eSystem));
        ASSERT_TRUE(evaluateBinding(direct.bindings[m], p, lambda, &fresh, eFresh).ok);
        EXPECT_TRUE(sameLobes(viaSystem, fresh)) << direct.bindings[m].name << " round " << round;
        EXPECT_TRUE(sameBits(eSystem, eFresh)) << direct.bindings[m].name << " round " << round;
        const Spectrum emitted = materials->emission(int(m), p, lambda);
        if (materials->isEmissive(int(m))) {
          EXPECT_TRUE(sameBits(emitted, eFresh)) << direct.bindings[m].name;
        }
        if (&p == &points[0]) first.copyLobesFrom(fresh);
        if (m >= kIndependent.size() && !sameLobes(first, fresh)) ++dependentDifferences;
      }
    }
  }
  // The Hit-dependent materials do vary over the points (so a stale replay would be caught).
  EXPECT_GT(dependentDifferences, 20);
}

bool sameLobeParameters(const Bsdf& a, const Bsdf& b) {
  if (!sameLobes(a, b)) return false;
  for (int i = 0; i < a.lobeCount(); ++i)
    if (!sameBits(a.lobe(i).a, b.lobe(i).a) || !sameBits(a.lobe(i).b, b.lobe(i).b) ||
        a.lobe(i).etaVaries != b.lobe(i).etaVaries)
      return false;
  return true;
}

TEST(ConstantClosure, CapturedOnlyWithoutHitOrWavelengthAndWalksLikeTheCompiledCode) {
  // Constant: the Hit-independent materials without wavelength-dependent values, a smooth glass
  // of constant IOR (a Spectrum splat). Not constant: a spectrum of lambda_nm, a dispersive
  // glass (Cauchy: its IOR reads the wavelengths), every Hit-dependent material.
  std::vector<std::string> entries = allEntries();
  entries.push_back("glass");
  entries.push_back("prism");
  const SceneDescription scene =
      sceneWith(entries, "constant_mats",
                std::string(kMaterials) + "export fn glass(h: Hit) -> Material = dielectric(1.5)\n"
                                          "export fn prism(h: Hit) -> Material = dielectric(1.5 + 4200.0 / (lambda_nm * lambda_nm))\n");
  CompiledBindings compiled;
  std::string error;
  ASSERT_TRUE(compileBindings(scene, 4, false, false, compiled, error)) << error;
  const std::vector<std::string> constant = {"plain", "helper", "folded", "light", "glass"};
  const Wavelengths probe = color::sampleWavelengthGroup(0.5f, 4);
  for (const CompiledBinding& binding : compiled.bindings) {
    ConstantClosure tree;
    const bool captured = captureConstantClosure(binding, pointAt(0.5f, 0.5f, 0.0f), probe, tree);
    const std::string entry = binding.name.substr(binding.name.rfind(':') + 1);  // "file:entry"
    const bool expected = std::find(constant.begin(), constant.end(), entry) != constant.end();
    EXPECT_EQ(captured, expected) << binding.name;
    if (!captured) continue;
    for (const float u : {0.05f, 0.3f, 0.5f, 0.95f}) {
      const Wavelengths lambda = color::sampleWavelengthGroup(u, 4);
      Bsdf walked(Frame(), Vec3(0, 0, 1)), compiledBsdf(Frame(), Vec3(0, 0, 1));
      Spectrum eWalked, eCompiled;
      ASSERT_TRUE(walkConstantClosure(tree, lambda, &walked, eWalked).ok) << binding.name;
      ASSERT_TRUE(evaluateBinding(binding, pointAt(u, 0.1f, 0.2f), lambda, &compiledBsdf, eCompiled).ok);
      EXPECT_TRUE(sameLobeParameters(walked, compiledBsdf)) << binding.name << " u " << u;
      EXPECT_TRUE(sameBits(eWalked, eCompiled)) << binding.name << " u " << u;
    }
  }
}

TEST(MaterialMemo, SystemsDoNotShareEntries) {
  // Two systems whose slot 0 holds different materials, used alternately on one thread.
  std::string error;
  const SceneDescription sceneA = sceneWith({"plain"}), sceneB = sceneWith({"helper"});
  const std::unique_ptr<MaterialSystem> a = MaterialSystem::create(sceneA, MaterialOptions{}, error);
  const std::unique_ptr<MaterialSystem> b = MaterialSystem::create(sceneB, MaterialOptions{}, error);
  ASSERT_TRUE(a && b) << error;
  const Wavelengths lambda = color::sampleWavelengthGroup(0.5f, 4);
  Bsdf fromA[2], fromB[2];
  Spectrum e;
  for (int k = 0; k < 2; ++k) {
    ASSERT_TRUE(a->shade(0, pointAt(0.1f, 0.1f, 0.0f), lambda, fromA[k], e));
    ASSERT_TRUE(b->shade(0, pointAt(0.1f, 0.1f, 0.0f), lambda, fromB[k], e));
  }
  EXPECT_TRUE(sameLobes(fromA[0], fromA[1]));
  EXPECT_TRUE(sameLobes(fromB[0], fromB[1]));
  EXPECT_FALSE(sameLobes(fromA[1], fromB[1]));
}

// Unbound glTF materials (std.gltf) replay from the memo when they read no texture: the
// replay equals a fresh evaluation bit for bit, and a textured material is never replayed
// across points (its two texels give different lobes).
TEST(MaterialMemo, GltfMaterialsWithoutTexturesReplayAndTexturedOnesDoNot) {
  SceneDescription scene;
  scene.images.push_back(redThenBlue());
  GltfMaterial plastic, metal, glass, textured, brokenTexture;
  plastic.baseColorFactor = Vec4(0.8f, 0.3f, 0.2f, 1.0f);
  plastic.metallicFactor = 0.0f;
  plastic.roughnessFactor = 0.5f;
  metal.metallicFactor = 1.0f;
  metal.roughnessFactor = 0.2f;
  glass.metallicFactor = 0.0f;
  glass.transmissionFactor = 1.0f;
  glass.dispersion = 0.5f;
  glass.emissiveFactor = Vec3(0.5f);
  textured = plastic;
  textured.baseColorTexture.image = 0;
  textured.baseColorTexture.wrapS = textured.baseColorTexture.wrapT = WrapMode::ClampToEdge;
  brokenTexture = plastic;
  brokenTexture.baseColorTexture.image = 7;  // no such image: the factor alone, as without one
  scene.materials = {plastic, metal, glass, textured, brokenTexture};
  EXPECT_FALSE(gltfReadsHit(scene, plastic));
  EXPECT_FALSE(gltfReadsHit(scene, brokenTexture));
  EXPECT_TRUE(gltfReadsHit(scene, textured));

  std::string error;
  const std::unique_ptr<MaterialSystem> materials = MaterialSystem::create(scene, MaterialOptions{}, error);
  ASSERT_TRUE(materials) << error;
  // glTF textures are looked up without a footprint: the path tracer must not pay two extra
  // camera rays per path for it.
  for (size_t m = 0; m < scene.materials.size(); ++m) EXPECT_FALSE(materials->readsPixelFootprint(int(m))) << m;
  CompiledGltf direct;
  ASSERT_TRUE(compileGltfMaterial(4, false, false, direct, error)) << error;
  EXPECT_TRUE(direct.hitIndependent);  // std.gltf reads only its inputs
  const Wavelengths groups[2] = {color::sampleWavelengthGroup(0.3f, 4), color::sampleWavelengthGroup(0.7f, 4)};
  const ShadingPoint points[2] = {pointAt(0.25f, 0.5f, 0.1f), pointAt(0.75f, 0.5f, 0.9f)};
  int texturedDifferences = 0;
  for (int round = 0; round < 3; ++round) {
    const Wavelengths& lambda = groups[round % 2];
    for (size_t m = 0; m < scene.materials.size(); ++m) {
      Bsdf first;
      for (const ShadingPoint& p : points) {
        Bsdf viaSystem(Frame(), Vec3(0, 0, 1)), fresh(Frame(), Vec3(0, 0, 1));
        Spectrum eSystem, eFresh;
        ASSERT_TRUE(materials->shade(int(m), p, lambda, viaSystem, eSystem));
        const GltfInputs in = gltfInputs(scene, scene.materials[m], p);
        const auto args = in.words();
        ASSERT_TRUE(evaluateEntry(direct.entry, args.data(), kGltfArgumentWords, p, lambda, &fresh, eFresh).ok);
        EXPECT_TRUE(sameLobeParameters(viaSystem, fresh)) << "material " << m << " round " << round;
        EXPECT_EQ(viaSystem.hasCoat(), fresh.hasCoat());
        EXPECT_TRUE(sameBits(eSystem, eFresh)) << "material " << m << " round " << round;
        if (&p == &points[0]) first.copyLobesFrom(fresh);
        else if (m == 3 && !sameLobeParameters(first, fresh)) ++texturedDifferences;
      }
    }
  }
  EXPECT_EQ(texturedDifferences, 3);  // so a stale replay of the textured material would be caught
}

// glTF 2.0's COLOR_0 multiplies the base colour (and a texture with texCoord 1 reads the second
// uv set), so a material without textures on a mesh with vertex colours differs from hit to hit:
// it must not replay from the memo. Its evaluations through the system equal fresh ones at
// points of different colours, and those differ from each other.
TEST(MaterialMemo, GltfVertexColoursAndSecondUvSetReachShading) {
  SceneDescription scene;
  scene.images.push_back(redThenBlue());
  GltfMaterial plastic;
  plastic.baseColorFactor = Vec4(0.8f, 0.6f, 0.4f, 1.0f);
  plastic.metallicFactor = 0.0f;
  plastic.roughnessFactor = 0.5f;
  GltfMaterial secondSet = plastic;
  secondSet.baseColorTexture.image = 0;
  secondSet.baseColorTexture.texCoord = 1;
  secondSet.baseColorTexture.wrapS = secondSet.baseColorTexture.wrapT = WrapMode::ClampToEdge;
  scene.materials = {plastic, secondSet};
  MeshPrimitive coloured;
  coloured.positions = {Vec3(0.0f), Vec3(1.0f, 0.0f, 0.0f), Vec3(0.0f, 1.0f, 0.0f)};
  coloured.indices = {0, 1, 2};
  coloured.colors = {Vec4(1.0f), Vec4(0.2f, 0.5f, 1.0f, 1.0f), Vec4(1.0f)};
  coloured.material = 0;
  scene.primitives.push_back(coloured);

  ShadingPoint white = pointAt(0.25f, 0.5f, 0.1f), tinted = pointAt(0.25f, 0.5f, 0.9f);
  tinted.color = Vec4(0.2f, 0.5f, 1.0f, 1.0f);
  const GltfInputs plain = gltfInputs(scene, plastic, white), tint = gltfInputs(scene, plastic, tinted);
  EXPECT_EQ(plain.baseColor, Vec3(0.8f, 0.6f, 0.4f));
  EXPECT_EQ(tint.baseColor, Vec3(0.8f, 0.6f, 0.4f) * Vec3(0.2f, 0.5f, 1.0f));
  // texCoord 1: the texel at uv1, whatever uv (TEXCOORD_0) says.
  ShadingPoint left = white, right = white;
  left.uv1 = Vec2(0.25f, 0.5f);
  right.uv1 = Vec2(0.75f, 0.5f);
  right.uv = left.uv;
  EXPECT_GT(gltfInputs(scene, secondSet, left).baseColor.x, gltfInputs(scene, secondSet, left).baseColor.z);
  EXPECT_LT(gltfInputs(scene, secondSet, right).baseColor.x, gltfInputs(scene, secondSet, right).baseColor.z);

  std::string error;
  const std::unique_ptr<MaterialSystem> materials = MaterialSystem::create(scene, MaterialOptions{}, error);
  ASSERT_TRUE(materials) << error;
  CompiledGltf direct;
  ASSERT_TRUE(compileGltfMaterial(4, false, false, direct, error)) << error;
  const Wavelengths lambda = color::sampleWavelengthGroup(0.4f, 4);
  Bsdf previous;
  for (int round = 0; round < 4; ++round) {
    const ShadingPoint& p = round % 2 ? tinted : white;
    Bsdf viaSystem(Frame(), Vec3(0, 0, 1)), fresh(Frame(), Vec3(0, 0, 1));
    Spectrum eSystem, eFresh;
    ASSERT_TRUE(materials->shade(materials->materialOfPrimitive(0), p, lambda, viaSystem, eSystem));
    const GltfInputs in = gltfInputs(scene, plastic, p);
    const auto args = in.words();
    ASSERT_TRUE(evaluateEntry(direct.entry, args.data(), kGltfArgumentWords, p, lambda, &fresh, eFresh).ok);
    EXPECT_TRUE(sameLobeParameters(viaSystem, fresh)) << "round " << round;
    if (round > 0) {
      EXPECT_FALSE(sameLobeParameters(previous, fresh)) << "round " << round;
    }
    previous.copyLobesFrom(fresh);
  }
}

}  // namespace
}  // namespace tex::render
