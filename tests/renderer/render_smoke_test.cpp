// Every shared glTF model and every shipped scene loads, builds (Embree, JIT materials, lights)
// and renders a few samples per pixel without errors, NaN or material failures.
#include <gtest/gtest.h>

#include <filesystem>

#include "renderer/integrators/path_tracer.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/scene/load_scene.h"

namespace tex::render {
namespace {

struct SmokeResult {
  bool ok = false;
  std::string error;
  PathCounters counters;
  double meanValue = 0;
};

SmokeResult renderFew(const std::string& path, uint64_t samples) {
  SmokeResult r;
  std::optional<SceneDescription> scene = loadScene(path, r.error);
  if (!scene) return r;
  RenderSceneOptions o;
  o.width = o.height = 24;
  std::unique_ptr<RenderScene> rs = RenderScene::build(*scene, o, r.error);
  if (!rs) return r;
  PathTracerSettings settings;
  settings.maxDepth = 6;
  const PathTracer tracer(*rs, sampling::Sampler(sampling::SamplerKind::Sobol, 1), settings);
  double sum = 0;
  for (uint64_t i = 0; i < samples; ++i) {
    const SampleRecord rec = tracer.record(i);
    for (int j = 0; j < rec.wavelengthCount; ++j) sum += rec.values[j];
  }
  r.meanValue = sum / double(samples);
  r.counters = tracer.counters();
  r.ok = true;
  return r;
}

std::vector<std::string> filesUnder(const std::filesystem::path& dir, const std::vector<std::string>& extensions) {
  std::vector<std::string> out;
  if (!std::filesystem::exists(dir)) return out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string ext = e.path().extension().string();
    for (const std::string& want : extensions)
      if (ext == want) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(RenderSmoke, EverySharedGltfModelLoadsAndRenders) {
  const std::vector<std::string> models = filesUnder(TEX_SOURCE_DIR "/../shared/gltf", {".gltf", ".glb"});
  if (models.empty()) GTEST_SKIP() << "no shared glTF models next to the repository";
  EXPECT_GE(models.size(), 11u);
  for (const std::string& model : models) {
    const SmokeResult r = renderFew(model, 24 * 24 * 2);
    ASSERT_TRUE(r.ok) << model << ": " << r.error;
    EXPECT_EQ(r.counters.nonFiniteSamples, 0u) << model;
    EXPECT_EQ(r.counters.materialFailures, 0u) << model;
    EXPECT_GT(r.meanValue, 0.0) << model << " rendered black";
  }
}

TEST(RenderSmoke, EveryShippedSceneLoadsAndRenders) {
  const std::vector<std::string> scenes = filesUnder(TEX_SOURCE_DIR "/scenes", {".json"});
  ASSERT_FALSE(scenes.empty());
  for (const std::string& scene : scenes) {
    if (scene.find("textured-gltf") != std::string::npos &&
        !std::filesystem::exists(TEX_SOURCE_DIR "/../shared/gltf/Duck/glTF-Binary/Duck.glb"))
      continue;  // references the shared models outside the repository
    const SmokeResult r = renderFew(scene, 24 * 24 * 2);
    ASSERT_TRUE(r.ok) << scene << ": " << r.error;
    EXPECT_EQ(r.counters.nonFiniteSamples, 0u) << scene;
    EXPECT_EQ(r.counters.materialFailures, 0u) << scene;
    EXPECT_GT(r.meanValue, 0.0) << scene << " rendered black";
  }
}

}  // namespace
}  // namespace tex::render
