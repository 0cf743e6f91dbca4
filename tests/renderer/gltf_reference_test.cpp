// Regression: every shared glTF model renders as its checked-in reference image
// (tests/renderer/data/references, made by make_references.sh: 48x48, 256 spp, seed 1) within
// noise. The test renders at another seed and 64 spp and compares with a per-pixel Z-test on
// both images' variance estimates: at most 1% of pixel channels may lie beyond 3 sigma
// (0.27% for Gaussian noise; the variance of Sobol estimates is overstated, which only helps),
// and the image means must agree within 5 standard errors. A change in how models render
// fails here until the references are deliberately re-made.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "renderer/film/film_sink.h"
#include "renderer/image/compare.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/scene/load_scene.h"
#include "runtime/stream.h"

namespace tex::render {
namespace {

const std::string kShared = TEX_SOURCE_DIR "/../shared/gltf";
const std::string kReferences = TEX_SOURCE_DIR "/tests/renderer/data/references";

std::string modelFile(const std::string& model) {
  for (const char* sub : {"/glTF-Binary", "/glTF", ""}) {
    const std::filesystem::path dir = kShared + "/" + model + sub;
    if (!std::filesystem::is_directory(dir)) continue;
    for (const auto& e : std::filesystem::directory_iterator(dir))
      if (e.path().extension() == ".glb" || e.path().extension() == ".gltf") return e.path().string();
  }
  return {};
}

TEST(GltfReference, EverySharedModelMatchesItsReferenceWithinNoise) {
  if (!std::filesystem::is_directory(kShared)) GTEST_SKIP() << "no shared glTF models next to the repository";
  int compared = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kReferences)) {
    if (entry.path().extension() != ".exr") continue;
    const std::string model = entry.path().stem().string();
    const std::string file = modelFile(model);
    ASSERT_FALSE(file.empty()) << "reference " << model << " has no model";
    std::string error;
    std::optional<SceneDescription> scene = loadScene(file, error);
    ASSERT_TRUE(scene) << error;
    RenderSceneOptions o;
    o.width = o.height = 48;
    std::unique_ptr<RenderScene> rs = RenderScene::build(*scene, o, error);
    ASSERT_TRUE(rs) << error;
    PathTracerSettings settings;
    settings.maxDepth = 6;
    const PathTracer tracer(*rs, sampling::Sampler(sampling::SamplerKind::Sobol, 2), settings);
    FilmSettings fs;
    fs.width = fs.height = 48;
    FilmSink sink(fs);
    std::vector<runtime::Sink<SampleRecord>*> sinks = {&sink};
    runtime::SchedulerOptions options;
    runtime::runStream<SampleRecord>({0, 48 * 48 * 64}, options, tracer, std::span<runtime::Sink<SampleRecord>* const>(sinks));
    const ExrImage rendered = sink.film().develop().toExr(true, false, {});
    ExrImage reference;
    ASSERT_EQ(readExr(entry.path().string(), reference), "");
    ImageComparison c;
    ASSERT_EQ(compareImages(rendered, reference, c), "") << model;
    ASSERT_TRUE(c.zTested) << model;
    EXPECT_LE(c.zOutlierFraction, 0.01) << model << ": " << comparisonToJson(c, "rendered", "reference");
    // Image means: the difference against the standard error of the mean of the difference.
    const ExrChannel* channels[2][3] = {{rendered.find("R"), rendered.find("G"), rendered.find("B")},
                                        {reference.find("R"), reference.find("G"), reference.find("B")}};
    const ExrChannel* variances[2][3] = {{rendered.find("variance.R"), rendered.find("variance.G"), rendered.find("variance.B")},
                                         {reference.find("variance.R"), reference.find("variance.G"), reference.find("variance.B")}};
    for (int k = 0; k < 3; ++k) {
      double difference = 0, variance = 0;
      const size_t n = channels[0][k]->values.size();
      for (size_t i = 0; i < n; ++i) {
        difference += channels[0][k]->values[i] - channels[1][k]->values[i];
        variance += variances[0][k]->values[i] + variances[1][k]->values[i];
      }
      EXPECT_LE(std::fabs(difference), 5.0 * std::sqrt(variance) + 1e-6 * double(n)) << model << " channel " << k;
    }
    ++compared;
  }
  EXPECT_GE(compared, 11);
}

}  // namespace
}  // namespace tex::render
