// A fixture for loader tests of glTF material extensions: the test quad
// (tests/renderer/data/scenes/quad.gltf) with `extensions` on its material, declared used and
// required, written to a temporary folder and loaded.
#pragma once
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "renderer/scene/gltf_loader.h"

namespace tex::render::test {

class GltfExtensionLoading : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("tex_gltf_extension_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
    std::ifstream in(TEX_SOURCE_DIR "/tests/renderer/data/scenes/quad.gltf");
    base_ = nlohmann::json::parse(in);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::optional<SceneDescription> loadWithExtensions(const nlohmann::json& extensions, std::vector<std::string>& errors,
                                                     const std::string& fileName) {
    nlohmann::json doc = base_;
    doc["materials"][0]["extensions"] = extensions;
    nlohmann::json used = nlohmann::json::array();
    for (const auto& [name, value] : extensions.items()) used.push_back(name);
    doc["extensionsUsed"] = used;
    doc["extensionsRequired"] = used;  // supported: required is fine
    const std::string path = (dir_ / fileName).string();
    std::ofstream(path) << doc.dump();
    return loadGltf(path, errors);
  }
  static bool anyContains(const std::vector<std::string>& lines, const std::string& needle) {
    for (const std::string& line : lines)
      if (line.find(needle) != std::string::npos) return true;
    return false;
  }

  std::filesystem::path dir_;
  nlohmann::json base_;
};

}  // namespace tex::render::test
