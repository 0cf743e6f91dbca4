// A small version of the thesis's Table 1 (bench/bench_table1.cpp has the full one): on the
// single-scattering glossy dispersive refraction scene (scenes/table1/glossy_n1000.json), the
// proposed spectral technique (wavelength group + spectral MIS, SpectralMode::Mis) must have a
// lower RMSE than one wavelength per path (SpectralMode::Single) at 4 and 16 samples per pixel,
// against a reference rendered here with many more samples; and both techniques, being
// unbiased, must converge to the same image (long renders agree within their noise).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "renderer/film/film_sink.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/scene/load_scene.h"
#include "runtime/stream.h"

namespace tex::render {
namespace {

constexpr int kRes = 16;  // small, so the references stay a few seconds in the test command
constexpr int kBlock = 4;  // pixels per block side for the agreement Z-test

struct Table1Scene {
  std::unique_ptr<SceneDescription> description;  // the render scene reads its meshes
  std::unique_ptr<RenderScene> scene;
  int maxDepth = 0;
};

Table1Scene loadTable1(const char* file) {
  Table1Scene t;
  std::string error;
  std::optional<SceneDescription> scene = loadScene(std::string(TEX_SOURCE_DIR "/scenes/table1/") + file, error);
  EXPECT_TRUE(scene) << error;
  if (!scene) return t;
  t.description = std::make_unique<SceneDescription>(std::move(*scene));
  RenderSceneOptions o;
  o.width = o.height = kRes;
  t.scene = RenderScene::build(*t.description, o, error);
  EXPECT_TRUE(t.scene) << error;
  t.maxDepth = t.description->settings.maxDepth;
  return t;
}

DevelopedImage renderTable1(const Table1Scene& t, SpectralMode mode, int spp, uint64_t seed) {
  PathTracerSettings settings;
  settings.maxDepth = t.maxDepth;
  settings.spectralMode = mode;
  const PathTracer tracer(*t.scene, sampling::Sampler(sampling::SamplerKind::Sobol, seed), settings);
  FilmSettings fs;
  fs.width = fs.height = kRes;
  FilmSink sink(fs);
  std::vector<runtime::Sink<SampleRecord>*> sinks = {&sink};
  runtime::SchedulerOptions options;
  runtime::runStream<SampleRecord>({0, uint64_t(kRes) * kRes * uint64_t(spp)}, options, tracer,
                                   std::span<runtime::Sink<SampleRecord>* const>(sinks));
  return sink.film().develop();
}

double rmse(const DevelopedImage& a, const DevelopedImage& ref) {
  double s = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) s += (double(a.rgb[i]) - ref.rgb[i]) * (double(a.rgb[i]) - ref.rgb[i]);
  return std::sqrt(s / double(a.rgb.size()));
}

// Mean RMSE over a few seeds (one image's RMSE at 4 spp fluctuates by a few per cent).
double meanRmse(const Table1Scene& t, SpectralMode mode, int spp, const DevelopedImage& ref) {
  double sum = 0;
  const int seeds = 4;
  for (int k = 0; k < seeds; ++k) sum += rmse(renderTable1(t, mode, spp, 100 + uint64_t(k)), ref);
  return sum / seeds;
}

// The long renders both tests use: mis (the reference) and single, 1024 spp each.
struct References {
  Table1Scene scene;
  DevelopedImage mis, single;
};

const References& references() {
  static const References r = [] {
    References x;
    x.scene = loadTable1("glossy_n1000.json");
    if (!x.scene.scene) return x;
    x.mis = renderTable1(x.scene, SpectralMode::Mis, 1024, 0);
    x.single = renderTable1(x.scene, SpectralMode::Single, 1024, 1);
    return x;
  }();
  return r;
}

TEST(Table1, SpectralMisBeatsOneWavelengthPerPathOnGlossyDispersiveRefraction) {
  const References& r = references();
  ASSERT_TRUE(r.scene.scene);
  ASSERT_EQ(r.scene.maxDepth, 1);  // single scattering
  const DevelopedImage& ref = r.mis;
  double mean = 0;
  for (float v : ref.rgb) mean += v;
  mean /= double(ref.rgb.size());
  ASSERT_GT(mean, 0.0);
  for (int spp : {4, 16}) {
    const double misError = meanRmse(r.scene, SpectralMode::Mis, spp, ref);
    const double singleError = meanRmse(r.scene, SpectralMode::Single, spp, ref);
    EXPECT_LT(misError, singleError) << spp << " spp (image mean " << mean << ")";
    std::printf("[ table1 ] %d spp: RMSE / mean: mis %.4f, single %.4f (ratio %.2f)\n", spp, misError / mean,
                singleError / mean, singleError / misError);
  }
}

// Both estimators are unbiased: long renders agree on blocks of kBlock x kBlock pixels (block
// sums are close to normal) within a Z threshold corrected for the 48 tests.
TEST(Table1, SpectralMisAndOneWavelengthPerPathConvergeToTheSameImage) {
  const References& r = references();
  ASSERT_TRUE(r.scene.scene);
  const DevelopedImage& mis = r.mis;
  const DevelopedImage& single = r.single;
  constexpr int kBlocks = kRes / kBlock;
  double worstZ = 0, meanMis = 0, meanSingle = 0;
  for (int by = 0; by < kBlocks; ++by)
    for (int bx = 0; bx < kBlocks; ++bx)
      for (int c = 0; c < 3; ++c) {
        double a = 0, b = 0, va = 0, vb = 0;
        for (int y = by * kBlock; y < by * kBlock + kBlock; ++y)
          for (int x = bx * kBlock; x < bx * kBlock + kBlock; ++x) {
            const size_t i = (size_t(y) * kRes + size_t(x)) * 3 + size_t(c);
            a += mis.rgb[i];
            b += single.rgb[i];
            va += mis.variance[i];
            vb += single.variance[i];
          }
        meanMis += a;
        meanSingle += b;
        ASSERT_GT(va + vb, 0.0) << "block " << by * kBlocks + bx << " is black in both images";
        worstZ = std::max(worstZ, std::fabs(a - b) / std::sqrt(va + vb));
      }
  EXPECT_LT(worstZ, 3.9) << "image means " << meanMis << " vs " << meanSingle;
  EXPECT_GT(meanMis, 0.0);
}

}  // namespace
}  // namespace tex::render
