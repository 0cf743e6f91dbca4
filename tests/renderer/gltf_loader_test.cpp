// glTF loading: the shared real-world models (facts from /work/shared/gltf/README.md) and
// broken inputs, which must give errors naming the file, never a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

#include <sys/stat.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>
#include <stb/stb_image_write.h>

#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/load_scene.h"

namespace tex::render {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

const std::string kShared = TEX_SOURCE_DIR "/../shared/gltf";
const std::string kFixtures = TEX_SOURCE_DIR "/tests/renderer/data/scenes";

#define SKIP_WITHOUT_SHARED()                                                      \
  if (!fs::exists(kShared)) GTEST_SKIP() << "shared glTF models not found at " << kShared

SceneDescription mustLoad(const std::string& relative) {
  std::vector<std::string> errors;
  std::optional<SceneDescription> scene = loadGltf(kShared + "/" + relative, errors);
  std::string joined;
  for (const auto& e : errors) joined += e + "\n";
  EXPECT_TRUE(scene.has_value()) << joined;
  EXPECT_TRUE(errors.empty()) << joined;
  return scene ? *scene : SceneDescription{};
}

size_t instancedTriangles(const SceneDescription& scene) {
  size_t n = 0;
  for (const MeshInstance& i : scene.instances) n += scene.primitives[size_t(i.primitive)].indices.size() / 3;
  return n;
}

bool anyContains(const std::vector<std::string>& messages, const std::string& needle) {
  for (const auto& m : messages)
    if (m.find(needle) != std::string::npos) return true;
  return false;
}

// Every primitive's indices are in range and whole triangles (the loader's contract).
void expectValidMeshes(const SceneDescription& scene) {
  for (const MeshPrimitive& p : scene.primitives) {
    ASSERT_EQ(p.indices.size() % 3, 0u);
    for (uint32_t i : p.indices) ASSERT_LT(i, p.positions.size());
    if (!p.normals.empty()) {
      ASSERT_EQ(p.normals.size(), p.positions.size());
    }
    if (!p.uv0.empty()) {
      ASSERT_EQ(p.uv0.size(), p.positions.size());
    }
    ASSERT_LT(p.material, int(scene.materials.size()));
  }
  for (const MeshInstance& i : scene.instances) ASSERT_LT(size_t(i.primitive), scene.primitives.size());
}

TEST(GltfLoader, EverySharedModelLoadsWithTheReadmeTriangleCounts) {
  SKIP_WITHOUT_SHARED();
  const std::map<std::string, size_t> triangles = {
      {"Box/glTF-Binary/Box.glb", 12},
      {"BoxTextured/glTF-Binary/BoxTextured.glb", 12},
      {"Duck/glTF-Binary/Duck.glb", 4212},
      {"TextureCoordinateTest/glTF-Binary/TextureCoordinateTest.glb", 10},
      {"TextureTransformTest/glTF/TextureTransformTest.gltf", 24},
      {"TransmissionTest/glTF-Binary/TransmissionTest.glb", 128775},
      {"AttenuationTest/glTF-Binary/AttenuationTest.glb", 292},
      {"DispersionTest/glTF-Binary/DispersionTest.glb", 51827},
      {"LightsPunctualLamp/glTF/LightsPunctualLamp.gltf", 6000},
      {"CornellBox/cornellBox.gltf", 16732},
  };
  for (const auto& [file, count] : triangles) {
    SCOPED_TRACE(file);
    SceneDescription scene = mustLoad(file);
    EXPECT_EQ(instancedTriangles(scene), count);
    expectValidMeshes(scene);
  }
}

TEST(GltfLoader, BoxHas12TrianglesInTheUnitCube) {
  SKIP_WITHOUT_SHARED();
  SceneDescription scene = mustLoad("Box/glTF-Binary/Box.glb");
  EXPECT_EQ(instancedTriangles(scene), 12u);
  EXPECT_EQ(scene.primitives.size(), 1u);
  const Bounds3 b = worldBounds(scene);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(b.lower[a], -0.5f, 1e-5f);
    EXPECT_NEAR(b.upper[a], 0.5f, 1e-5f);
  }
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].name, "Red");
  EXPECT_NEAR(scene.materials[0].baseColorFactor.r, 0.8f, 1e-6f);
  EXPECT_EQ(scene.materials[0].metallicFactor, 0.0f);
  EXPECT_EQ(scene.materials[0].roughnessFactor, 1.0f);
  EXPECT_TRUE(scene.cameras.empty());
  EXPECT_TRUE(scene.lights.empty());
}

TEST(GltfLoader, BoxTexturedDecodesItsEmbeddedPng) {
  SKIP_WITHOUT_SHARED();
  SceneDescription scene = mustLoad("BoxTextured/glTF-Binary/BoxTextured.glb");
  ASSERT_EQ(scene.images.size(), 1u);
  const ImageData& image = scene.images[0];
  EXPECT_GT(image.width, 0);
  EXPECT_GT(image.height, 0);
  EXPECT_EQ(image.valueCount(), size_t(image.width) * size_t(image.height) * size_t(image.channels));
  EXPECT_FALSE(image.bytes.empty());  // an 8-bit PNG keeps its bytes
  float lo = 1, hi = 0;
  for (size_t i = 0; i < image.valueCount(); ++i) lo = std::min(lo, image.value(i)), hi = std::max(hi, image.value(i));
  EXPECT_GE(lo, 0.0f);
  EXPECT_LE(hi, 1.0f);
  EXPECT_LT(lo, hi);  // not a constant image
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].baseColorTexture.image, 0);
}

TEST(GltfLoader, DuckHasAPerspectiveCameraAndTheReadmeBounds) {
  SKIP_WITHOUT_SHARED();
  SceneDescription scene = mustLoad("Duck/glTF-Binary/Duck.glb");
  ASSERT_GE(scene.cameras.size(), 1u);
  EXPECT_GT(scene.cameras[0].yFovRadians, 0.0f);
  EXPECT_LT(scene.cameras[0].yFovRadians, kPi);
  const Bounds3 b = worldBounds(scene);
  const Vec3 lower(-0.693f, 0.099f, -0.613f), upper(0.962f, 1.640f, 0.539f);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(b.lower[a], lower[a], 2e-3f);
    EXPECT_NEAR(b.upper[a], upper[a], 2e-3f);
  }
  // The camera frame is orthonormal (scale in its node chain is removed).
  const Mat4& m = scene.cameras[0].cameraToWorld;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(glm::length(Vec3(m[c])), 1.0f, 1e-5f);
}

TEST(GltfLoader, TextureCoordinateTestReadsUint8Indices) {
  SKIP_WITHOUT_SHARED();
  SceneDescription scene = mustLoad("TextureCoordinateTest/glTF-Binary/TextureCoordinateTest.glb");
  EXPECT_EQ(instancedTriangles(scene), 10u);
  for (const MeshPrimitive& p : scene.primitives) EXPECT_EQ(p.indices.size(), 6u);
  for (const GltfMaterial& m : scene.materials) EXPECT_TRUE(m.doubleSided);
  // "TopLeftMesh" shows the upper-left of the texture: its TEXCOORD_0 lie in about [0, 0.4].
  bool found = false;
  for (const MeshPrimitive& p : scene.primitives)
    if (p.meshName == "TopLeftMesh") {
      found = true;
      ASSERT_FALSE(p.uv0.empty());
      for (const Vec2& uv : p.uv0) {
        EXPECT_LE(uv.x, 0.45f);
        EXPECT_LE(uv.y, 0.45f);
      }
    }
  EXPECT_TRUE(found);
}

TEST(GltfLoader, TextureTransformTestHasNoNormalsAndParsesTransforms) {
  SKIP_WITHOUT_SHARED();
  SceneDescription scene = mustLoad("TextureTransformTest/glTF/TextureTransformTest.gltf");
  for (const MeshPrimitive& p : scene.primitives) EXPECT_TRUE(p.normals.empty());
  EXPECT_EQ(scene.primitives.size(), 9u);  // 9 meshes instanced by 12 nodes
  EXPECT_EQ(scene.instances.size(), 12u);
  bool rotation = false, scale = false, offset = false, clamped = false;
  for (const GltfMaterial& m : scene.materials) {
    const TextureRef& t = m.baseColorTexture;
    if (std::fabs(t.rotation - 0.39269908f) < 1e-5f) rotation = true;  // 22.5 degrees
    if (std::fabs(t.scale.x - 1.5f) < 1e-6f && std::fabs(t.scale.y - 1.5f) < 1e-6f) scale = true;
    if (t.offset != Vec2(0.0f)) offset = true;
    clamped = clamped || (t.image >= 0 && t.wrapS == WrapMode::ClampToEdge && t.wrapT == WrapMode::ClampToEdge);
  }
  EXPECT_TRUE(rotation);
  EXPECT_TRUE(scale);
  EXPECT_TRUE(offset);
  EXPECT_TRUE(clamped);  // textures 0 and 1 use the CLAMP_TO_EDGE sampler
}

TEST(GltfLoader, LightsPunctualLampHasFivePointLightsWithTheReadmeIntensities) {
  SKIP_WITHOUT_SHARED();
  SceneDescription scene = mustLoad("LightsPunctualLamp/glTF/LightsPunctualLamp.gltf");
  ASSERT_EQ(scene.lights.size(), 5u);
  std::map<std::string, float> intensity;
  for (const LightDesc& l : scene.lights) {
    EXPECT_EQ(l.kind, LightDesc::Kind::Point);
    EXPECT_EQ(l.emission.kind, SpectrumDesc::Kind::Rgb);
    intensity[l.name] = l.intensity;
  }
  EXPECT_FLOAT_EQ(intensity["Point"], 15.0f);
  EXPECT_FLOAT_EQ(intensity["Point.001"], 80.0f);
  EXPECT_FLOAT_EQ(intensity["Point.002"], 1.5f);
  EXPECT_FLOAT_EQ(intensity["Point.003"], 80.0f);
  EXPECT_FLOAT_EQ(intensity["Point.004"], 180.0f);
  for (const LightDesc& l : scene.lights)
    if (l.name == "Point") {
      EXPECT_NEAR(l.emission.rgb.g, 0.632f, 1e-3f);
      EXPECT_NEAR(l.emission.rgb.b, 0.239f, 1e-3f);
    }
  // Each light sits at its (root) node's matrix translation and shines down the node's -z.
  std::ifstream in(kShared + "/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf");
  const json doc = json::parse(in);
  size_t checked = 0;
  for (const json& node : doc["nodes"]) {
    if (!node.contains("extensions")) continue;
    const int index = node["extensions"]["KHR_lights_punctual"]["light"];
    const std::string name = doc["extensions"]["KHR_lights_punctual"]["lights"][size_t(index)]["name"];
    const json& m = node["matrix"];
    for (const LightDesc& l : scene.lights)
      if (l.name == name) {
        ++checked;
        EXPECT_NEAR(l.position.x, float(m[12]), 1e-5f);
        EXPECT_NEAR(l.position.y, float(m[13]), 1e-5f);
        EXPECT_NEAR(l.position.z, float(m[14]), 1e-5f);
        const Vec3 minusZ = -glm::normalize(Vec3(float(m[8]), float(m[9]), float(m[10])));
        EXPECT_NEAR(glm::dot(l.direction, minusZ), 1.0f, 1e-5f);
      }
  }
  EXPECT_EQ(checked, 5u);
  bool transmissive = false, tangents = false;
  for (const GltfMaterial& m : scene.materials) transmissive = transmissive || m.transmissionFactor > 0;
  for (const MeshPrimitive& p : scene.primitives) tangents = tangents || !p.tangents.empty();
  EXPECT_TRUE(transmissive);
  EXPECT_TRUE(tangents);
}

TEST(GltfLoader, CornellBoxWarnsAboutTheMissingImageAndLoads) {
  SKIP_WITHOUT_SHARED();
  SceneDescription scene = mustLoad("CornellBox/cornellBox.gltf");
  EXPECT_TRUE(anyContains(scene.warnings, "image")) << "expected a warning about texture 0's missing image";
  EXPECT_TRUE(anyContains(scene.warnings, "cornellBox.gltf"));
  for (const GltfMaterial& m : scene.materials) {
    EXPECT_EQ(m.baseColorTexture.image, -1);
    EXPECT_EQ(m.emissiveTexture.image, -1);
  }
  EXPECT_TRUE(scene.lights.empty());
  ASSERT_EQ(scene.cameras.size(), 1u);
  EXPECT_NEAR(scene.cameras[0].yFovRadians, 0.7175f, 1e-3f);
  EXPECT_NEAR(scene.cameras[0].aspect, 4.0f / 3.0f, 1e-3f);
  bool panel = false;
  for (const GltfMaterial& m : scene.materials) panel = panel || m.emissiveFactor == Vec3(10.0f);
  EXPECT_TRUE(panel);
}

TEST(GltfLoader, DispersionTestHas25IorDispersionPairsWithDefaultIor) {
  SKIP_WITHOUT_SHARED();
  SceneDescription scene = mustLoad("DispersionTest/glTF-Binary/DispersionTest.glb");
  std::map<std::pair<int, int>, int> pairs;  // (ior * 100, dispersion * 10) -> count
  for (const MeshInstance& i : scene.instances) {
    if (i.nodeName.rfind("Prism_IOR", 0) != 0) continue;
    const MeshPrimitive& p = scene.primitives[size_t(i.primitive)];
    ASSERT_GE(p.material, 0);
    const GltfMaterial& m = scene.materials[size_t(p.material)];
    EXPECT_EQ(m.transmissionFactor, 1.0f);
    EXPECT_NEAR(m.thicknessFactor, 0.018478f, 1e-5f);
    pairs[{int(std::lround(m.ior * 100)), int(std::lround(m.dispersion * 10))}]++;
  }
  EXPECT_EQ(pairs.size(), 25u);
  // Its vertex data is interleaved (byteStride 24 and 32): strided reads give unit normals.
  for (const MeshPrimitive& p : scene.primitives)
    for (const Vec3& n : p.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-3f);
  for (int ior : {100, 133, 150, 176, 242})
    for (int dispersion : {0, 5, 10, 20, 50}) EXPECT_EQ(pairs.count({ior, dispersion}), 1u) << ior << " " << dispersion;
}

TEST(GltfLoader, AttenuationTestReadsVolumeParameters) {
  SKIP_WITHOUT_SHARED();
  SceneDescription scene = mustLoad("AttenuationTest/glTF-Binary/AttenuationTest.glb");
  int volumetric = 0;
  for (const GltfMaterial& m : scene.materials) {
    EXPECT_EQ(m.thinWalled, !(m.thicknessFactor > 0)) << m.name;  // glTF: thickness 0 is a thin wall
    if (m.thicknessFactor > 0) {
      ++volumetric;
      EXPECT_NEAR(m.attenuationColor.r, 0.1f, 1e-4f);
      EXPECT_NEAR(m.attenuationColor.g, 0.5f, 1e-4f);
      EXPECT_NEAR(m.attenuationColor.b, 0.9f, 1e-4f);
      EXPECT_GE(m.attenuationDistance, 0.25f);
    }
  }
  EXPECT_EQ(volumetric, 11);
  // 292 triangles instanced from 232 stored: meshes shared by nodes are stored once.
  size_t stored = 0;
  for (const MeshPrimitive& p : scene.primitives) stored += p.indices.size() / 3;
  EXPECT_EQ(stored, 232u);
  EXPECT_EQ(instancedTriangles(scene), 292u);
}

TEST(GltfLoader, MetalRoughSpheresInstancesAboutOneMillionTriangles) {
  SKIP_WITHOUT_SHARED();
  SceneDescription scene = mustLoad("MetalRoughSpheresNoTextures/glTF-Binary/MetalRoughSpheresNoTextures.glb");
  EXPECT_EQ(instancedTriangles(scene), 1040409u);
  // One MeshPrimitive per glTF primitive of the 102 meshes, however many nodes use them.
  std::ifstream in(kShared + "/MetalRoughSpheresNoTextures/glTF-Binary/MetalRoughSpheresNoTextures.glb",
                   std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  uint32_t jsonBytes = 0;
  std::memcpy(&jsonBytes, bytes.data() + 12, 4);
  const json doc = json::parse(bytes.substr(20, jsonBytes));
  size_t gltfPrimitives = 0;
  for (const json& mesh : doc["meshes"]) gltfPrimitives += mesh["primitives"].size();
  EXPECT_EQ(doc["meshes"].size(), 102u);
  EXPECT_EQ(scene.primitives.size(), gltfPrimitives);
  const Bounds3 b = worldBounds(scene);
  const Vec3 extent = b.upper - b.lower;  // millimetre-sized, in metres
  EXPECT_GT(extent.x, 0.005f);
  EXPECT_LT(extent.x, 0.01f);
}

// ---- broken inputs ----------------------------------------------------------------------

class GltfMutated : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("tex_gltf_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ifstream in(kFixtures + "/quad.gltf");
    base_ = json::parse(in);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& bytes) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }
  // Loads `doc` and expects an error that names the file and contains `needle`.
  void expectError(const json& doc, const std::string& needle) {
    const std::string path = write("broken.gltf", doc.dump());
    std::vector<std::string> errors;
    EXPECT_FALSE(loadGltf(path, errors).has_value());
    ASSERT_FALSE(errors.empty());
    EXPECT_TRUE(anyContains(errors, path)) << errors[0];
    EXPECT_TRUE(anyContains(errors, needle)) << errors[0];
  }

  fs::path dir_;
  json base_;
};

TEST_F(GltfMutated, TheFixtureItselfLoads) {
  std::vector<std::string> errors;
  auto scene = loadGltf(kFixtures + "/quad.gltf", errors);
  ASSERT_TRUE(scene) << (errors.empty() ? "" : errors[0]);
  EXPECT_EQ(scene->primitives.size(), 1u);  // one mesh used by two nodes
  EXPECT_EQ(scene->instances.size(), 2u);
  const Bounds3 b = worldBounds(*scene);
  EXPECT_NEAR(b.lower.x, -2.0f, 1e-5f);  // the scaled quad
  EXPECT_NEAR(b.upper.y, 2.0f, 1e-5f);
  EXPECT_NEAR(b.lower.z, -3.0f, 1e-5f);  // the quad turned 90 degrees about y, moved to z = -2
  EXPECT_NEAR(b.upper.z, -1.0f, 1e-5f);
}

TEST_F(GltfMutated, TruncatedGlb) {
  SKIP_WITHOUT_SHARED();
  std::ifstream in(kShared + "/Duck/glTF-Binary/Duck.glb", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (size_t length : {size_t(3000), size_t(12), size_t(100), bytes.size() / 2, bytes.size() - 1}) {
    const std::string path = write("truncated.glb", bytes.substr(0, length));
    std::vector<std::string> errors;
    EXPECT_FALSE(loadGltf(path, errors).has_value()) << length;
    ASSERT_FALSE(errors.empty());
    EXPECT_TRUE(anyContains(errors, path));
  }
}

TEST_F(GltfMutated, GarbageBytes) {
  std::string garbage(4096, '\0');
  uint32_t state = 12345;
  for (char& c : garbage) c = char((state = state * 1664525u + 1013904223u) >> 24);
  for (const char* name : {"garbage.glb", "garbage.gltf"}) {
    const std::string path = write(name, garbage);
    std::vector<std::string> errors;
    EXPECT_FALSE(loadGltf(path, errors).has_value());
    EXPECT_TRUE(anyContains(errors, path));
  }
  // A glb header that claims more data than there is.
  std::string header = "glTF";
  const uint32_t fields[] = {2, 1000000, 999980, 0x4E4F534A};
  header.append(reinterpret_cast<const char*>(fields), sizeof fields);
  std::vector<std::string> errors;
  EXPECT_FALSE(loadGltf(write("lying.glb", header + "{}"), errors).has_value());
  // A GLB container of version 1 (glTF 1.0's binary extension) is not read as glTF 2.0.
  std::string v1 = "glTF";
  const uint32_t v1Fields[] = {1, 32, 12, 0x4E4F534A};
  v1.append(reinterpret_cast<const char*>(v1Fields), sizeof v1Fields);
  errors.clear();
  EXPECT_FALSE(loadGltf(write("v1.glb", v1 + "{\"a\":1}   "), errors).has_value());
  EXPECT_TRUE(anyContains(errors, "container version 1"));
}

TEST_F(GltfMutated, MissingFile) {
  std::vector<std::string> errors;
  EXPECT_FALSE(loadGltf((dir_ / "nope.glb").string(), errors).has_value());
  EXPECT_TRUE(anyContains(errors, "nope.glb"));
}

TEST_F(GltfMutated, AccessorIndexOutOfRange) {
  json doc = base_;
  doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 99;
  expectError(doc, "accessor 99");
}

TEST_F(GltfMutated, IndexValueNotBelowVertexCount) {
  json doc = base_;
  // Point the index accessor at the normals' bytes read as uint16: (0,0,1.0f) has 0x3F80 = 16256.
  doc["accessors"][3]["bufferView"] = 1;
  expectError(doc, "vertices");
}

TEST_F(GltfMutated, BufferViewBeyondItsBuffer) {
  json doc = base_;
  doc["bufferViews"][2]["byteLength"] = 1000;
  std::vector<std::string> errors;
  const std::string path = write("broken.gltf", doc.dump());
  EXPECT_FALSE(loadGltf(path, errors).has_value());
  EXPECT_TRUE(anyContains(errors, path));
}

TEST_F(GltfMutated, AccessorBeyondItsBufferView) {
  json doc = base_;
  doc["accessors"][0]["count"] = 5;
  expectError(doc, "do not fit");
  doc = base_;
  doc["accessors"][0]["byteOffset"] = 4;
  expectError(doc, "do not fit");
}

TEST_F(GltfMutated, WrongComponentTypeOrType) {
  json doc = base_;
  doc["accessors"][0]["type"] = "VEC2";
  expectError(doc, "expected VEC3");
  doc = base_;
  doc["accessors"][3]["componentType"] = 5126;  // float indices
  expectError(doc, "componentType");
}

TEST_F(GltfMutated, IndexCountNotAMultipleOfThree) {
  json doc = base_;
  doc["accessors"][3]["count"] = 5;
  expectError(doc, "multiple of 3");
}

TEST_F(GltfMutated, NodeCycle) {
  json doc = base_;
  doc["nodes"][1]["children"] = json::array({0});
  std::vector<std::string> errors;
  const std::string path = write("broken.gltf", doc.dump());
  EXPECT_FALSE(loadGltf(path, errors).has_value());
  EXPECT_TRUE(anyContains(errors, path));
}

// Round 13's hostile files: each used to crash, hang, take gigabytes or load wrong silently.
TEST_F(GltfMutated, HostileStructureIsRefusedWithAMessage) {
  // Extras nested a million deep overflowed tinygltf's recursion (a segfault).
  {
    json doc = base_;
    std::string deep = doc.dump();
    deep.insert(1, "\"extras\": " + std::string(300, '[') + std::string(300, ']') + ", ");
    const std::string path = write("deep.gltf", deep);
    std::vector<std::string> errors;
    EXPECT_FALSE(loadGltf(path, errors).has_value());
    EXPECT_TRUE(anyContains(errors, "levels deep")) << (errors.empty() ? "" : errors[0]);
  }
  // 2^27 zeros claimed by a 700-byte file took 12 GB.
  json doc = base_;
  doc["accessors"].push_back({{"componentType", 5126}, {"count", 1 << 24}, {"type", "VEC3"}});
  expectError(doc, "without a bufferView");
  doc = base_;
  doc["accessors"][0]["bufferView"] = -5;
  expectError(doc, "bufferView -5");
  doc = base_;
  doc["accessors"][3]["normalized"] = true;  // indices are never normalized
  expectError(doc, "normalized");
  // A cycle with no way in (every node is someone's child) and no scenes rendered nothing.
  doc = base_;
  doc.erase("scenes");
  doc.erase("scene");
  doc["nodes"][0]["children"] = json::array({1});
  doc["nodes"][1]["children"] = json::array({0});
  expectError(doc, "cycle");
  // A buffer that is a FIFO blocked forever; a directory threw bad_alloc.
  doc = base_;
  const std::string fifo = (dir_ / "fifo.bin").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  doc["buffers"][0]["uri"] = "fifo.bin";
  expectError(doc, "fifo.bin");
  doc["buffers"][0]["uri"] = ".";
  expectError(doc, "not found");
  // glTF 2.x only.
  doc = base_;
  doc["asset"]["version"] = "3.0";
  expectError(doc, "not glTF 2.x");
}

// A field tinygltf drops is reported: a three-number baseColorFactor lost the whole
// pbrMetallicRoughness without a word, and the material rendered as a grey metal.
TEST_F(GltfMutated, FieldsTinygltfDropsAreWarnedAbout) {
  json doc = base_;
  doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = json::array({1, 0, 0});
  const std::string path = write("short_factor.gltf", doc.dump());
  std::vector<std::string> errors;
  const auto scene = loadGltf(path, errors);
  ASSERT_TRUE(scene) << (errors.empty() ? "" : errors[0]);
  EXPECT_TRUE(anyContains(scene->warnings, "baseColorFactor"));
}

TEST_F(GltfMutated, UnsupportedRequiredExtension) {
  json doc = base_;
  doc["extensionsUsed"] = json::array({"KHR_draco_mesh_compression"});
  doc["extensionsRequired"] = json::array({"KHR_draco_mesh_compression"});
  expectError(doc, "KHR_draco_mesh_compression");
}

TEST_F(GltfMutated, MissingImageFileIsAWarning) {
  json doc = base_;
  doc["images"] = json::array({{{"uri", "does_not_exist.png"}}});
  doc["textures"] = json::array({{{"source", 0}}, {{"source", 7}}});
  doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  doc["materials"][0]["emissiveTexture"] = {{"index", 1}};
  std::vector<std::string> errors;
  auto scene = loadGltf(write("missing_image.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  EXPECT_EQ(scene->materials[0].baseColorTexture.image, -1);
  EXPECT_EQ(scene->materials[0].emissiveTexture.image, -1);
  EXPECT_TRUE(anyContains(scene->warnings, "does_not_exist.png"));
  EXPECT_TRUE(anyContains(scene->warnings, "image 7"));
}

// An image data URI that does not decode (not base64, or empty) is a warning like any image that
// cannot be read, in .gltf and .glb files alike: tinygltf had failed the whole file ("Failed to
// decode 'uri' for image[0]", exit 1), and an empty one had thrown.
TEST_F(GltfMutated, UndecodableImageDataUrisAreWarnings) {
  for (const char* uri : {"data:image/png;base64,@@@@", "data:image/png;base64,"}) {
    json doc = base_;
    doc["images"] = json::array({{{"uri", uri}}, {{"uri", "does_not_exist.png"}}});
    doc["textures"] = json::array({{{"source", 0}}});
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    std::string text = doc.dump();
    while (text.size() % 4) text.push_back(' ');
    std::string glb = "glTF";
    const auto u32 = [&](uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
    u32(2);
    u32(uint32_t(20 + text.size()));
    u32(uint32_t(text.size()));
    glb += "JSON" + text;
    for (const auto& [name, bytes] : {std::pair<std::string, std::string>{"bad_uri.gltf", doc.dump()}, {"bad_uri.glb", glb}}) {
      std::vector<std::string> errors;
      auto scene = loadGltf(write(name, bytes), errors);
      ASSERT_TRUE(scene) << name << ": " << errors[0];
      EXPECT_EQ(scene->materials[0].baseColorTexture.image, -1);
      EXPECT_TRUE(anyContains(scene->warnings, "image 0 (undecodable data URI) has no pixels (its data URI does not decode"))
          << name;
      EXPECT_FALSE(anyContains(scene->warnings, "image[0]")) << name;
      EXPECT_TRUE(anyContains(scene->warnings, "image[1]")) << name;  // other images' warnings stay
      EXPECT_EQ(scene->primitives.size(), 1u);
    }
  }
}

TEST_F(GltfMutated, SparseAccessorOverridesPositions) {
  json doc = base_;
  // Replace vertex 2 by the first normal, (0, 0, 1), through a sparse substitution.
  doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 128}, {"byteLength", 2}});  // index 0 (uint16)
  doc["accessors"][0]["sparse"] = {{"count", 1},
                                   {"indices", {{"bufferView", 4}, {"componentType", 5123}}},
                                   {"values", {{"bufferView", 1}}}};
  doc["accessors"][0].erase("min");
  doc["accessors"][0].erase("max");
  std::vector<std::string> errors;
  auto scene = loadGltf(write("sparse.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  EXPECT_EQ(scene->primitives[0].positions[0], Vec3(0, 0, 1));
  EXPECT_EQ(scene->primitives[0].positions[1], Vec3(1, -1, 0));
  // Sparse values that do not fit in their buffer view are an error.
  doc["accessors"][0]["sparse"]["indices"]["bufferView"] = 3;  // 5 indices < 4 vertices, but 5 values need 60 bytes of 48
  doc["accessors"][0]["sparse"]["count"] = 5;
  expectError(doc, "sparse");
}

TEST_F(GltfMutated, NormalizedByteTexcoords) {
  json doc = base_;
  // The index bytes 00 00 01 00 02 00 00 00 read as normalized ubyte VEC2.
  doc["accessors"].push_back({{"bufferView", 3}, {"componentType", 5121}, {"normalized", true}, {"count", 4}, {"type", "VEC2"}});
  doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = 4;
  std::vector<std::string> errors;
  auto scene = loadGltf(write("uv1.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  EXPECT_EQ(scene->primitives[0].uv1, (std::vector<Vec2>{{0, 0}, {1 / 255.0f, 0}, {2 / 255.0f, 0}, {0, 0}}));
  doc["accessors"][4]["normalized"] = false;  // plain bytes are (KHR_mesh_quantization): read exactly
  scene = loadGltf(write("uv1-bytes.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  EXPECT_EQ(scene->primitives[0].uv1, (std::vector<Vec2>{{0, 0}, {1, 0}, {2, 0}, {0, 0}}));
  doc["accessors"][4]["componentType"] = 5125;  // 32-bit integers are not texture coordinates
  expectError(doc, "componentType 5125");
}

// COLOR_0: RGB floats read with alpha 1, RGBA normalized bytes as value / 255; a count that
// disagrees with POSITION or a scalar type is an error naming the attribute.
TEST_F(GltfMutated, VertexColoursRgbFloatsAndRgbaBytes) {
  json doc = base_;
  doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = 1;  // the normals' floats, as RGB
  std::vector<std::string> errors;
  auto scene = loadGltf(write("rgb.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  const MeshPrimitive& rgb = scene->primitives[0];
  ASSERT_EQ(rgb.colors.size(), rgb.normals.size());
  for (size_t i = 0; i < rgb.colors.size(); ++i) EXPECT_EQ(rgb.colors[i], Vec4(rgb.normals[i], 1.0f));

  // The texture coordinates' first 16 bytes as normalized unsigned byte RGBA.
  doc["accessors"].push_back({{"bufferView", 2}, {"componentType", 5121}, {"normalized", true}, {"count", 4}, {"type", "VEC4"}});
  doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = 4;
  scene = loadGltf(write("rgba.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  const MeshPrimitive& rgba = scene->primitives[0];
  ASSERT_EQ(rgba.colors.size(), 4u);
  unsigned char bytes[16];
  std::memcpy(bytes, rgba.uv0.data(), 16);
  for (size_t i = 0; i < 4; ++i)
    EXPECT_EQ(rgba.colors[i], Vec4(bytes[4 * i] / 255.0f, bytes[4 * i + 1] / 255.0f, bytes[4 * i + 2] / 255.0f,
                                   bytes[4 * i + 3] / 255.0f));

  doc["accessors"][4]["count"] = 3;
  expectError(doc, "COLOR_0 has 3 elements");
  doc["accessors"][4]["count"] = 4;
  doc["accessors"][4]["type"] = "SCALAR";
  expectError(doc, "COLOR_0");
}

// A data URI holding `bytes` (base64), for buffers the tests below add to the fixture.
std::string dataUri(const std::string& bytes) {
  static const char* kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out = "data:application/octet-stream;base64,";
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t n = uint32_t(uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) n |= uint32_t(uint8_t(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) n |= uint32_t(uint8_t(bytes[i + 2]));
    out += kDigits[(n >> 18) & 63];
    out += kDigits[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? kDigits[(n >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kDigits[n & 63] : '=';
  }
  return out;
}

template <class T>
std::string bytesOf(const std::vector<T>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

// Morph targets at their default weights: mesh.weights pose every node's mesh, node.weights
// override them for that node (a primitive of its own); zero weights leave the mesh as stored.
TEST_F(GltfMutated, MorphTargetsAtTheirDefaultWeights) {
  json doc = base_;
  // One target displacing POSITION and NORMAL by the normals' (0, 0, 1).
  doc["meshes"][0]["primitives"][0]["targets"] = json::array({{{"POSITION", 1}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}});
  doc["meshes"][0]["weights"] = {0.0};
  std::vector<std::string> errors;
  auto scene = loadGltf(write("morph0.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  ASSERT_EQ(scene->primitives.size(), 1u);
  EXPECT_EQ(scene->primitives[0].positions[2], Vec3(1.0f, 1.0f, 0.0f));

  doc["meshes"][0]["weights"] = {0.5};
  doc["nodes"][2]["weights"] = {2.0};  // quad2
  scene = loadGltf(write("morph.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  ASSERT_EQ(scene->primitives.size(), 2u);  // the mesh at 0.5 (node quad) and at 2 (node quad2)
  ASSERT_EQ(scene->instances.size(), 2u);
  for (const MeshInstance& instance : scene->instances) {
    const float w = instance.nodeName == "quad2" ? 2.0f : 0.5f;
    const MeshPrimitive& prim = scene->primitives[size_t(instance.primitive)];
    EXPECT_EQ(prim.positions[0], Vec3(-1.0f, -1.0f, w)) << instance.nodeName;
    EXPECT_EQ(prim.positions[2], Vec3(1.0f, 1.0f, w)) << instance.nodeName;
    EXPECT_EQ(prim.normals[1], Vec3(0.0f, 0.0f, 1.0f + w)) << instance.nodeName;
    EXPECT_EQ(prim.uv0[1], Vec2(1.0f, 1.0f)) << instance.nodeName;  // TEXCOORD_0 targets are not applied
  }
  EXPECT_TRUE(anyContains(scene->warnings, "TEXCOORD_0 is not applied"));

  doc["accessors"].push_back({{"bufferView", 2}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}});
  doc["meshes"][0]["primitives"][0]["targets"][0]["POSITION"] = 4;  // VEC2: not a displacement
  expectError(doc, "morph target 0 POSITION");
}

// Skinning in the rest pose: each vertex is placed by its joints' world transforms times their
// inverse bind matrices, blended by its weights; the skinned node's own transform (a scale of 2
// here) is ignored. A joint outside the scene leaves the mesh unskinned, with a warning.
TEST_F(GltfMutated, SkinnedMeshesArePlacedByTheirJointsInTheRestPose) {
  json doc = base_;
  const std::vector<uint8_t> joints = {0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0};
  const std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0.25f, 0.75f, 0, 0};
  Mat4 inverseBind1(1.0f);
  inverseBind1[3] = Vec4(1.0f, 0.0f, 0.0f, 1.0f);  // translate by +x before the joint's transform
  const std::vector<Mat4> inverseBind = {Mat4(1.0f), inverseBind1};
  const std::string skinBytes = bytesOf(joints) + bytesOf(weights) + bytesOf(inverseBind);
  doc["buffers"].push_back({{"byteLength", skinBytes.size()}, {"uri", dataUri(skinBytes)}});
  doc["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 0}, {"byteLength", 16}});
  doc["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 16}, {"byteLength", 64}});
  doc["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 80}, {"byteLength", 128}});
  doc["accessors"].push_back({{"bufferView", 4}, {"componentType", 5121}, {"count", 4}, {"type", "VEC4"}});
  doc["accessors"].push_back({{"bufferView", 5}, {"componentType", 5126}, {"count", 4}, {"type", "VEC4"}});
  doc["accessors"].push_back({{"bufferView", 6}, {"componentType", 5126}, {"count", 2}, {"type", "MAT4"}});
  doc["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = 4;
  doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] = 5;
  doc["skins"] = json::array({{{"joints", {0, 2}}, {"inverseBindMatrices", 6}}});
  doc["nodes"][1]["skin"] = 0;  // node "quad" (scale 2), child of "root" (z = -2)
  std::vector<std::string> errors;
  auto scene = loadGltf(write("skin.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];

  const Mat4 root = glm::translate(Mat4(1.0f), Vec3(0.0f, 0.0f, -2.0f));
  const Mat4 quad2 = root * glm::mat4_cast(glm::quat(0.7071068f, 0.0f, 0.7071068f, 0.0f));  // (w, x, y, z)
  const Mat4 joint[2] = {root, quad2 * inverseBind1};
  const Vec3 object[4] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  const MeshInstance* skinned = nullptr;
  for (const MeshInstance& instance : scene->instances)
    if (instance.nodeName == "quad") skinned = &instance;
  ASSERT_TRUE(skinned);
  EXPECT_EQ(skinned->objectToWorld, Mat4(1.0f));
  const MeshPrimitive& prim = scene->primitives[size_t(skinned->primitive)];
  for (int v = 0; v < 4; ++v) {
    const Mat4 m = v < 2 ? joint[0] : v == 2 ? joint[1] : 0.25f * joint[0] + 0.75f * joint[1];
    const Vec3 expected = Vec3(m * Vec4(object[v], 1.0f));
    EXPECT_LT(glm::length(prim.positions[size_t(v)] - expected), 1e-5f) << "vertex " << v;
    EXPECT_NEAR(glm::length(prim.normals[size_t(v)]), 1.0f, 1e-5f);
  }
  // Vertex 2 follows joint 1 (rotated 90 degrees about y): its normal turns from +z to +x.
  EXPECT_LT(glm::length(prim.normals[2] - Vec3(1.0f, 0.0f, 0.0f)), 1e-5f);
  // The unskinned node quad2 still uses the mesh as stored.
  EXPECT_EQ(scene->primitives[0].positions[0], Vec3(-1.0f, -1.0f, 0.0f));
  {
    // Joints that mirror (the root scaled by -1 in x) turn the skinned triangles' winding, as a
    // mirroring node does (glTF 2.0 3.7.4): the mesh is placed with an identity transform, so
    // its front had faced the other way (one-sided emission came out of the back).
    json mirrored = doc;
    mirrored["nodes"][0]["scale"] = {-1.0, 1.0, 1.0};
    const auto mirroredScene = loadGltf(write("skin-mirrored.gltf", mirrored.dump()), errors);
    ASSERT_TRUE(mirroredScene) << errors[0];
    const MeshPrimitive* turned = nullptr;
    for (const MeshInstance& instance : mirroredScene->instances)
      if (instance.nodeName == "quad") turned = &mirroredScene->primitives[size_t(instance.primitive)];
    ASSERT_TRUE(turned);
    const std::vector<uint32_t>& stored = mirroredScene->primitives[0].indices;
    ASSERT_EQ(turned->indices.size(), stored.size());
    for (size_t t = 0; t < stored.size(); t += 3) {
      EXPECT_EQ(turned->indices[t], stored[t]);
      EXPECT_EQ(turned->indices[t + 1], stored[t + 2]);
      EXPECT_EQ(turned->indices[t + 2], stored[t + 1]);
    }
  }

  doc["skins"][0]["joints"] = {0, 7};  // no node 7 in the file
  scene = loadGltf(write("skin-outside.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  EXPECT_TRUE(anyContains(scene->warnings, "unskinned"));
  doc["skins"][0]["joints"] = {0, 2};
  {
    json bare = doc;  // a skinned node whose primitive has no influences: placed by the node
    bare["meshes"][0]["primitives"][0]["attributes"].erase("JOINTS_0");
    bare["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_0");
    scene = loadGltf(write("skin-bare.gltf", bare.dump()), errors);
    ASSERT_TRUE(scene) << errors[0];
    EXPECT_TRUE(anyContains(scene->warnings, "no JOINTS_0"));
    for (const MeshInstance& instance : scene->instances) {
      if (instance.nodeName == "quad") {
        EXPECT_EQ(instance.objectToWorld[0][0], 2.0f);  // the node's scale
      }
    }
  }
  doc["accessors"][6]["count"] = 1;  // one inverse bind matrix for two joints
  expectError(doc, "inverse bind matrices");
  doc["accessors"][6]["count"] = 2;
  doc["nodes"][1]["skin"] = 3;
  expectError(doc, "skin 3, which does not exist");
}

// KHR_mesh_quantization: positions as normalized shorts, normals as normalized bytes (each
// element padded to 4 bytes, as the extension requires), texture coordinates as plain
// unsigned shorts; signed values decode as max(c / 127 or 32767, -1). The extension may be
// required. Normals as plain (unnormalized) bytes are still refused.
TEST_F(GltfMutated, QuantizedAttributes) {
  json doc = base_;
  const std::vector<int16_t> positions = {-32768, -32767, 0, 0, 32767, -32767, 0, 0, 32767, 32767, 16384, 0, -32767, 32767, 0, 0};
  const std::vector<int8_t> normals = {0, 0, 127, 0, 0, -128, 127, 0, 0, 0, 127, 0, -127, 0, 0, 0};
  const std::vector<uint16_t> uv = {0, 0, 3, 0, 3, 2, 0, 2};
  const std::string bytes = bytesOf(positions) + bytesOf(normals) + bytesOf(uv);
  doc["buffers"].push_back({{"byteLength", bytes.size()}, {"uri", dataUri(bytes)}});
  doc["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 0}, {"byteLength", 32}, {"byteStride", 8}});
  doc["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 32}, {"byteLength", 16}, {"byteStride", 4}});
  doc["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 48}, {"byteLength", 16}});
  doc["accessors"].push_back({{"bufferView", 4}, {"componentType", 5122}, {"normalized", true}, {"count", 4}, {"type", "VEC3"}});
  doc["accessors"].push_back({{"bufferView", 5}, {"componentType", 5120}, {"normalized", true}, {"count", 4}, {"type", "VEC3"}});
  doc["accessors"].push_back({{"bufferView", 6}, {"componentType", 5123}, {"count", 4}, {"type", "VEC2"}});
  json& attributes = doc["meshes"][0]["primitives"][0]["attributes"];
  attributes["POSITION"] = 4;
  attributes["NORMAL"] = 5;
  attributes["TEXCOORD_0"] = 6;
  doc["extensionsUsed"] = {"KHR_mesh_quantization"};
  doc["extensionsRequired"] = {"KHR_mesh_quantization"};
  std::vector<std::string> errors;
  auto scene = loadGltf(write("quantized.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  const MeshPrimitive& prim = scene->primitives[0];
  EXPECT_EQ(prim.positions[0], Vec3(-1.0f, -1.0f, 0.0f));  // -32768 clamps to -1
  EXPECT_EQ(prim.positions[1], Vec3(1.0f, -1.0f, 0.0f));
  EXPECT_EQ(prim.positions[2], Vec3(1.0f, 1.0f, float(16384.0 / 32767.0)));
  EXPECT_EQ(prim.normals[0], Vec3(0.0f, 0.0f, 1.0f));
  EXPECT_EQ(prim.normals[1], Vec3(0.0f, -1.0f, 1.0f));  // -128 clamps to -1
  EXPECT_EQ(prim.normals[3], Vec3(-1.0f, 0.0f, 0.0f));
  EXPECT_EQ(prim.uv0[2], Vec2(3.0f, 2.0f));
  doc["accessors"][5]["normalized"] = false;
  expectError(doc, "componentType 5120");
}

TEST_F(GltfMutated, NonIndexedAndStripPrimitives) {
  json doc = base_;
  doc["meshes"][0]["primitives"][0].erase("indices");
  doc["meshes"][0]["primitives"][0]["mode"] = 5;  // strip of 4 vertices: 2 triangles
  std::vector<std::string> errors;
  auto scene = loadGltf(write("strip.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  EXPECT_EQ(scene->primitives[0].indices, (std::vector<uint32_t>{0, 1, 2, 2, 1, 3}));
  doc["meshes"][0]["primitives"][0]["mode"] = 1;  // lines: skipped with a warning
  scene = loadGltf(write("lines.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene);
  EXPECT_TRUE(scene->primitives.empty());
  EXPECT_TRUE(anyContains(scene->warnings, "mode 1"));
}

// glTF 2.0 section 3.9.6: a primitive without a material, or (after a warning) with one that does
// not exist, has "a material with no properties specified": base colour 1, metallic 1,
// roughness 1, one such material per file. It had been a grey 0.8 Lambertian that also
// ignored COLOR_0.
TEST_F(GltfMutated, PrimitivesWithoutAMaterialGetTheSpecsDefaultMaterial) {
  for (const bool outOfRange : {false, true}) {
    json doc = base_;
    if (outOfRange) doc["meshes"][0]["primitives"][0]["material"] = 7;
    else doc["meshes"][0]["primitives"][0].erase("material");
    std::vector<std::string> errors;
    auto scene = loadGltf(write("nomaterial.gltf", doc.dump()), errors);
    ASSERT_TRUE(scene) << errors[0];
    const int m = scene->primitives[0].material;
    ASSERT_GE(m, 0);
    ASSERT_LT(size_t(m), scene->materials.size());
    const GltfMaterial& d = scene->materials[size_t(m)];
    EXPECT_EQ(d.baseColorFactor, Vec4(1.0f));
    EXPECT_EQ(d.metallicFactor, 1.0f);
    EXPECT_EQ(d.roughnessFactor, 1.0f);
    EXPECT_EQ(d.emissiveFactor, Vec3(0.0f));
    EXPECT_EQ(d.alphaMode, GltfMaterial::AlphaMode::Opaque);
    EXPECT_EQ(anyContains(scene->warnings, "does not exist"), outOfRange);
  }
}

TEST_F(GltfMutated, MaterialExtensionsAndTextureTransforms) {
  json doc = base_;
  json& m = doc["materials"][0];
  m["emissiveFactor"] = {1, 0.5, 0.25};
  m["alphaMode"] = "MASK";
  m["alphaCutoff"] = 0.3;
  m["doubleSided"] = true;
  m["extensions"] = {
      {"KHR_materials_emissive_strength", {{"emissiveStrength", 40}}},
      {"KHR_materials_transmission", {{"transmissionFactor", 0.75}}},
      {"KHR_materials_ior", {{"ior", 1.33}}},
      {"KHR_materials_dispersion", {{"dispersion", 2}}},
      {"KHR_materials_volume",
       {{"thicknessFactor", 0.5}, {"attenuationDistance", 2}, {"attenuationColor", {0.1, 0.5, 0.9}}}},
      {"VENDOR_unknown", json::object()},
  };
  doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_transmission", "KHR_materials_ior",
                           "KHR_materials_dispersion", "KHR_materials_volume", "VENDOR_unknown"};
  doc["extensionsRequired"] = {"KHR_materials_transmission", "KHR_materials_volume"};  // supported: fine
  std::vector<std::string> errors;
  auto scene = loadGltf(write("extensions.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  const GltfMaterial& g = scene->materials[0];
  EXPECT_EQ(g.emissiveFactor, Vec3(1, 0.5f, 0.25f));
  EXPECT_EQ(g.emissiveStrength, 40.0f);
  EXPECT_EQ(g.transmissionFactor, 0.75f);
  EXPECT_FLOAT_EQ(g.ior, 1.33f);
  EXPECT_EQ(g.dispersion, 2.0f);
  EXPECT_EQ(g.thicknessFactor, 0.5f);
  EXPECT_EQ(g.attenuationDistance, 2.0f);
  EXPECT_EQ(g.attenuationColor, Vec3(0.1f, 0.5f, 0.9f));
  EXPECT_EQ(g.alphaMode, GltfMaterial::AlphaMode::Mask);
  EXPECT_FLOAT_EQ(g.alphaCutoff, 0.3f);
  EXPECT_TRUE(g.doubleSided);
  EXPECT_TRUE(anyContains(scene->warnings, "VENDOR_unknown"));
}

// Without NORMAL the given tangents MUST be ignored (glTF 2.0 3.7.2.1: flat normals); a node
// matrix MUST be decomposable to TRS, so a last row other than (0, 0, 0, 1) is warned about.
TEST_F(GltfMutated, TangentsWithoutNormalsAndNonAffineMatricesAreWarnedAbout) {
  json doc = base_;
  const std::vector<float> tangents = {-1, 0, 0, 1, -1, 0, 0, 1, -1, 0, 0, 1, -1, 0, 0, 1};
  const std::string bytes = bytesOf(tangents);
  doc["buffers"].push_back({{"byteLength", bytes.size()}, {"uri", dataUri(bytes)}});
  doc["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 0}, {"byteLength", bytes.size()}});
  doc["accessors"].push_back({{"bufferView", 4}, {"componentType", 5126}, {"count", 4}, {"type", "VEC4"}});
  doc["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL");
  doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = int(doc["accessors"].size()) - 1;
  doc["nodes"][1].erase("scale");
  doc["nodes"][1]["matrix"] = {1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::vector<std::string> errors;
  const auto scene = loadGltf(write("tangent-no-normal.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  for (const MeshPrimitive& p : scene->primitives) EXPECT_TRUE(p.tangents.empty());
  EXPECT_TRUE(anyContains(scene->warnings, "has TANGENT but no NORMAL; the tangents are ignored"));
  EXPECT_TRUE(anyContains(scene->warnings, "matrix is not affine"));
}

// Values outside the specification's ranges are clamped with a warning, and numbers beyond a
// float fall back to the default with one: they had been taken silently (a negative emissive
// strength blacked out the scene, a negative factor made negative pixels, 1e39 became inf and
// a black object, "abc" read as the default). KHR_materials_ior's 0 is valid and kept.
TEST_F(GltfMutated, OutOfRangeMaterialValuesAreClampedWithAWarning) {
  const auto load = [&](const json& pbr, const json& extensions, const json& emissive) {
    json doc = base_;
    json& m = doc["materials"][0];
    for (const auto& [k, v] : pbr.items()) m["pbrMetallicRoughness"][k] = v;
    if (!emissive.is_null()) m["emissiveFactor"] = emissive;
    m["extensions"] = extensions;
    std::vector<std::string> errors;
    auto scene = loadGltf(write("ranges.gltf", doc.dump()), errors);
    EXPECT_TRUE(scene.has_value()) << (errors.empty() ? "" : errors[0]);
    return scene;
  };
  auto scene = load({{"roughnessFactor", -0.5}, {"metallicFactor", 2}},
                    {{"KHR_materials_emissive_strength", {{"emissiveStrength", -2}}},
                     {"KHR_materials_transmission", {{"transmissionFactor", 2}}},
                     {"KHR_materials_ior", {{"ior", 0.5}}},
                     {"KHR_materials_volume", {{"thicknessFactor", 1}, {"attenuationDistance", -1}, {"attenuationColor", {2, 0.5, -1}}}}},
                    {-1, 0.5, 0.5});
  ASSERT_TRUE(scene);
  const GltfMaterial& g = scene->materials[0];
  EXPECT_EQ(g.roughnessFactor, 0.0f);
  EXPECT_EQ(g.metallicFactor, 1.0f);
  EXPECT_EQ(g.emissiveStrength, 0.0f);
  EXPECT_EQ(g.emissiveFactor, Vec3(0, 0.5f, 0.5f));
  EXPECT_EQ(g.transmissionFactor, 1.0f);
  EXPECT_EQ(g.ior, 1.5f);
  EXPECT_EQ(g.attenuationColor, Vec3(1, 0.5f, 0));
  for (const char* what : {"roughnessFactor -0.5", "metallicFactor 2", "emissiveStrength -2", "emissiveFactor component -1",
                           "transmissionFactor 2", "ior 0.5", "attenuationDistance -1", "attenuationColor component 2"})
    EXPECT_TRUE(anyContains(scene->warnings, what)) << what;
  scene = load(json::object(),
               {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1e39}}}, {"KHR_materials_ior", {{"ior", "abc"}}}},
               {1e39, 1, 1});
  ASSERT_TRUE(scene);
  EXPECT_EQ(scene->materials[0].emissiveStrength, 1.0f);
  EXPECT_EQ(scene->materials[0].ior, 1.5f);
  EXPECT_EQ(scene->materials[0].emissiveFactor, Vec3(0.0f));
  EXPECT_TRUE(anyContains(scene->warnings, "emissiveStrength is not a number within the range of a 32-bit float"));
  EXPECT_TRUE(anyContains(scene->warnings, "ior is not a number within the range of a 32-bit float"));
  EXPECT_TRUE(anyContains(scene->warnings, "emissiveFactor is not 3 finite numbers"));
  scene = load(json::object(), {{"KHR_materials_ior", {{"ior", 0}}}}, nullptr);
  ASSERT_TRUE(scene);
  EXPECT_EQ(scene->materials[0].ior, 0.0f);
  EXPECT_FALSE(anyContains(scene->warnings, "ior"));
}

// A normal-mapped material on a mesh without TANGENT gets per-vertex tangents (of the normal
// texture's uv set); without a normal map nothing is generated.
TEST_F(GltfMutated, NormalMapsWithoutTangentsGetVertexTangents) {
  const unsigned char pixels[] = {128, 128, 255, 128, 128, 255};
  ASSERT_NE(stbi_write_png((dir_ / "flat.png").c_str(), 2, 1, 3, pixels, 6), 0);
  json doc = base_;
  std::vector<std::string> errors;
  auto scene = loadGltf(write("plain.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  EXPECT_TRUE(scene->primitives[0].tangents.empty());

  doc["images"] = json::array({{{"uri", "flat.png"}}});
  doc["textures"] = json::array({{{"source", 0}}});
  doc["materials"][0]["normalTexture"] = {{"index", 0}};
  scene = loadGltf(write("normalmap.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  const MeshPrimitive& prim = scene->primitives[0];
  ASSERT_EQ(prim.tangents.size(), prim.positions.size());
  // The quad lies in z = 0 with u growing along +x and v along -y (glTF's image rows).
  for (const Vec4& t : prim.tangents) {
    EXPECT_LT(glm::length(Vec3(t) - Vec3(1.0f, 0.0f, 0.0f)), 1e-5f);
    EXPECT_EQ(t.w, 1.0f);
  }
}

// Without NORMAL, a normal map on TEXCOORD_1 gets tangents generated from TEXCOORD_1 (the hit's
// own triangle frame follows TEXCOORD_0: the map's frame had followed the wrong uv set, or,
// with TEXCOORD_1 alone, the map was ignored).
TEST_F(GltfMutated, NormalMapsOnTheSecondUvSetOfMeshesWithoutNormalsGetItsTangents) {
  const unsigned char pixels[] = {128, 128, 255, 128, 128, 255};
  ASSERT_NE(stbi_write_png((dir_ / "flat.png").c_str(), 2, 1, 3, pixels, 6), 0);
  json doc = base_;
  json& attributes = doc["meshes"][0]["primitives"][0]["attributes"];
  attributes["TEXCOORD_1"] = attributes["TEXCOORD_0"];
  attributes.erase("TEXCOORD_0");
  attributes.erase("NORMAL");
  doc["images"] = json::array({{{"uri", "flat.png"}}});
  doc["textures"] = json::array({{{"source", 0}}});
  doc["materials"][0]["normalTexture"] = {{"index", 0}, {"texCoord", 1}};
  std::vector<std::string> errors;
  const auto scene = loadGltf(write("uv1-normalmap.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  const MeshPrimitive& prim = scene->primitives[0];
  EXPECT_TRUE(prim.normals.empty());
  ASSERT_EQ(prim.tangents.size(), prim.positions.size());
  for (const Vec4& t : prim.tangents) {
    EXPECT_LT(glm::length(Vec3(t) - Vec3(1.0f, 0.0f, 0.0f)), 1e-5f);
    EXPECT_EQ(t.w, 1.0f);
  }
}

TEST_F(GltfMutated, TextureTransformOnAnExtensionTexture) {
  // A 2x1 RGB PNG next to the fixture, as an external image.
  const unsigned char pixels[] = {255, 0, 0, 0, 128, 255};
  ASSERT_NE(stbi_write_png((dir_ / "logo.png").c_str(), 2, 1, 3, pixels, 6), 0);
  json doc = base_;
  doc["images"] = json::array({{{"uri", "logo.png"}}});
  doc["samplers"] = json::array({{{"wrapS", 33648}, {"wrapT", 33071}, {"magFilter", 9728}}});
  doc["textures"] = json::array({{{"source", 0}, {"sampler", 0}}});
  doc["materials"][0]["extensions"]["KHR_materials_transmission"] = {
      {"transmissionFactor", 1},
      {"transmissionTexture",
       {{"index", 0},
        {"extensions", {{"KHR_texture_transform", {{"offset", {0.25, 0.5}}, {"rotation", 0.5}, {"scale", {2, 3}},
                                                   {"texCoord", 1}}}}}}}};
  std::vector<std::string> errors;
  auto scene = loadGltf(write("transform.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  ASSERT_EQ(scene->images.size(), 1u);
  const ImageData& image = scene->images[0];
  EXPECT_EQ(image.width, 2);
  EXPECT_EQ(image.height, 1);
  ASSERT_EQ(image.channels, 3);
  std::vector<float> values;
  for (size_t i = 0; i < image.valueCount(); ++i) values.push_back(image.value(i));
  EXPECT_EQ(values, (std::vector<float>{1, 0, 0, 0, 128 / 255.0f, 1}));
  const TextureRef& t = scene->materials[0].transmissionTexture;
  EXPECT_EQ(t.image, 0);
  EXPECT_EQ(t.offset, Vec2(0.25f, 0.5f));
  EXPECT_EQ(t.rotation, 0.5f);
  EXPECT_EQ(t.scale, Vec2(2, 3));
  EXPECT_EQ(t.texCoord, 1);
  EXPECT_EQ(t.wrapS, WrapMode::MirroredRepeat);
  EXPECT_EQ(t.wrapT, WrapMode::ClampToEdge);
  EXPECT_TRUE(t.nearest);
}

TEST_F(GltfMutated, SpotLightAndCamerasOnRotatedNodes) {
  json doc = base_;
  // Node 3: rotated -90 degrees about x, so its -z points down (-y).
  doc["nodes"].push_back({{"name", "lamp"}, {"translation", {1, 2, 3}}, {"rotation", {-0.7071068, 0, 0, 0.7071068}},
                          {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}, {"camera", 0}});
  doc["nodes"].push_back({{"name", "ortho"}, {"camera", 1}});
  doc["scenes"][0]["nodes"] = {0, 3, 4};
  doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array(
      {{{"type", "spot"}, {"name", "spot"}, {"intensity", 7}, {"color", {1, 0, 0}},
        {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.4}}}}});
  doc["cameras"] = json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.6}, {"znear", 0.1}, {"aspectRatio", 1.5}}}},
                                {{"type", "orthographic"},
                                 {"orthographic", {{"xmag", 2}, {"ymag", 0.5}, {"znear", 0.1}, {"zfar", 10}}}}});
  std::vector<std::string> errors;
  auto scene = loadGltf(write("spot.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  ASSERT_EQ(scene->lights.size(), 1u);
  const LightDesc& l = scene->lights[0];
  EXPECT_EQ(l.kind, LightDesc::Kind::Spot);
  EXPECT_EQ(l.intensity, 7.0f);
  EXPECT_EQ(l.emission.rgb, Vec3(1, 0, 0));
  EXPECT_NEAR(glm::distance(l.position, Vec3(1, 2, 3)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::dot(l.direction, Vec3(0, -1, 0)), 1.0f, 1e-6f);
  EXPECT_FLOAT_EQ(l.innerConeRadians, 0.2f);
  EXPECT_FLOAT_EQ(l.outerConeRadians, 0.4f);
  {
    // A negative intensity is clamped to a dark light that stays (docs/scene-format.md), so
    // the renderer does not replace the scene's lighting by its default sky.
    json dark = doc;
    dark["extensions"]["KHR_lights_punctual"]["lights"][0]["intensity"] = -5;
    std::vector<std::string> darkErrors;
    const auto darkScene = loadGltf(write("dark.gltf", dark.dump()), darkErrors);
    ASSERT_TRUE(darkScene);
    ASSERT_EQ(darkScene->lights.size(), 1u);
    EXPECT_EQ(darkScene->lights[0].intensity, 0.0f);
    EXPECT_TRUE(anyContains(darkScene->warnings, "clamped to 0"));
  }
  {
    // Malformed or out-of-range light values are reported, not taken silently: a negative
    // colour component had made negative pixels, a colour of four numbers rendered white, an
    // intensity "10" rendered at 1, and values beyond a float overflowed to a dark light.
    const auto lightWith = [&](const char* key, const json& value, std::vector<std::string>& warnings) -> std::optional<LightDesc> {
      json bad = doc;
      bad["extensions"]["KHR_lights_punctual"]["lights"][0][key] = value;
      std::vector<std::string> badErrors;
      const auto badScene = loadGltf(write("bad_light.gltf", bad.dump()), badErrors);
      EXPECT_TRUE(badScene.has_value());
      if (!badScene) return std::nullopt;
      warnings = badScene->warnings;
      if (badScene->lights.empty()) return std::nullopt;
      return badScene->lights[0];
    };
    std::vector<std::string> warnings;
    std::optional<LightDesc> l2 = lightWith("color", {1, -1, 1}, warnings);
    ASSERT_TRUE(l2);
    EXPECT_EQ(l2->emission.rgb, Vec3(1, 0, 1));
    EXPECT_TRUE(anyContains(warnings, "light 0 has a negative colour component; clamped to 0"));
    l2 = lightWith("color", {1, 0, 0, 1}, warnings);
    ASSERT_TRUE(l2);
    EXPECT_TRUE(anyContains(warnings, "light 0 has a colour that is not three finite numbers; white is used"));
    l2 = lightWith("intensity", "10", warnings);
    ASSERT_TRUE(l2);
    EXPECT_TRUE(anyContains(warnings, "light 0 has an intensity that is not a number; 1 is used"));
    EXPECT_FALSE(lightWith("intensity", 1e39, warnings));
    EXPECT_TRUE(anyContains(warnings, "beyond the range of a 32-bit float; ignored"));
    EXPECT_FALSE(lightWith("color", {1e39, 1, 1}, warnings));
    EXPECT_TRUE(anyContains(warnings, "light 0 has a colour beyond the range of a 32-bit float; ignored"));
  }
  ASSERT_EQ(scene->cameras.size(), 2u);
  const CameraDesc& c = scene->cameras[0];
  EXPECT_NEAR(glm::dot(Vec3(c.cameraToWorld * Vec4(0, 0, -1, 0)), Vec3(0, -1, 0)), 1.0f, 1e-6f);
  EXPECT_FLOAT_EQ(c.yFovRadians, 0.6f);
  EXPECT_FLOAT_EQ(c.aspect, 1.5f);
  EXPECT_EQ(c.orthoHalfHeight, 0.0f);
  const CameraDesc& ortho = scene->cameras[1];
  EXPECT_EQ(ortho.orthoHalfHeight, 0.5f);
  EXPECT_EQ(ortho.aspect, 4.0f);  // xmag / ymag
  doc["cameras"][1]["orthographic"]["ymag"] = 0;
  scene = loadGltf(write("ortho0.gltf", doc.dump()), errors);
  ASSERT_TRUE(scene) << errors[0];
  EXPECT_EQ(scene->cameras.size(), 1u);
  EXPECT_TRUE(anyContains(scene->warnings, "ymag"));
}

TEST_F(GltfMutated, EveryByteTruncationOfAGlbFailsCleanly) {
  SKIP_WITHOUT_SHARED();
  std::ifstream in(kShared + "/Box/glTF-Binary/Box.glb", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (size_t length = 0; length < bytes.size(); length += 7) {
    std::vector<std::string> errors;
    EXPECT_FALSE(loadGltf(write("cut.glb", bytes.substr(0, length)), errors).has_value()) << length;
  }
}

}  // namespace
}  // namespace tex::render
