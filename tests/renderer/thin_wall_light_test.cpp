// Light sampling through windows: next-event estimation toward area and environment lights
// passes smooth thin walls (passStraightThrough), and a BSDF-sampled path that passes straight
// through a wall is weighted by MIS against the light sampling of the vertex before the wall.
// Both estimators (with and without next-event estimation) must agree at every maximum depth
// (walls count as bounces for both), and light sampling must pay off behind a window.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <vector>

#include "renderer/integrators/path_tracer.h"
#include "renderer/scene/shapes.h"
#include "tests/renderer/radiance_estimate.h"
#include "tests/renderer/scene_fixtures.h"

namespace tex::render {
namespace {

using test::Estimate;
using test::estimateRadiance;

enum class Lamp { SmallQuad, Sky };
// A bare wall; a glTF-like mixture of a diffuse and a wall; such a mixture (with a coated
// diffuse) under a clearcoat, or under a sheen cover (the covers' factors are in what shadow
// rays pass and in the BSDF samples alike).
enum class Pane { Bare, Mixed, Clearcoated, Sheened };
const char* paneName(Pane pane) {
  const char* names[] = {"pane", "mixed", "clearcoated", "sheened"};
  return names[int(pane)];
}

// A grey floor (albedo 0.5) at z = 0 seen from above (z = 3) through `panes` smooth thin walls
// (IOR 1.5, tint 0.5; bare, mixed or covered: Pane) at z = 1, 1.25, ..., lit through them by a
// small downward-facing lamp off to the side (x = 1, z = 2) or a sky.
SceneDescription windowScene(Lamp lamp, int panes, Pane pane) {
  const std::string file = test::writeTexModule(
      "window_nee", "export fn pane(h: Hit) -> Material = thin_dielectric(1.5, 0.0, 0.5)\n"
                    "export fn mixed(h: Hit) -> Material = mix_material(diffuse(spectrum(0.5)), thin_dielectric(1.5, 0.0, 0.5), 0.7)\n"
                    "export fn clearcoated(h: Hit) -> Material = layer(dielectric(1.5, 0.0), mix_material(layer(dielectric(1.4, 0.1), diffuse(spectrum(0.5))), thin_dielectric(1.5, 0.0, 0.5), 0.7))\n"
                    "export fn sheened(h: Hit) -> Material = layer(sheen(spectrum(0.6), 0.3), mix_material(diffuse(spectrum(0.5)), thin_dielectric(1.5, 0.0, 0.5), 0.7))\n"
                    "export fn floor(h: Hit) -> Material = diffuse(spectrum(0.5))\n"
                    "export fn lamp(h: Hit) -> Material = emission(spectrum(20.0))\n");
  SceneDescription scene;
  const auto add = [&](const std::string& name, MeshPrimitive quad) { test::addNamedMesh(scene, name, std::move(quad)); };
  add("floor", makeQuad(Vec3(-5, -5, 0), Vec3(10, 0, 0), Vec3(0, 10, 0)));
  for (int i = 0; i < panes; ++i)
    add(paneName(pane), makeQuad(Vec3(-2, -2, 1.0f + 0.25f * float(i)), Vec3(4, 0, 0), Vec3(0, 4, 0)));
  if (lamp == Lamp::SmallQuad) add("lamp", makeQuad(Vec3(0.75f, -0.25f, 2.0f), Vec3(0, 0.5f, 0), Vec3(0.5f, 0, 0)));  // faces -z
  else scene.lights.push_back(test::constantSky(1.0f));
  test::bindEntriesByMaterialName(scene, file, {"floor", "pane", "mixed", "clearcoated", "sheened", "lamp"});
  scene.cameras.push_back(test::cameraLookingDownZ(Vec3(0.0f, 0.0f, 3.0f), 0.05f));
  return scene;
}

Estimate estimate(const SceneDescription& scene, int maxDepth, bool nee) {
  PathTracerSettings settings;
  settings.maxDepth = maxDepth;
  settings.rouletteDepth = 1000;  // no roulette: its noise would hide the techniques'
  settings.nextEventEstimation = nee;
  return estimateRadiance(scene, settings, 1 << 16);
}

// With light sampling through the walls and MIS, and with BSDF sampling alone (the reference):
// the same expectation at every depth, including depths where the walls exhaust the budget
// (a shadow ray passes at most as many walls as a BSDF path from the same vertex could).
TEST(ThinWallLight, LightSamplingThroughWallsAgreesWithBsdfSamplingAtEveryDepth) {
  for (const Lamp lamp : {Lamp::SmallQuad, Lamp::Sky})
    for (const auto& [panes, pane] : {std::tuple{1, Pane::Bare}, std::tuple{1, Pane::Mixed}, std::tuple{1, Pane::Clearcoated},
                                       std::tuple{1, Pane::Sheened}, std::tuple{2, Pane::Bare}}) {
      const SceneDescription scene = windowScene(lamp, panes, pane);
      for (const int maxDepth : {2, 3, 4, 5}) {
        const Estimate withNee = estimate(scene, maxDepth, true), bsdfOnly = estimate(scene, maxDepth, false);
        const double sigma = std::sqrt(withNee.standardError * withNee.standardError + bsdfOnly.standardError * bsdfOnly.standardError);
        EXPECT_NEAR(withNee.mean, bsdfOnly.mean, 4.5 * sigma + 1e-6)
            << (lamp == Lamp::Sky ? "sky" : "lamp") << ", " << panes << " " << paneName(pane) << " pane(s)," << ", depth " << maxDepth;
        EXPECT_EQ(withNee.nonFinite, 0u);
      }
    }
}

// Behind a window a small lamp is found by light sampling: the estimate's standard error is a
// fraction of BSDF sampling's. Before light samples passed walls only toward Dirac lights, the
// lamp was found by BSDF samples alone and the two errors were the same.
TEST(ThinWallLight, LightSamplingFindsASmallLampBehindAWindow) {
  for (const Pane pane : {Pane::Bare, Pane::Mixed, Pane::Clearcoated, Pane::Sheened}) {
    const SceneDescription scene = windowScene(Lamp::SmallQuad, 1, pane);
    const Estimate withNee = estimate(scene, 3, true), bsdfOnly = estimate(scene, 3, false);
    ASSERT_GT(withNee.mean, 0.0);
    std::printf("%s: standard error %.3g with light sampling, %.3g with BSDF sampling (ratio %.3f)\n", paneName(pane),
                withNee.standardError, bsdfOnly.standardError, withNee.standardError / bsdfOnly.standardError);
    EXPECT_LT(withNee.standardError, 0.3 * bsdfOnly.standardError) << paneName(pane);
  }
}

}  // namespace
}  // namespace tex::render
