// KHR_materials_anisotropy: the loader reads strength, rotation and texture (defaults, clamps
// and warnings), gltfAnisotropyInto turns the direction (rotation and texture RG, strength x B)
// from glTF's tangent frame into the shading frame, and std.gltf gives the metal and the
// dielectric's specular the extension's alphas: none at strength 0 (bit for bit), a highlight
// stretched along the direction otherwise, and no energy gained.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "renderer/material/closure_lobes.h"
#include "renderer/material/gltf_material.h"
#include "renderer/material/tex_binding.h"
#include "renderer/sampling/pcg.h"
#include "renderer/scene/gltf_loader.h"
#include "tests/renderer/gltf_entry.h"
#include "tests/renderer/gltf_extension_loading.h"

namespace tex::render {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr int kWavelengths = test::kGltfEntryWavelengths;
using test::flatPoint;
using test::gltfEntry;

Bsdf shade(const GltfInputs& in) {
  static const Wavelengths lambda = color::sampleWavelengthGroup(0.3f, kWavelengths);
  Bsdf bsdf(Frame(), Vec3(0, 0, 1));
  Spectrum emission;
  const auto words = in.words();
  EXPECT_TRUE(evaluateEntry(gltfEntry().entry, words.data(), kGltfArgumentWords, flatPoint(), lambda, &bsdf, emission).ok);
  return bsdf;
}

GltfInputs metal(float roughness) {
  GltfInputs in;
  in.baseColor = Vec3(0.95f, 0.93f, 0.88f);
  in.metallic = 1.0f;
  in.roughness = roughness;
  return in;
}

Vec3 tilted(float thetaRad, float phiRad) {
  return Vec3(std::sin(thetaRad) * std::cos(phiRad), std::sin(thetaRad) * std::sin(phiRad), std::cos(thetaRad));
}

// ---- loading -----------------------------------------------------------------------------

class GltfAnisotropyLoading : public test::GltfExtensionLoading {
 protected:
  std::optional<SceneDescription> load(const json& extension, std::vector<std::string>& errors) {
    return loadWithExtensions({{"KHR_materials_anisotropy", extension}}, errors, "aniso.gltf");
  }
};

TEST_F(GltfAnisotropyLoading, ReadsStrengthRotationAndTexture) {
  std::vector<std::string> errors;
  const auto scene = load({{"anisotropyStrength", 0.6}, {"anisotropyRotation", 1.25}, {"anisotropyTexture", {{"index", 0}}}},
                          errors);
  ASSERT_TRUE(scene) << (errors.empty() ? "" : errors[0]);
  const GltfMaterial& g = scene->materials[0];
  EXPECT_EQ(g.anisotropyStrength, 0.6f);
  EXPECT_EQ(g.anisotropyRotationRad, 1.25f);
  EXPECT_FALSE(anyContains(scene->warnings, "not supported"));
  // The quad has no textures: the reference is read, warned about and ignored.
  EXPECT_TRUE(anyContains(scene->warnings, "anisotropyTexture uses texture 0, which does not exist"));
}

TEST_F(GltfAnisotropyLoading, DefaultsAreNoAnisotropy) {
  std::vector<std::string> errors;
  const auto scene = load(json::object(), errors);
  ASSERT_TRUE(scene) << (errors.empty() ? "" : errors[0]);
  const GltfMaterial& g = scene->materials[0];
  EXPECT_EQ(g.anisotropyStrength, 0.0f);
  EXPECT_EQ(g.anisotropyRotationRad, 0.0f);
  EXPECT_LT(g.anisotropyTexture.image, 0);
  EXPECT_TRUE(scene->warnings.empty()) << scene->warnings[0];
}

TEST_F(GltfAnisotropyLoading, BadValuesAreClampedOrIgnoredWithWarningsNamingThem) {
  std::vector<std::string> errors;
  auto scene = load({{"anisotropyStrength", 1.5}, {"anisotropyRotation", "north"}, {"anisotropyTexture", {{"texCoord", 0}}}},
                    errors);
  ASSERT_TRUE(scene) << (errors.empty() ? "" : errors[0]);
  EXPECT_EQ(scene->materials[0].anisotropyStrength, 1.0f);
  EXPECT_EQ(scene->materials[0].anisotropyRotationRad, 0.0f);
  EXPECT_LT(scene->materials[0].anisotropyTexture.image, 0);
  for (const char* what : {"KHR_materials_anisotropy: anisotropyStrength 1.5", "anisotropyRotation is not a number",
                           "anisotropyTexture has no integer index"})
    EXPECT_TRUE(anyContains(scene->warnings, what)) << what;
  scene = load({{"anisotropyStrength", -0.5}}, errors);
  ASSERT_TRUE(scene);
  EXPECT_EQ(scene->materials[0].anisotropyStrength, 0.0f);
  EXPECT_TRUE(anyContains(scene->warnings, "anisotropyStrength -0.5"));
}

// ---- inputs ------------------------------------------------------------------------------

TEST(GltfAnisotropy, DirectionIsRotationPlusTextureInTheTangentFrameAndStrengthTimesBlue) {
  SceneDescription scene;
  ImageData image;  // direction at 60 degrees, strength 0.5 (linear: a data texture)
  image.width = image.height = 1;
  image.channels = 4;
  const float texAngle = 1.0471976f;
  image.pixels = {0.5f + 0.5f * std::cos(texAngle), 0.5f + 0.5f * std::sin(texAngle), 0.5f, 1.0f};
  scene.images.push_back(image);
  GltfMaterial m;
  m.anisotropyStrength = 0.8f;
  m.anisotropyRotationRad = 0.25f;
  ShadingPoint p = flatPoint();
  p.tangent = Vec4(1, 0, 0, 1);  // bitangent = cross(n, t) = +y: glTF's frame is the shading frame
  GltfInputs in;
  gltfAnisotropyInto(scene, m, p, Frame(), in);
  EXPECT_FLOAT_EQ(in.anisotropyStrength, 0.8f);  // no texture: direction (1, 0), strength 1
  EXPECT_NEAR(in.anisotropyRotationRad, 0.25f, 1e-6f);
  m.anisotropyTexture.image = 0;
  gltfAnisotropyInto(scene, m, p, Frame(), in);
  EXPECT_NEAR(in.anisotropyStrength, 0.4f, 1e-6f);
  EXPECT_NEAR(in.anisotropyRotationRad, 0.25f + texAngle, 2e-3f);  // 8-bit-free float texel: only rounding
  // Without a TANGENT the bitangent follows decreasing v (-y here): the angle turns the other way.
  p.tangent = Vec4(0.0f);
  gltfAnisotropyInto(scene, m, p, Frame(), in);
  EXPECT_NEAR(in.anisotropyRotationRad, -(0.25f + texAngle), 2e-3f);
  // A shading frame whose x axis is glTF's bitangent: the angle is measured from there.
  p.tangent = Vec4(1, 0, 0, 1);
  gltfAnisotropyInto(scene, m, p, Frame::fromNormalTangent(Vec3(0, 0, 1), Vec3(0, 1, 0)), in);
  EXPECT_NEAR(in.anisotropyRotationRad, 0.25f + texAngle - 1.5707963f, 2e-3f);
  // The texture's KHR_texture_transform turns the frame its texels' directions are in, as a
  // normal map's: a rotation by 0.5 turns the texture's tangent to -0.5 here (uv' = R uv), and a
  // mirroring scale mirrors the texel's angle; anisotropyRotation stays in the mesh's frame.
  p.tangent = Vec4(1, 0, 0, 1);
  m.anisotropyTexture.rotation = 0.5f;
  gltfAnisotropyInto(scene, m, p, Frame(), in);
  EXPECT_NEAR(in.anisotropyRotationRad, 0.25f + texAngle - 0.5f, 2e-3f);
  m.anisotropyTexture.rotation = 0.0f;
  m.anisotropyTexture.scale = Vec2(-1.0f, 1.0f);
  gltfAnisotropyInto(scene, m, p, Frame(), in);
  EXPECT_NEAR(in.anisotropyRotationRad, 0.25f + 3.14159265f - texAngle, 2e-3f);
  m.anisotropyTexture.scale = Vec2(1.0f);
  EXPECT_TRUE(gltfReadsHit(scene, m));  // the direction depends on each point's frame
  m.anisotropyStrength = 0.0f;
  GltfInputs none;
  gltfAnisotropyInto(scene, m, p, Frame(), none);
  EXPECT_EQ(none.anisotropyStrength, 0.0f);
}

// ---- shading -----------------------------------------------------------------------------

TEST(GltfAnisotropy, ZeroStrengthIsTheIsotropicMaterialBitForBit) {
  for (GltfInputs in : {metal(0.4f), metal(0.0f)}) {
    for (float metallic : {0.0f, 1.0f}) {
      in.metallic = metallic;
      GltfInputs turned = in;
      turned.anisotropyRotationRad = 0.7f;  // no strength: the rotation does nothing
      const Bsdf a = shade(in), b = shade(turned);
      for (float t : {0.1f, 0.6f, 1.2f}) {
        const Vec3 wo = tilted(0.5f, 0.2f), wi = tilted(t, 2.0f);
        const Spectrum fa = a.eval(wo, wi, TransportMode::Radiance), fb = b.eval(wo, wi, TransportMode::Radiance);
        for (int lane = 0; lane < kWavelengths; ++lane) EXPECT_EQ(fa[lane], fb[lane]);
      }
    }
  }
}

TEST(GltfAnisotropy, TheHighlightStretchesAlongTheDirectionForMetalAndPlastic) {
  // alpha_t = mix(alpha, 1, s^2) along the direction, alpha_b = alpha across: seen from the
  // normal, light 25 degrees off along the direction reflects more than 25 degrees across it.
  for (float metallic : {1.0f, 0.0f}) {
    for (float rotation : {0.0f, 1.5707963f}) {
      GltfInputs in = metal(0.3f);
      in.metallic = metallic;
      in.anisotropyStrength = 0.8f;
      in.anisotropyRotationRad = rotation;
      const Bsdf bsdf = shade(in);
      const Vec3 wo(0, 0, 1);
      const float alongX = bsdf.eval(wo, tilted(0.44f, 0.0f), TransportMode::Radiance)[0];
      const float alongY = bsdf.eval(wo, tilted(0.44f, 1.5707963f), TransportMode::Radiance)[0];
      // The plastic's diffuse base (about 0.29 either way) dilutes its coat's difference.
      const float ratio = metallic > 0.0f ? 2.0f : 1.1f;
      if (rotation == 0.0f) {
        EXPECT_GT(alongX, ratio * alongY) << metallic;
      } else {
        EXPECT_GT(alongY, ratio * alongX) << metallic;
      }
    }
  }
}

TEST(GltfAnisotropy, AnisotropicMaterialsGainNoEnergyAndSampleWhatTheyEvaluate) {
  for (float metallic : {1.0f, 0.0f}) {
    GltfInputs in = metal(0.5f);
    in.metallic = metallic;
    in.baseColor = Vec3(1.0f);
    in.anisotropyStrength = 1.0f;
    in.anisotropyRotationRad = 0.4f;
    const Bsdf bsdf = shade(in);
    for (float theta : {0.0f, 0.8f, 1.3f}) {
      const Vec3 wo = tilted(theta, 1.0f);
      sampling::Pcg32 rng(3, 1);
      double sum = 0;
      const int n = 100000;
      for (int i = 0; i < n; ++i) {
        const auto s = bsdf.sample(wo, rng.nextFloat(), Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Importance);
        if (!s || !(s->pdfW > 0.0f)) continue;
        if (!s->specular && i % 97 == 0) {
          float pdfW = 0.0f;
          const Spectrum f = bsdf.evalWithPdf(wo, s->wi, TransportMode::Importance, pdfW);
          ASSERT_NEAR(f[0], s->f[0], 1e-4f * std::max(1.0f, f[0]));
          ASSERT_NEAR(pdfW, s->pdfW, 1e-4f * std::max(1.0f, pdfW));
        }
        sum += double(s->f[0]) * std::fabs(s->wi.z) / s->pdfW;
      }
      std::printf("  glTF anisotropic %s, strength 1, theta %.1f: albedo %.4f\n", metallic > 0 ? "metal" : "plastic", theta,
                  sum / n);
      EXPECT_LE(sum / n, 1.0 + 0.01) << metallic << " " << theta;
    }
  }
}

}  // namespace
}  // namespace tex::render
