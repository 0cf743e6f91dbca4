// Two estimators of the same image must agree within noise: the path tracer with next-event
// estimation and MIS against the same tracer with BSDF sampling only (no MIS weights at all),
// on the spectral Cornell box. A wrong MIS weight, light pdf or area-measure conversion shifts
// the MIS image by far more than its noise. Compared on 8 x 8 blocks of a 32 x 32 film (each
// block averages 16 pixels, so its error is close to normal), with a Z-test per block and
// channel at a threshold corrected for the 192 tests.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/film/film_sink.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/scene/load_scene.h"
#include "runtime/stream.h"

namespace tex::render {
namespace {

DevelopedImage renderCornell(const RenderScene& rs, bool nee, uint64_t samples) {
  PathTracerSettings settings;
  settings.maxDepth = 5;
  settings.nextEventEstimation = nee;
  const PathTracer tracer(rs, sampling::Sampler(sampling::SamplerKind::Sobol, nee ? 5 : 6), settings);
  FilmSettings fs;
  fs.width = fs.height = 32;
  FilmSink sink(fs);
  std::vector<runtime::Sink<SampleRecord>*> sinks = {&sink};
  runtime::SchedulerOptions options;
  runtime::runStream<SampleRecord>({0, samples}, options, tracer, std::span<runtime::Sink<SampleRecord>* const>(sinks));
  return sink.film().develop();
}

TEST(MisAgreement, NextEventEstimationWithMisAgreesWithBsdfSamplingOnTheCornellBox) {
  std::string error;
  std::optional<SceneDescription> scene = loadScene(TEX_SOURCE_DIR "/scenes/cornell-box.json", error);
  ASSERT_TRUE(scene) << error;
  RenderSceneOptions o;
  o.width = o.height = 32;
  std::unique_ptr<RenderScene> rs = RenderScene::build(*scene, o, error);
  ASSERT_TRUE(rs) << error;
  const DevelopedImage mis = renderCornell(*rs, true, 32 * 32 * 256);
  const DevelopedImage bsdf = renderCornell(*rs, false, 32 * 32 * 1024);
  int worstBlock = -1;
  double worstZ = 0, meanMis = 0, meanBsdf = 0;
  for (int by = 0; by < 4; ++by)
    for (int bx = 0; bx < 4; ++bx)
      for (int c = 0; c < 3; ++c) {
        double a = 0, b = 0, va = 0, vb = 0;
        for (int y = by * 8; y < by * 8 + 8; ++y)
          for (int x = bx * 8; x < bx * 8 + 8; ++x) {
            const size_t i = (size_t(y) * 32 + size_t(x)) * 3 + size_t(c);
            a += mis.rgb[i];
            b += bsdf.rgb[i];
            va += mis.variance[i];
            vb += bsdf.variance[i];
          }
        meanMis += a;
        meanBsdf += b;
        const double z = (a - b) / std::sqrt(va + vb);
        if (std::fabs(z) > std::fabs(worstZ)) {
          worstZ = z;
          worstBlock = (by * 4 + bx) * 3 + c;
        }
      }
  EXPECT_LT(std::fabs(worstZ), 3.9) << "block " << worstBlock / 3 << " channel " << worstBlock % 3
                                    << "; image means " << meanMis / 3072 << " vs " << meanBsdf / 3072;
  EXPECT_GT(meanMis, 0.0);
}

}  // namespace
}  // namespace tex::render
