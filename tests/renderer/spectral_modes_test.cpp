// The three spectral modes are unbiased estimators of the same image, so on a scene with rough
// dispersive glass (where `mis` really weights every wavelength by its per-lane pdf) their
// images must agree within noise; and `mis` must be the less noisy of `mis` and `single`. MIS
// weights that do not sum to one over the lanes (a wrong per-lane pdf or ratio) bias `mis` away
// from `single`, whose one-wavelength estimate involves neither (checked by breaking them).
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/film/film_sink.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/scene/shapes.h"
#include "tests/renderer/scene_fixtures.h"
#include "runtime/stream.h"

namespace tex::render {
namespace {

DevelopedImage renderMode(const RenderScene& rs, SpectralMode mode, uint64_t samples, int maxDepth = 6) {
  PathTracerSettings settings;
  settings.maxDepth = maxDepth;
  settings.rouletteDepth = maxDepth;
  settings.spectralMode = mode;
  const PathTracer tracer(rs, sampling::Sampler(sampling::SamplerKind::Sobol, 9 + uint64_t(mode)), settings);
  FilmSettings fs;
  fs.width = fs.height = 16;
  FilmSink sink(fs);
  std::vector<runtime::Sink<SampleRecord>*> sinks = {&sink};
  runtime::runStream<SampleRecord>({0, samples}, runtime::SchedulerOptions{}, tracer,
                                   std::span<runtime::Sink<SampleRecord>* const>(sinks));
  return sink.film().develop();
}

std::unique_ptr<RenderScene> buildSixteenSquare(const SceneDescription& scene, std::string& error) {
  RenderSceneOptions o;
  o.width = o.height = 16;
  o.useCache = false;
  return RenderScene::build(scene, o, error);
}

// A unit ball of the module's `glass` seen from z = 3.
SceneDescription glassBall(const std::string& stem, const std::string& source, float yFovRadians) {
  const std::string file = test::writeTexModule(stem, source);
  return test::oneObjectScene(makeSphere(Vec3(0.0f), 1.0f, 48, 24, false), file, "glass", Vec3(0.0f, 0.0f, 3.0f), yFovRadians);
}

TEST(SpectralModes, RoughDispersiveGlassGivesTheSameImageInEveryMode) {
  SceneDescription scene = glassBall("prism",
                                     "import std.spectra.{cauchy}\n"
                                     "export fn glass(h: Hit) -> Material = dielectric(cauchy(1.55, 20000.0), roughness: 0.15)\n",
                                     0.75f);
  // A small bright light behind the ball and a dim sky: colour fringes come from dispersion.
  LightDesc sun;
  sun.kind = LightDesc::Kind::Directional;
  sun.direction = glm::normalize(Vec3(0.3f, -0.2f, 1.0f));
  sun.emission.kind = SpectrumDesc::Kind::Constant;
  sun.emission.value = 3.0f;
  scene.lights.push_back(sun);
  scene.lights.push_back(test::constantSky(0.2f));
  std::string error;
  const std::unique_ptr<RenderScene> rs = buildSixteenSquare(scene, error);
  ASSERT_TRUE(rs) << error;

  const uint64_t samples = 16 * 16 * 2048;
  const DevelopedImage mis = renderMode(*rs, SpectralMode::Mis, samples);
  const DevelopedImage single = renderMode(*rs, SpectralMode::Single, samples);
  const DevelopedImage terminate = renderMode(*rs, SpectralMode::Terminate, samples);
  double misVariance = 0, singleVariance = 0;
  for (const DevelopedImage* other : {&single, &terminate}) {
    double worst = 0;
    // 4 x 4 blocks of 4 x 4 pixels, R G B: 48 Z-tests, threshold corrected for them.
    for (int by = 0; by < 4; ++by)
      for (int bx = 0; bx < 4; ++bx)
        for (int k = 0; k < 3; ++k) {
          double a = 0, bsum = 0, va = 0, vb = 0;
          for (int y = by * 4; y < by * 4 + 4; ++y)
            for (int x = bx * 4; x < bx * 4 + 4; ++x) {
              const size_t i = (size_t(y) * 16 + size_t(x)) * 3 + size_t(k);
              a += mis.rgb[i];
              bsum += other->rgb[i];
              va += mis.variance[i];
              vb += other->variance[i];
            }
          if (va + vb > 0) worst = std::max(worst, std::fabs(a - bsum) / std::sqrt(va + vb));
        }
    EXPECT_LT(worst, 3.6) << (other == &single ? "single" : "terminate");
  }
  for (size_t i = 0; i < mis.variance.size(); ++i) {
    misVariance += mis.variance[i];
    singleVariance += single.variance[i];
  }
  EXPECT_LT(misVariance, singleVariance);
}

// A rough dispersive event and then a smooth one: the smooth one keeps only the hero, and from
// there the path is a one-wavelength estimate whose MIS weight must be 1. The earlier rough
// vertex's weight n pdf_hero / sum_k pdf_k had been kept, so each lane's expectation became the
// integral of f_j n pdf_j / sum_k pdf_k: a lossless glass ball in a white furnace reflected 1.10
// to 1.20 of the sky, bluish, while `terminate` and `single` gave 0.994.
TEST(SpectralModes, ARoughThenASmoothDispersiveEventStaysUnbiased) {
  SceneDescription scene =
      glassBall("furnace_glass",
                "fn ior(h: Hit) -> Spectrum = 1.5 + 40000.0 / (lambda_nm * lambda_nm)\n"
                "export fn glass(h: Hit) -> Material = mix_material(dielectric(ior(h)), dielectric(ior(h), 0.02), 0.5)\n",
                0.6f);
  scene.lights.push_back(test::constantSky(1.0f));
  std::string error;
  const std::unique_ptr<RenderScene> rs = buildSixteenSquare(scene, error);
  ASSERT_TRUE(rs) << error;
  const uint64_t samples = 16 * 16 * 256;
  const DevelopedImage mis = renderMode(*rs, SpectralMode::Mis, samples, 64);
  const DevelopedImage terminate = renderMode(*rs, SpectralMode::Terminate, samples, 64);
  for (int k = 0; k < 3; ++k) {
    double a = 0, b = 0, va = 0, vb = 0;
    for (size_t i = size_t(k); i < mis.rgb.size(); i += 3) {
      a += mis.rgb[i];
      b += terminate.rgb[i];
      va += mis.variance[i];
      vb += terminate.variance[i];
    }
    ASSERT_GT(va + vb, 0.0);
    EXPECT_LT(std::fabs(a - b) / std::sqrt(va + vb), 4.0) << "channel " << k << ": mis " << a / 256 << ", terminate " << b / 256;
  }
}

}  // namespace
}  // namespace tex::render
