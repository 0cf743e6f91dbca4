// scenes/cornell-box-mitsuba.json (Mitsuba 3's mi.cornell_box(), for bench/cornell_vs_mitsuba.sh):
// it loads cleanly, its shapes are where Mitsuba puts them (rectangles [-1,1]^2 facing +z and
// cubes [-1,1]^3, moved by translate * rotate * scale), and a small render has no NaN and the
// image mean Mitsuba 3 gives.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "renderer/color/color.h"
#include "renderer/color/spectral_to_rgb.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/scene/load_scene.h"

namespace tex::render {
namespace {

const std::string kScene = TEX_SOURCE_DIR "/scenes/cornell-box-mitsuba.json";

struct PlacedShape {
  Vec3 lo{1e30f}, hi{-1e30f};
  Vec3 normal{0.0f};  // world normal of the first vertex
};

std::map<std::string, PlacedShape> placedShapes(const SceneDescription& s) {
  std::map<std::string, PlacedShape> out;
  for (const MeshInstance& inst : s.instances) {
    const MeshPrimitive& m = s.primitives[size_t(inst.primitive)];
    PlacedShape b;
    for (const Vec3& p : m.positions) {
      const Vec3 w = Vec3(inst.objectToWorld * Vec4(p, 1.0f));
      b.lo = glm::min(b.lo, w);
      b.hi = glm::max(b.hi, w);
    }
    const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(inst.objectToWorld)));
    b.normal = glm::normalize(normalMatrix * m.normals[0]);
    out[inst.nodeName] = b;
  }
  return out;
}

void expectVecNear(const Vec3& a, const Vec3& b, float tol, const std::string& what) {
  EXPECT_NEAR(a.x, b.x, tol) << what;
  EXPECT_NEAR(a.y, b.y, tol) << what;
  EXPECT_NEAR(a.z, b.z, tol) << what;
}

TEST(CornellScene, LoadsWithMitsubasGeometry) {
  std::string error;
  const std::optional<SceneDescription> s = loadScene(kScene, error);
  ASSERT_TRUE(s) << error;
  EXPECT_TRUE(s->warnings.empty()) << s->warnings.front();
  ASSERT_EQ(s->instances.size(), 8u);
  const auto b = placedShapes(*s);
  ASSERT_EQ(b.size(), 8u);
  constexpr float kTol = 1e-5f;
  // Light: 0.46 x 0.38 at y = 0.99, centred on z = 0.01, facing down.
  expectVecNear(b.at("light").lo, Vec3(-0.23f, 0.99f, -0.18f), kTol, "light lo");
  expectVecNear(b.at("light").hi, Vec3(0.23f, 0.99f, 0.20f), kTol, "light hi");
  expectVecNear(b.at("light").normal, Vec3(0, -1, 0), kTol, "light normal");
  // The walls close [-1,1]^3 except the front, and face inwards.
  const std::map<std::string, std::pair<Vec3, Vec3>> walls = {
      {"floor", {Vec3(0, -1, 0), Vec3(0, 1, 0)}},  {"ceiling", {Vec3(0, 1, 0), Vec3(0, -1, 0)}},
      {"back", {Vec3(0, 0, -1), Vec3(0, 0, 1)}},   {"green-wall", {Vec3(1, 0, 0), Vec3(-1, 0, 0)}},
      {"red-wall", {Vec3(-1, 0, 0), Vec3(1, 0, 0)}}};
  for (const auto& [name, placeNormal] : walls) {
    const PlacedShape& w = b.at(name);
    expectVecNear(0.5f * (w.lo + w.hi), placeNormal.first, kTol, name + " centre");
    expectVecNear(w.hi - w.lo, Vec3(2.0f) - 2.0f * glm::abs(placeNormal.second), kTol, name + " extent");
    expectVecNear(w.normal, placeNormal.second, kTol, name + " normal");
  }
  // Boxes: the small one stands on the floor, the large one sinks 0.01 into it (as in Mitsuba).
  EXPECT_NEAR(b.at("small-box").lo.y, -1.0f, kTol);
  EXPECT_NEAR(b.at("small-box").hi.y, -0.4f, kTol);
  EXPECT_NEAR(b.at("large-box").lo.y, -1.01f, kTol);
  EXPECT_NEAR(b.at("large-box").hi.y, 0.21f, kTol);
  // Rotated by -17 degrees about y: the x extent of a 0.6-wide square turned by 17 degrees.
  const float turned = 0.6f * (std::cos(17.0f * 3.14159265f / 180) + std::sin(17.0f * 3.14159265f / 180));
  EXPECT_NEAR(b.at("small-box").hi.x - b.at("small-box").lo.x, turned, kTol);
  ASSERT_EQ(s->cameras.size(), 1u);
  EXPECT_NEAR(s->cameras[0].yFovRadians, 39.3077f * 3.14159265f / 180, 1e-6f);
  EXPECT_EQ(s->settings.maxDepth, 7);       // Mitsuba's max_depth 8
  EXPECT_EQ(s->settings.rouletteDepth, 5);  // Mitsuba's rr_depth 5
}

// Image mean of Mitsuba 3.9.1 on mi.cornell_box(), 256x256, 256 spp, mean of its scalar_spectral and
// llvm_ad_spectral renders
// (bench/cornell_vs_mitsuba.sh; standard errors 0.02-0.07 %, the two variants differ by up to 0.15 %).
constexpr double kMitsubaMeanRgb[3] = {0.23426, 0.14050, 0.05826};
constexpr double kMitsubaRelativeError = 0.003;

TEST(CornellScene, SmallRenderIsFiniteAndMatchesMitsubaMean) {
  std::string error;
  const std::optional<SceneDescription> s = loadScene(kScene, error);
  ASSERT_TRUE(s) << error;
  RenderSceneOptions o;
  o.width = o.height = 32;
  o.wavelengths = 4;
  o.useCache = false;
  std::unique_ptr<RenderScene> rs = RenderScene::build(*s, o, error);
  ASSERT_TRUE(rs) << error;
  PathTracerSettings settings;
  settings.maxDepth = s->settings.maxDepth;
  settings.rouletteDepth = s->settings.rouletteDepth;
  settings.wavelengths = 4;
  const PathTracer tracer(*rs, sampling::Sampler(sampling::SamplerKind::Sobol, 11), settings);
  // Every pixel equally often; the image mean is the mean of the per-sample colours.
  const uint64_t samples = uint64_t(o.width) * uint64_t(o.height) * 256;
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  for (uint64_t i = 0; i < samples; ++i) {
    const SampleRecord r = tracer.record(i);
    const color::Rgb c =
        color::xyzToLinearSrgb(color::xyzFromRadianceOverPdf(r.lambdaNm.data(), r.values.data(), r.wavelengthCount));
    const double v[3] = {c.r, c.g, c.b};
    for (int k = 0; k < 3; ++k) {
      ASSERT_TRUE(std::isfinite(v[k])) << "sample " << i;
      sum[k] += v[k];
      sum2[k] += v[k] * v[k];
    }
  }
  EXPECT_EQ(tracer.counters().nonFiniteSamples, 0u);
  EXPECT_EQ(tracer.counters().materialFailures, 0u);
  for (int k = 0; k < 3; ++k) {
    const double mean = sum[k] / double(samples);
    const double standardError = std::sqrt(std::max(0.0, sum2[k] / double(samples) - mean * mean) / double(samples));
    EXPECT_NEAR(mean, kMitsubaMeanRgb[k], 4 * standardError + kMitsubaRelativeError * kMitsubaMeanRgb[k])
        << "channel " << k << ", standard error " << standardError;
  }
}

}  // namespace
}  // namespace tex::render
