// Compiled .tex materials walked into native lobes (renderer/material/closure_lobes.cpp): every
// closure kind maps to the lobe and parameters the ABI promises, mix/scale weights multiply
// down the tree, layers put their base under the Bsdf's coat, and bad trees fail cleanly.
#include <gtest/gtest.h>

#include "renderer/bsdf/microfacet.h"

#include <chrono>
#include <filesystem>
#include <fstream>


#include "lang/interpreter.h"
#include "lang/session.h"
#include "renderer/material/closure_lobes.h"
#include "renderer/material/gltf_material.h"
#include "renderer/material/tex_binding.h"
#include "renderer/sampling/pcg.h"
#include "tests/renderer/scene_fixtures.h"

namespace tex::render {
namespace {

struct Compiled {
  CompiledBindings bindings;
  std::string error;
};

Compiled compileEntries(const std::string& source, const std::vector<std::string>& entries) {
  const std::string file = test::writeTexModule("mats", source);
  SceneDescription scene;
  test::bindEntriesByMaterialName(scene, file, entries);
  Compiled c;
  EXPECT_TRUE(compileBindings(scene, 4, false, false, c.bindings, c.error)) << c.error;
  return c;
}

struct Shaded {
  Bsdf bsdf{Frame(), Vec3(0, 0, 1)};
  Spectrum emission;
  ClosureEvaluation result;
};

Shaded shade(const CompiledBinding& b) {
  Shaded s;
  ShadingPoint p;
  p.p = Vec3(0.1f, 0.2f, 0.3f);
  p.ng = p.ns = Vec3(0, 0, 1);
  p.uv = Vec2(0.25f, 0.75f);
  const Wavelengths lambda = color::sampleWavelengthGroup(0.3f, 4);
  s.result = evaluateBinding(b, p, lambda, &s.bsdf, s.emission);
  return s;
}

TEST(ClosureLobes, EveryKindMapsToItsLobe) {
  const Compiled c = compileEntries(
      "import std.spectra.{cauchy}\n"
      "export fn rough_glass(h: Hit) -> Material = dielectric(1.5, roughness: 0.3)\n"
      "export fn flint(h: Hit) -> Material = dielectric(cauchy(1.6, 12000.0))\n"
      "export fn rough_metal(h: Hit) -> Material = conductor(spectrum(0.2), spectrum(3.0), roughness: 0.5)\n"
      "export fn pane(h: Hit) -> Material = thin_dielectric(1.5)\n"
      "export fn shiny(h: Hit) -> Material = glossy(spectrum(0.9), 1000.0)\n"
      "export fn prism(h: Hit) -> Material = glossy_dielectric(cauchy(1.5, 8000.0), 4000.0)\n"
      "export fn plastic(h: Hit) -> Material = layer(dielectric(1.5), diffuse(spectrum(0.5)))\n"
      "export fn scaled(h: Hit) -> Material = scale_material(add_material(diffuse(spectrum(0.5)), emission(spectrum(2.0))), 0.5)\n"
      "export fn frosted(h: Hit) -> Material = thin_dielectric(cauchy(1.5, 8000.0), roughness: 0.25)\n",
      {"rough_glass", "flint", "rough_metal", "pane", "shiny", "prism", "plastic", "scaled", "frosted"});
  ASSERT_EQ(c.bindings.bindings.size(), 9u);
  const auto& b = c.bindings.bindings;

  Shaded s = shade(b[0]);
  ASSERT_TRUE(s.result.ok);
  ASSERT_EQ(s.bsdf.lobeCount(), 1);
  EXPECT_EQ(s.bsdf.lobe(0).kind, LobeKind::RoughDielectric);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(0).roughness, 0.3f);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(0).a.v[2], 1.5f);
  EXPECT_FALSE(s.bsdf.lobe(0).etaVaries);

  s = shade(b[1]);
  ASSERT_EQ(s.bsdf.lobeCount(), 1);
  EXPECT_EQ(s.bsdf.lobe(0).kind, LobeKind::SmoothDielectric);
  EXPECT_TRUE(s.bsdf.lobe(0).etaVaries);
  EXPECT_NE(s.bsdf.lobe(0).a.v[0], s.bsdf.lobe(0).a.v[1]);

  s = shade(b[2]);
  ASSERT_EQ(s.bsdf.lobeCount(), 1);
  EXPECT_EQ(s.bsdf.lobe(0).kind, LobeKind::RoughConductor);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(0).b.v[1], 3.0f);

  s = shade(b[3]);
  ASSERT_EQ(s.bsdf.lobeCount(), 1);
  EXPECT_EQ(s.bsdf.lobe(0).kind, LobeKind::ThinDielectric);

  // A rough wall of a varying IOR: its lanes keep their own IORs (each its own R'), and the
  // Bsdf has no dispersive density (the wall bends nothing).
  s = shade(b[8]);
  ASSERT_TRUE(s.result.ok);
  ASSERT_EQ(s.bsdf.lobeCount(), 1);
  EXPECT_EQ(s.bsdf.lobe(0).kind, LobeKind::RoughThinDielectric);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(0).roughness, 0.25f);
  EXPECT_TRUE(s.bsdf.lobe(0).etaVaries);
  EXPECT_NE(s.bsdf.lobe(0).a.v[0], s.bsdf.lobe(0).a.v[1]);
  EXPECT_FALSE(s.bsdf.hasDispersiveDensity());

  s = shade(b[4]);
  ASSERT_EQ(s.bsdf.lobeCount(), 1);
  EXPECT_EQ(s.bsdf.lobe(0).kind, LobeKind::GlossyReflection);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(0).exponent, 1000.0f);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(0).weight.v[3], 0.9f);

  s = shade(b[5]);
  ASSERT_EQ(s.bsdf.lobeCount(), 1);
  EXPECT_EQ(s.bsdf.lobe(0).kind, LobeKind::GlossyDielectric);
  EXPECT_TRUE(s.bsdf.lobe(0).etaVaries);

  s = shade(b[6]);
  ASSERT_TRUE(s.result.ok);
  ASSERT_TRUE(s.bsdf.hasCoat());
  EXPECT_EQ(s.bsdf.coat().kind, LobeKind::SmoothDielectric);
  ASSERT_EQ(s.bsdf.lobeCount(), 1);
  EXPECT_EQ(s.bsdf.lobe(0).kind, LobeKind::Lambertian);
  EXPECT_TRUE(s.bsdf.lobe(0).underCoat);

  s = shade(b[7]);
  ASSERT_EQ(s.bsdf.lobeCount(), 1);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(0).weight.v[0], 0.25f);  // 0.5 albedo x 0.5 scale
  EXPECT_FLOAT_EQ(s.emission.v[0], 1.0f);               // 2.0 x 0.5
  EXPECT_TRUE(s.result.sawEmission);
}

// A closure tree shares nodes (add_material(m, m) refers to m twice): 30 such levels are 31
// nodes but 2^30 paths, which the walk had followed one by one (a render hung at its first
// hit). It gives up after a budget of visits, as a counted failure.
TEST(ClosureLobes, SharedSubtreesAreWalkedWithinABudget) {
  const Compiled c = compileEntries(
      "export fn doubling(h: Hit) -> Material = fold(30, diffuse(spectrum(0.5)), |m, i| add_material(m, m))\n"
      "export fn twice(h: Hit) -> Material { let m = diffuse(spectrum(0.25)); add_material(m, m) }\n",
      {"doubling", "twice"});
  ASSERT_EQ(c.bindings.bindings.size(), 2u);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(shade(c.bindings.bindings[0]).result.ok);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  const Shaded s = shade(c.bindings.bindings[1]);  // sharing itself is fine
  ASSERT_TRUE(s.result.ok);
  EXPECT_EQ(s.bsdf.lobeCount(), 2);
}

// A coat of a wavelength-dependent IOR reflects each lane's own Fresnel reflectance (it had
// reflected the hero's in every lane: a dispersive coat's colour blurred across the group).
TEST(ClosureLobes, DispersiveCoatsReflectEachLanesOwnFresnel) {
  const Compiled c = compileEntries(
      "import std.spectra.{cauchy}\n"
      "export fn coated(h: Hit) -> Material = layer(dielectric(cauchy(1.5, 40000.0)), diffuse(spectrum(0.5)))\n",
      {"coated"});
  ASSERT_EQ(c.bindings.bindings.size(), 1u);
  Shaded s = shade(c.bindings.bindings[0]);
  ASSERT_TRUE(s.result.ok);
  ASSERT_TRUE(s.bsdf.hasCoat());
  const Lobe& coat = s.bsdf.coat();
  EXPECT_TRUE(coat.etaVaries);
  const Vec3 wo = glm::normalize(Vec3(0.3f, 0.1f, 1.0f));
  const auto sample = s.bsdf.sample(wo, 0.999f, Vec2(0.5f), TransportMode::Radiance);  // the coat comes last
  ASSERT_TRUE(sample && sample->specular);
  const float cosO = wo.z;
  for (int k = 1; k < 4; ++k) {
    ASSERT_NE(coat.a.v[k], coat.a.v[0]);
    const float expected = fresnelDielectric(cosO, coat.a.v[k]) / fresnelDielectric(cosO, coat.a.v[0]);
    EXPECT_NEAR(sample->f[k] / sample->f[0], expected, 1e-5f) << "lane " << k;
  }
}

TEST(ClosureLobes, MixWeightsMultiplyDownTheTree) {
  const Compiled c = compileEntries(
      "export fn m(h: Hit) -> Material = mix_material(diffuse(spectrum(1.0)), mix_material(diffuse(spectrum(1.0)), "
      "conductor(spectrum(0.2), spectrum(3.0)), 0.25), 0.5)\n",
      {"m"});
  const Shaded s = shade(c.bindings.bindings[0]);
  ASSERT_EQ(s.bsdf.lobeCount(), 3);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(0).weight.v[0], 0.5f);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(1).weight.v[0], 0.375f);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(2).weight.v[0], 0.125f);
}

// Lanes past the group's count stay zero in every lobe weight (spectrum.h), whether the weight
// comes from a colour or from a constant (a conductor's, a dielectric's, a coat's, the mix
// weights): otherwise the Bsdf's selection weights, which sum over all nonzero lanes, would
// favour constant-weighted lobes twice over in groups of 4.
TEST(ClosureLobes, LobeWeightsAreZeroPastTheGroupsLanes) {
  const Compiled c = compileEntries(
      "export fn metal_or_paint(h: Hit) -> Material =\n"
      "  mix_material(diffuse(rgb(0.8, 0.4, 0.2)), conductor(spectrum(0.2), spectrum(3.0), roughness: 0.3), 0.5)\n"
      "export fn plastic(h: Hit) -> Material = layer(dielectric(1.5, 0.2), diffuse(rgb(0.5, 0.5, 0.5)))\n"
      "export fn glass(h: Hit) -> Material = scale_material(dielectric(1.5), 0.9)\n",
      {"metal_or_paint", "plastic", "glass"});
  ASSERT_EQ(c.bindings.bindings.size(), 3u);
  for (const CompiledBinding& b : c.bindings.bindings) {
    const Shaded s = shade(b);
    ASSERT_TRUE(s.result.ok) << b.name;
    ASSERT_GT(s.bsdf.lobeCount(), 0);
    for (int i = 0; i < s.bsdf.lobeCount(); ++i) {
      const Lobe& lobe = s.bsdf.lobe(i);
      for (int lane = 0; lane < 4; ++lane) EXPECT_GT(lobe.weight.v[lane], 0.0f) << b.name << " lobe " << i;
      EXPECT_TRUE(lobe.weight.upperLanesZero()) << b.name << " lobe " << i;
    }
  }
  // The coat too.
  const Shaded plastic = shade(c.bindings.bindings[1]);
  ASSERT_TRUE(plastic.bsdf.hasCoat());
  EXPECT_TRUE(plastic.bsdf.coat().weight.upperLanesZero());
}

TEST(ClosureLobes, UnsupportedLayersFailCleanly) {
  // A coat must be a dielectric; a Bsdf holds one coat and one clearcoat over everything (a coat
  // over a layered base), so a third level, or a lobe beside a clearcoat, shades black and is
  // reported.
  const Compiled c = compileEntries(
      "export fn bad_coat(h: Hit) -> Material = layer(diffuse(spectrum(0.5)), diffuse(spectrum(0.5)))\n"
      "export fn three(h: Hit) -> Material = layer(dielectric(1.5), layer(dielectric(1.3), layer(dielectric(1.2), diffuse(spectrum(0.5)))))\n"
      "export fn beside(h: Hit) -> Material = add_material(layer(dielectric(1.5), layer(dielectric(1.3), diffuse(spectrum(0.5)))), diffuse(spectrum(0.2)))\n"
      "export fn nested(h: Hit) -> Material = layer(dielectric(1.5), layer(dielectric(1.3), diffuse(spectrum(0.5))))\n",
      {"bad_coat", "three", "beside", "nested"});
  EXPECT_FALSE(shade(c.bindings.bindings[0]).result.ok);
  EXPECT_FALSE(shade(c.bindings.bindings[1]).result.ok);
  EXPECT_FALSE(shade(c.bindings.bindings[2]).result.ok);
  const Shaded nested = shade(c.bindings.bindings[3]);
  EXPECT_TRUE(nested.result.ok);
  EXPECT_TRUE(nested.bsdf.hasClearcoat());
  EXPECT_TRUE(nested.bsdf.hasCoat());
}

// NaN or infinite colours (which the RGB fit would sanitise to 0 or 1) and mix weights (which
// skipped both branches) are failed evaluations, counted, not silently black or white.
TEST(ClosureLobes, NonFiniteColoursAndMixWeightsFail) {
  const Compiled c = compileEntries(
      "export fn nan_albedo(h: Hit) -> Material = diffuse(rgb(0.0 / 0.0, 0.5, 0.5))\n"
      "export fn inf_albedo(h: Hit) -> Material = diffuse(rgb(1.0 / 0.0, 0.5, 0.5))\n"
      "export fn nan_mix(h: Hit) -> Material = mix_material(diffuse(spectrum(0.5)), diffuse(spectrum(0.2)), 0.0 / 0.0)\n"
      "export fn nan_emission(h: Hit) -> Material = emission(rgb(0.0 / 0.0, 1.0, 1.0))\n"
      // Scalars too: a NaN roughness rendered as the smooth lobe and a NaN glossy exponent black,
      // both uncounted.
      "export fn nan_rough_metal(h: Hit) -> Material = conductor(0.2, 3.0, 0.0 / 0.0)\n"
      "export fn nan_rough_glass(h: Hit) -> Material = dielectric(1.5, 0.0 / 0.0)\n"
      "export fn nan_rough_coat(h: Hit) -> Material = layer(dielectric(1.5, 0.0 / 0.0), diffuse(spectrum(0.5)))\n"
      "export fn nan_glossy(h: Hit) -> Material = glossy(1.0, 0.0 / 0.0)\n"
      "export fn inf_glossy_dielectric(h: Hit) -> Material = glossy_dielectric(1.5, 1.0 / 0.0)\n"
      "export fn nan_sheen(h: Hit) -> Material = sheen(rgb(0.5, 0.5, 0.5), 0.0 / 0.0)\n"
      "export fn nan_thin(h: Hit) -> Material = thin_dielectric(1.5, 0.0 / 0.0)\n"
      "export fn fine(h: Hit) -> Material = mix_material(diffuse(rgb(0.5, 0.4, 0.3)), emission(rgb(1.0, 2.0, 3.0)), 0.5)\n",
      {"nan_albedo", "inf_albedo", "nan_mix", "nan_emission", "nan_rough_metal", "nan_rough_glass", "nan_rough_coat",
       "nan_glossy", "inf_glossy_dielectric", "nan_sheen", "nan_thin", "fine"});
  ASSERT_EQ(c.bindings.bindings.size(), 12u);
  for (int i = 0; i < 11; ++i) EXPECT_FALSE(shade(c.bindings.bindings[size_t(i)]).result.ok) << i;
  EXPECT_TRUE(shade(c.bindings.bindings[11]).result.ok);
}


// A glossy exponent beyond 1e15 is 1e15 (a mirror for every purpose): glossy_dielectric had lost
// its whole transmission at n = 1e19 (0.023 where the smooth dielectric gives 0.559).
TEST(ClosureLobes, HugeGlossyExponentsAreHeldAtAMirrorsValue) {
  const Compiled c = compileEntries(
      "export fn m(h: Hit) -> Material = glossy_dielectric(1.35, 1.0e19)\n"
      "export fn g(h: Hit) -> Material = glossy(spectrum(1.0), 1.0e30)\n",
      {"m", "g"});
  for (const CompiledBinding& b : c.bindings.bindings) {
    const Shaded s = shade(b);
    ASSERT_TRUE(s.result.ok);
    ASSERT_EQ(s.bsdf.lobeCount(), 1);
    EXPECT_EQ(s.bsdf.lobe(0).exponent, 1e15f);
  }
}

// A Vec2 roughness reaches the lobes as two alphas and a rotation (the conductor, the rough
// glass, and a layer's coat); both alphas below 1e-3 are the smooth lobe; one below 1e-3 is
// raised to kMinGgxAlpha beside a rough other; a NaN rotation is a counted failure.
TEST(ClosureLobes, AnisotropicRoughnessMapsToTwoAlphasAndARotation) {
  const Compiled c = compileEntries(
      "export fn metal(h: Hit) -> Material = conductor(spectrum(0.2), spectrum(3.0), vec2(0.4, 0.05), 0.5)\n"
      "export fn glass(h: Hit) -> Material = dielectric(1.5, vec2(0.1, 2.0), rotation: -1.0)\n"
      "export fn coat(h: Hit) -> Material = layer(dielectric(1.5, vec2(0.3, 0.2)), diffuse(spectrum(0.5)))\n"
      "export fn mirror(h: Hit) -> Material = conductor(spectrum(0.2), spectrum(3.0), vec2(0.0005, 0.0))\n"
      "export fn groove(h: Hit) -> Material = conductor(spectrum(0.2), spectrum(3.0), vec2(0.0, 0.3))\n"
      "export fn bad(h: Hit) -> Material = conductor(spectrum(0.2), spectrum(3.0), vec2(0.3, 0.1), nan)\n",
      {"metal", "glass", "coat", "mirror", "groove", "bad"});
  const auto& b = c.bindings.bindings;
  ASSERT_EQ(b.size(), 6u);
  Shaded s = shade(b[0]);
  ASSERT_TRUE(s.result.ok);
  ASSERT_EQ(s.bsdf.lobeCount(), 1);
  EXPECT_EQ(s.bsdf.lobe(0).kind, LobeKind::RoughConductor);
  EXPECT_EQ(s.bsdf.lobe(0).roughness, 0.4f);
  EXPECT_EQ(s.bsdf.lobe(0).roughnessY, 0.05f);
  EXPECT_EQ(s.bsdf.lobe(0).anisotropyRotationRad, 0.5f);
  s = shade(b[1]);
  EXPECT_EQ(s.bsdf.lobe(0).kind, LobeKind::RoughDielectric);
  EXPECT_EQ(s.bsdf.lobe(0).roughness, 0.1f);
  EXPECT_EQ(s.bsdf.lobe(0).roughnessY, 1.0f);  // clamped as a Float roughness is
  EXPECT_EQ(s.bsdf.lobe(0).anisotropyRotationRad, -1.0f);
  s = shade(b[2]);
  ASSERT_TRUE(s.bsdf.hasCoat());
  EXPECT_EQ(s.bsdf.coat().kind, LobeKind::RoughDielectric);
  EXPECT_EQ(s.bsdf.coat().roughness, 0.3f);
  EXPECT_EQ(s.bsdf.coat().roughnessY, 0.2f);
  s = shade(b[3]);
  EXPECT_EQ(s.bsdf.lobe(0).kind, LobeKind::SmoothConductor);
  s = shade(b[4]);
  EXPECT_EQ(s.bsdf.lobe(0).kind, LobeKind::RoughConductor);
  EXPECT_EQ(s.bsdf.lobe(0).roughness, kMinGgxAlpha);
  EXPECT_EQ(s.bsdf.lobe(0).roughnessY, 0.3f);
  s = shade(b[5]);
  EXPECT_FALSE(s.result.ok);
}

TEST(ClosureLobes, GlossyCoatLayersAsTheMatchingGgxCoat) {
  const Compiled c = compileEntries(
      "export fn m(h: Hit) -> Material = layer(glossy_dielectric(1.5, 98.0), diffuse(spectrum(0.5)))\n", {"m"});
  const Shaded s = shade(c.bindings.bindings[0]);
  ASSERT_TRUE(s.result.ok);
  ASSERT_TRUE(s.bsdf.hasCoat());
  EXPECT_EQ(s.bsdf.coat().kind, LobeKind::RoughDielectric);
  EXPECT_FLOAT_EQ(s.bsdf.coat().roughness, std::sqrt(2.0f / 100.0f));
  EXPECT_TRUE(s.bsdf.lobe(0).underCoat);
}


TEST(ClosureLobes, SheenMapsToItsLobeAndCoatsLambertianBases) {
  const Compiled c = compileEntries(
      "export fn cloth(h: Hit) -> Material = sheen(spectrum(0.7), 0.4)\n"
      "export fn clamped(h: Hit) -> Material = sheen(spectrum(0.7), 0.0)\n"
      "export fn velvet(h: Hit) -> Material =\n"
      "  layer(sheen(spectrum(0.6), 0.3), mix_material(diffuse(spectrum(0.5)), diffuse(spectrum(0.3)), 0.5))\n"
      "export fn coated(h: Hit) -> Material = layer(dielectric(1.5), layer(sheen(spectrum(0.6), 0.3), diffuse(spectrum(0.5))))\n"
      "export fn tinted(h: Hit) -> Material = layer(sheen(rgb(0.9, 0.3, 0.1), 0.5), diffuse(spectrum(0.5)))\n",
      {"cloth", "clamped", "velvet", "coated", "tinted"});
  ASSERT_EQ(c.bindings.bindings.size(), 5u);
  const auto& b = c.bindings.bindings;

  Shaded s = shade(b[0]);
  ASSERT_TRUE(s.result.ok);
  ASSERT_EQ(s.bsdf.lobeCount(), 1);
  EXPECT_EQ(s.bsdf.lobe(0).kind, LobeKind::Sheen);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(0).roughness, 0.4f);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(0).weight.v[2], 0.7f);
  EXPECT_TRUE(s.bsdf.hasNonSpecular());

  s = shade(b[1]);
  ASSERT_EQ(s.bsdf.lobeCount(), 1);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(0).roughness, 0.01f);  // clamped to the model's range

  // The sheen, then each diffuse base as a Lambertian under it, carrying its colour and alpha.
  s = shade(b[2]);
  ASSERT_TRUE(s.result.ok);
  EXPECT_FALSE(s.bsdf.hasCoat());
  ASSERT_EQ(s.bsdf.lobeCount(), 3);
  EXPECT_EQ(s.bsdf.lobe(0).kind, LobeKind::Sheen);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(0).weight.v[0], 0.6f);
  for (int i = 1; i < 3; ++i) {
    EXPECT_EQ(s.bsdf.lobe(i).kind, LobeKind::LambertianUnderSheen);
    EXPECT_FLOAT_EQ(s.bsdf.lobe(i).a.v[1], 0.6f);
    EXPECT_FLOAT_EQ(s.bsdf.lobe(i).roughness, 0.3f);
  }
  EXPECT_FLOAT_EQ(s.bsdf.lobe(1).weight.v[0], 0.25f);
  EXPECT_FLOAT_EQ(s.bsdf.lobe(2).weight.v[0], 0.15f);

  // Under a dielectric coat, both sheen lobes are coated.
  s = shade(b[3]);
  ASSERT_TRUE(s.result.ok);
  ASSERT_TRUE(s.bsdf.hasCoat());
  ASSERT_EQ(s.bsdf.lobeCount(), 2);
  EXPECT_TRUE(s.bsdf.lobe(0).underCoat && s.bsdf.lobe(1).underCoat);
  EXPECT_EQ(s.bsdf.lobe(1).kind, LobeKind::LambertianUnderSheen);

  // A Color sheen is upsampled as a reflectance; the base's scaling uses the same spectrum.
  s = shade(b[4]);
  ASSERT_EQ(s.bsdf.lobeCount(), 2);
  for (int i = 0; i < 4; ++i) {
    EXPECT_GT(s.bsdf.lobe(0).weight.v[i], 0.0f);
    EXPECT_LE(s.bsdf.lobe(0).weight.v[i], 1.0f);
    EXPECT_FLOAT_EQ(s.bsdf.lobe(1).a.v[i], s.bsdf.lobe(0).weight.v[i]);
  }
  EXPECT_NE(s.bsdf.lobe(0).weight.v[0], s.bsdf.lobe(0).weight.v[3]);
}

// glTF metals through std.gltf: a black or nearly black metal keeps the rim glTF's Schlick form
// gives it (Gulbrandsen's fit with edge tint r is an index-matched interface at r = 0, which had
// reflected nothing at any angle), and KHR_materials_ior's ior 0 is a Fresnel of 1 (a mirror;
// it had been read as 1.5 on opaque surfaces and as no interface at all on glass).
TEST(ClosureLobes, GltfDarkMetalsKeepTheirRimAndIorZeroIsAMirror) {
  const Compiled c = compileEntries(
      "import std.gltf.{metallic_roughness}\n"
      "export fn black_metal(h: Hit) -> Material = metallic_roughness(h, rgb(0.0, 0.0, 0.0), 1.0, 0.0, 0.0, 1.5, 0.0, rgb(0.0, 0.0, 0.0))\n"
      "export fn dark_metal(h: Hit) -> Material = metallic_roughness(h, rgb(0.01, 0.01, 0.01), 1.0, 0.0, 0.0, 1.5, 0.0, rgb(0.0, 0.0, 0.0))\n"
      "export fn mirror(h: Hit) -> Material = metallic_roughness(h, rgb(0.3, 0.3, 0.3), 0.0, 0.0, 0.0, 0.0, 0.0, rgb(0.0, 0.0, 0.0))\n"
      "export fn mirror_glass(h: Hit) -> Material = metallic_roughness(h, rgb(1.0, 1.0, 1.0), 0.0, 0.0, 1.0, 0.0, 0.0, rgb(0.0, 0.0, 0.0))\n",
      {"black_metal", "dark_metal", "mirror", "mirror_glass"});
  ASSERT_EQ(c.bindings.bindings.size(), 4u);
  for (int m = 0; m < 2; ++m) {
    const float base = m == 0 ? 0.0f : 0.01f;
    Shaded s = shade(c.bindings.bindings[size_t(m)]);
    ASSERT_TRUE(s.result.ok);
    ASSERT_EQ(s.bsdf.lobeCount(), 1);
    const Lobe& metal = s.bsdf.lobe(0);
    ASSERT_EQ(metal.kind, LobeKind::SmoothConductor);
    // glTF: F = base + (1 - base)(1 - cos)^5 for a metal.
    for (float cosTheta : {1.0f, 0.53f, 0.37f, 0.2f}) {
      const float schlick = base + (1.0f - base) * std::pow(1.0f - cosTheta, 5.0f);
      const Spectrum f = fresnelConductor(cosTheta, metal.a, metal.b);
      for (int k = 0; k < 4; ++k) EXPECT_NEAR(f[k], schlick, 0.02f + 0.15f * schlick) << base << " cos " << cosTheta;
    }
  }
  for (int m = 2; m < 4; ++m) {
    Shaded s = shade(c.bindings.bindings[size_t(m)]);
    ASSERT_TRUE(s.result.ok);
    ASSERT_EQ(s.bsdf.lobeCount(), 1) << m;  // nothing diffuse, nothing transmitted
    const Lobe& mirror = s.bsdf.lobe(0);
    ASSERT_EQ(mirror.kind, LobeKind::SmoothConductor);
    for (float cosTheta : {1.0f, 0.5f, 0.1f}) {
      const Spectrum f = fresnelConductor(cosTheta, mirror.a, mirror.b);
      for (int k = 0; k < 4; ++k) EXPECT_FLOAT_EQ(f[k] * mirror.weight[k], 1.0f) << m;
    }
  }
}

// Solid tinted glass (glTF transmission with a base colour) reflects as its interface does from
// either side, and the base colour tints only what crosses it. Its reflection had been a coat,
// which takes the outside's Fresnel from inside too: a 0.5 base reflected 0.53 beyond the
// critical angle (TIR: 1), 0.065 at 35 degrees inside (0.086), and 0.274 at 75 degrees outside
// for a slab (0.291).
TEST(ClosureLobes, GltfTintedGlassReflectsAsItsInterfaceFromEitherSide) {
  const Compiled c = compileEntries(
      "import std.gltf.{metallic_roughness}\n"
      "export fn smooth(h: Hit) -> Material = metallic_roughness(h, rgb(0.5, 0.5, 0.5), 0.0, 0.0, 1.0, 1.5, 0.0, rgb(0.0, 0.0, 0.0))\n"
      "export fn rough(h: Hit) -> Material = metallic_roughness(h, rgb(0.5, 0.5, 0.5), 0.0, 0.5, 1.0, 1.5, 0.0, rgb(0.0, 0.0, 0.0))\n"
      "export fn clear(h: Hit) -> Material = metallic_roughness(h, rgb(1.0, 1.0, 1.0), 0.0, 0.5, 1.0, 1.5, 0.0, rgb(0.0, 0.0, 0.0))\n",
      {"smooth", "rough", "clear"});
  ASSERT_EQ(c.bindings.bindings.size(), 3u);
  constexpr int kSamples = 200000;
  // Mean reflected and transmitted weight f |cos| / pdf of BSDF samples from wo (radiance mode).
  const auto albedos = [&](const Bsdf& bsdf, const Vec3& wo, double& reflected, double& transmitted) {
    sampling::Pcg32 rng(7, 11);
    reflected = transmitted = 0;
    for (int i = 0; i < kSamples; ++i) {
      const float uc = rng.nextFloat(), u1 = rng.nextFloat(), u2 = rng.nextFloat();
      const auto s = bsdf.sample(wo, uc, Vec2(u1, u2), TransportMode::Radiance);
      if (!s || !(s->pdfW > 0.0f)) continue;
      (s->wi.z * wo.z > 0.0f ? reflected : transmitted) += double(s->f[0]) * std::fabs(s->wi.z) / s->pdfW;
    }
    reflected /= kSamples, transmitted /= kSamples;
  };
  const auto direction = [](float thetaDeg, bool inside) {
    const float t = thetaDeg * float(M_PI) / 180.0f;
    return Vec3(std::sin(t), 0.0f, inside ? -std::cos(t) : std::cos(t));
  };
  {
    Shaded s = shade(c.bindings.bindings[0]);
    ASSERT_TRUE(s.result.ok);
    double r = 0, t = 0;
    albedos(s.bsdf, direction(50.0f, true), r, t);  // beyond the critical angle, 41.8 degrees
    EXPECT_NEAR(r, 1.0, 1e-6);
    EXPECT_EQ(t, 0.0);
    for (const auto& [theta, inside] : {std::pair{35.0f, true}, std::pair{75.0f, false}, std::pair{0.0f, false}}) {
      const Vec3 wo = direction(theta, inside);
      const double fresnel = fresnelDielectric(wo.z, 1.5f);
      const double eta2 = inside ? 1.0 / (1.5 * 1.5) : 1.5 * 1.5;  // radiance's 1 / eta_rel^2
      albedos(s.bsdf, wo, r, t);
      const double sigma = std::sqrt(fresnel * (1 - fresnel) / kSamples);
      EXPECT_NEAR(r, fresnel, 5 * sigma + 1e-6) << theta << " inside " << inside;
      EXPECT_NEAR(t, 0.5 * (1.0 - fresnel) / eta2, 5 * sigma * 0.5 / eta2 + 1e-6) << theta << " inside " << inside;
    }
  }
  // Rough: the tinted glass reflects what clear glass reflects, from inside as from outside,
  // and transmits half of what it transmits.
  Shaded rough = shade(c.bindings.bindings[1]), clear = shade(c.bindings.bindings[2]);
  ASSERT_TRUE(rough.result.ok && clear.result.ok);
  for (const auto& [theta, inside] : {std::pair{30.0f, true}, std::pair{60.0f, true}, std::pair{70.0f, false}}) {
    double rTinted = 0, tTinted = 0, rClear = 0, tClear = 0;
    albedos(rough.bsdf, direction(theta, inside), rTinted, tTinted);
    albedos(clear.bsdf, direction(theta, inside), rClear, tClear);
    EXPECT_NEAR(rTinted, rClear, 1e-6) << theta << " inside " << inside;  // the same samples
    EXPECT_NEAR(tTinted, 0.5 * tClear, 1e-6) << theta << " inside " << inside;
    EXPECT_GT(rClear, inside && theta > 45.0f ? 0.5 : 0.02) << theta;
  }
}

// The renderer's copy of KHR_materials_dispersion's formula (for volumes' media) is std.gltf's.
TEST(ClosureLobes, GltfDispersiveIorIsStdGltfs) {
  lang::Session session;
  lang::ModuleInfo* m = session.loadSource("dispersive.tex", "import std.gltf.{dispersive_ior}\n"
                                                             "fn main(ior: Float, d: Float) -> Spectrum = dispersive_ior(ior, d)\n");
  ASSERT_FALSE(session.diags().hasErrors());
  const int fn = session.instantiate(m, "main", {lang::TypeTable::global().floating(), lang::TypeTable::global().floating()}, lang::Span{});
  ASSERT_GE(fn, 0);
  lang::WavelengthGroup group;
  group.count = 8;
  for (int i = 0; i < 8; ++i) group.lambdaNm[i] = 380.0f + 60.0f * float(i);
  for (const auto& [ior, dispersion] : {std::pair{1.5f, 0.0f}, std::pair{1.5f, 1.2f}, std::pair{1.1f, 40.0f}, std::pair{2.4f, 0.3f}}) {
    const lang::Value spectrum = lang::evaluate(session.program(), fn, {lang::Value::ofFloat(ior), lang::Value::ofFloat(dispersion)}, group);
    for (int i = 0; i < 8; ++i)
      EXPECT_FLOAT_EQ(gltfDispersiveIor(ior, dispersion, group.lambdaNm[i]), spectrum.f[i]) << ior << " " << dispersion << " " << group.lambdaNm[i];
  }
}

// A binding's file is imported as a module by its name, so it must be a .tex file whose name is
// a module name: wall.mat was loaded and then wall.tex beside it rendered, and type.tex failed
// with parse errors in a generated file. Both are now errors naming the user's file.
TEST(ClosureLobes, BindingFilesMustBeImportableTexModules) {
  const std::string good = test::writeTexModule("wall", "export fn m(h: Hit) -> Material = diffuse(spectrum(0.9))\n");
  const std::filesystem::path dir = std::filesystem::path(good).parent_path();
  for (const char* name : {"wall.mat", "type.tex"}) {
    std::ofstream(dir / name) << "export fn m(h: Hit) -> Material = diffuse(spectrum(0.0))\n";
    SceneDescription scene;
    test::bindEntriesByMaterialName(scene, (dir / name).string(), {"m"});
    CompiledBindings compiled;
    std::string error;
    EXPECT_FALSE(compileBindings(scene, 4, false, false, compiled, error)) << name;
    EXPECT_NE(error.find(name), std::string::npos) << error;
    EXPECT_EQ(error.find("__scene_binding"), std::string::npos) << error;
  }
}

TEST(ClosureLobes, SheenOverOtherBasesIsACoverAndSheenUnderSheenFails) {
  // A sheen over Lambertian bases scales them (LambertianUnderSheen); over any other base it is
  // a cover over the whole Bsdf; a sheen under a sheen is not supported.
  const Compiled c = compileEntries(
      "export fn shiny(h: Hit) -> Material = layer(sheen(spectrum(0.5), 0.3), glossy(spectrum(0.5), 10.0))\n"
      "export fn nested(h: Hit) -> Material = layer(sheen(spectrum(0.5), 0.3), layer(dielectric(1.5), diffuse(spectrum(0.5))))\n"
      "export fn twice(h: Hit) -> Material = layer(sheen(spectrum(0.5), 0.3), add_material(sheen(spectrum(0.5), 0.3), diffuse(spectrum(0.5))))\n"
      "export fn beside(h: Hit) -> Material = add_material(diffuse(spectrum(0.5)), layer(sheen(spectrum(0.5), 0.3), glossy(spectrum(0.5), 10.0)))\n",
      {"shiny", "nested", "twice", "beside"});
  for (int i : {0, 1}) {
    const Shaded s = shade(c.bindings.bindings[size_t(i)]);
    EXPECT_TRUE(s.result.ok) << i;
    EXPECT_TRUE(s.bsdf.hasSheenCover()) << i;
  }
  EXPECT_FALSE(shade(c.bindings.bindings[2]).result.ok);
  EXPECT_FALSE(shade(c.bindings.bindings[3]).result.ok);
}


// What a shadow ray passes through a wall (Bsdf::straightThrough) is what BSDF samples marked
// straight carry on average (f |cos| / pdf over the lobe choice), lane by lane, and they leave
// along -wo: the path tracer's light sampling through windows and its BSDF paths through them
// are two estimators of one integral only then (a missing cover factor had passed the
// render-level agreement test within its noise). Bare, mixed, clearcoated and sheen-covered
// walls, from either side; a wall under an ordinary coat passes nothing either way.
TEST(ClosureLobes, StraightThroughIsWhatStraightSamplesCarry) {
  const Compiled c = compileEntries(
      "export fn bare(h: Hit) -> Material = thin_dielectric(1.5, 0.0, 0.5)\n"
      "export fn mixed(h: Hit) -> Material = mix_material(diffuse(spectrum(0.5)), thin_dielectric(1.5, 0.0, rgb(0.9, 0.5, 0.2)), 0.7)\n"
      "export fn clearcoated(h: Hit) -> Material = layer(dielectric(1.5, 0.0), mix_material(layer(dielectric(1.4, 0.1), diffuse(spectrum(0.5))), thin_dielectric(1.5, 0.0, 0.5), 0.7))\n"
      "export fn sheened(h: Hit) -> Material = layer(sheen(spectrum(0.6), 0.3), mix_material(diffuse(spectrum(0.5)), thin_dielectric(1.5, 0.0, 0.5), 0.7))\n"
      "export fn coated(h: Hit) -> Material = layer(dielectric(1.5, 0.0), thin_dielectric(1.5, 0.0, 0.5))\n",
      {"bare", "mixed", "clearcoated", "sheened", "coated"});
  ASSERT_EQ(c.bindings.bindings.size(), 5u);
  constexpr int kChoices = 20000;  // a stratified grid over the lobe choice
  for (size_t b = 0; b < c.bindings.bindings.size(); ++b) {
    const Shaded s = shade(c.bindings.bindings[b]);
    ASSERT_FALSE(s.bsdf.empty()) << b;
    for (const float thetaDeg : {0.0f, 30.0f, 65.0f})
      for (const bool below : {false, true}) {
        const float t = thetaDeg * float(M_PI) / 180.0f;
        const Vec3 wo(std::sin(t), 0.0f, below ? -std::cos(t) : std::cos(t));
        double carried[kLanes] = {};
        sampling::Pcg32 rng(3, 5);
        for (int i = 0; i < kChoices; ++i) {
          const auto sample = s.bsdf.sample(wo, (float(i) + 0.5f) / kChoices, Vec2(rng.nextFloat(), rng.nextFloat()), TransportMode::Radiance);
          if (!sample || !sample->straight) continue;
          ASSERT_LT(length(sample->wi + wo), 1e-5f) << b;
          for (int k = 0; k < kLanes; ++k) carried[k] += double(sample->f[k]) * std::fabs(dot3(sample->wi, s.bsdf.frame().n)) / sample->pdfW;
        }
        const Spectrum passed = s.bsdf.straightThrough(-wo);
        for (int k = 0; k < kLanes; ++k)
          EXPECT_NEAR(carried[k] / kChoices, passed[k], 2e-4 + 1e-3 * passed[k]) << "binding " << b << ", " << thetaDeg << (below ? " below" : " above") << ", lane " << k;
        if (b == 4) {
          EXPECT_TRUE(passed.isBlack());
        }
        if (b < 4) {
          EXPECT_GT(passed[0], 0.05f) << b;
        }
      }
  }
}

}  // namespace
}  // namespace tex::render
