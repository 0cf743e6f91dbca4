// Scene JSON: every section of the format, inline shapes, and error messages that point at
// file:line:column and say what is wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "renderer/scene/load_scene.h"
#include "renderer/scene/json_located.h"
#include "renderer/scene/scene_json.h"
#include "renderer/scene/shapes.h"

namespace tex::render {
namespace {

const std::string kFixtures = TEX_SOURCE_DIR "/tests/renderer/data/scenes";

std::optional<SceneDescription> parse(const std::string& text, std::vector<std::string>& errors) {
  return parseSceneJson(text, "scene.json", kFixtures, errors);
}

// Parses text that must fail; returns the first error.
std::string firstError(const std::string& text) {
  std::vector<std::string> errors;
  EXPECT_FALSE(parse(text, errors).has_value()) << text;
  return errors.empty() ? std::string() : errors[0];
}

size_t triangles(const MeshPrimitive& p) { return p.indices.size() / 3; }

const MeshPrimitive* meshNamed(const SceneDescription& scene, const std::string& name) {
  for (const MeshPrimitive& p : scene.primitives)
    if (p.meshName == name) return &p;
  return nullptr;
}

TEST(SceneJson, FixtureLoadsEverySection) {
  std::string error;
  std::optional<SceneDescription> scene = loadScene(kFixtures + "/shapes.json", error);
  ASSERT_TRUE(scene) << error;
  // Two instances of quad.gltf's 2 nodes share its one primitive per file; 4 shapes.
  EXPECT_EQ(scene->instances.size(), 2u + 2u + 4u);
  ASSERT_NE(meshNamed(*scene, "ball"), nullptr);
  EXPECT_EQ(triangles(*meshNamed(*scene, "ball")), 2u * 16u * (8u - 1u));
  EXPECT_EQ(triangles(*meshNamed(*scene, "floor")), 2u);
  EXPECT_EQ(triangles(*meshNamed(*scene, "crate")), 12u);

  // Materials: quad.gltf's "Red" twice, then Glass and Lamp, then White created by a shape.
  std::vector<std::string> names;
  for (const GltfMaterial& m : scene->materials) names.push_back(m.name);
  EXPECT_EQ(names, (std::vector<std::string>{"Red", "Red", "Glass", "Lamp", "White"}));
  EXPECT_EQ(scene->materials[2].transmissionFactor, 1.0f);
  EXPECT_EQ(scene->materials[2].dispersion, 0.5f);
  EXPECT_EQ(scene->materials[3].emissiveStrength, 10.0f);
  EXPECT_EQ(scene->materials[size_t(meshNamed(*scene, "crate")->material)].name, "White");

  // Bindings with resolved paths and typed parameters.
  ASSERT_EQ(scene->texMaterials.size(), 2u);
  const TexMaterialBinding& white = scene->texMaterials[0];
  EXPECT_EQ(white.matchMaterial, "White");
  EXPECT_EQ(white.entry, "white");
  EXPECT_TRUE(std::filesystem::exists(white.file)) << white.file;
  EXPECT_EQ(std::filesystem::path(white.file).filename(), "walls.tex");
  EXPECT_NE(white.origin.find("shapes.json:"), std::string::npos) << white.origin;
  EXPECT_EQ(white.params.at("albedo").kind, TexParamValue::Kind::Spectrum);
  EXPECT_EQ(white.params.at("albedo").spectrum.kind, SpectrumDesc::Kind::Rgb);
  EXPECT_EQ(white.params.at("roughness").kind, TexParamValue::Kind::Float);
  EXPECT_FLOAT_EQ(white.params.at("roughness").floats[0], 0.1f);
  EXPECT_EQ(white.params.at("layers").kind, TexParamValue::Kind::Int);
  EXPECT_EQ(white.params.at("layers").intValue, 3);
  EXPECT_EQ(white.params.at("tint").kind, TexParamValue::Kind::Vec);
  EXPECT_EQ(white.params.at("tint").floats, (std::vector<float>{1, 0.5f, 0.25f}));
  EXPECT_EQ(white.params.at("glossy").kind, TexParamValue::Kind::Bool);
  EXPECT_TRUE(white.params.at("glossy").boolValue);
  EXPECT_EQ(white.params.at("emitter").spectrum.kind, SpectrumDesc::Kind::Blackbody);
  EXPECT_EQ(white.params.at("emitter").spectrum.kelvin, 3000.0f);
  EXPECT_EQ(white.params.at("emitter").spectrum.scale, 2.0f);
  EXPECT_EQ(scene->texMaterials[1].matchMesh, "Quad");
  EXPECT_TRUE(scene->warnings.empty()) << scene->warnings[0];

  // The scene's own camera.
  ASSERT_EQ(scene->cameras.size(), 1u);
  const CameraDesc& camera = scene->cameras[0];
  const Vec3 view = Vec3(camera.cameraToWorld * Vec4(0, 0, -1, 0));
  const Vec3 expected = glm::normalize(Vec3(0, 1, 0) - Vec3(0, 2, 8));
  EXPECT_NEAR(glm::dot(view, expected), 1.0f, 1e-6f);
  EXPECT_NEAR(Vec3(camera.cameraToWorld * Vec4(0, 1, 0, 0)).y, std::sqrt(1 - expected.y * expected.y), 1e-5f);
  EXPECT_EQ(Vec3(camera.cameraToWorld[3]), Vec3(0, 2, 8));
  EXPECT_NEAR(camera.yFovRadians, 35.0f * kPi / 180.0f, 1e-6f);
  EXPECT_EQ(camera.lensRadius, 0.05f);
  EXPECT_NEAR(camera.focusDistance, std::sqrt(65.0f), 1e-5f);  // default: distance to "to"

  // Lights.
  ASSERT_EQ(scene->lights.size(), 4u);
  EXPECT_EQ(scene->lights[0].kind, LightDesc::Kind::Point);
  EXPECT_EQ(scene->lights[0].intensity, 10.0f);
  EXPECT_EQ(scene->lights[0].emission.kind, SpectrumDesc::Kind::Named);
  EXPECT_EQ(scene->lights[0].emission.name, "D65");
  EXPECT_EQ(scene->lights[1].kind, LightDesc::Kind::Spot);
  EXPECT_NEAR(glm::dot(scene->lights[1].direction, Vec3(0, -1, 0)), 1.0f, 1e-6f);
  EXPECT_NEAR(scene->lights[1].outerConeRadians, 20.0f * kPi / 180.0f, 1e-6f);
  EXPECT_EQ(scene->lights[1].emission.lambdaNm, (std::vector<float>{400, 550, 700}));
  EXPECT_EQ(scene->lights[2].kind, LightDesc::Kind::Directional);
  EXPECT_EQ(scene->lights[2].emission.rgb, Vec3(1, 0.9f, 0.8f));
  EXPECT_EQ(scene->lights[3].kind, LightDesc::Kind::ConstantEnvironment);
  EXPECT_EQ(scene->lights[3].emission.value, 0.25f);

  EXPECT_TRUE(scene->resolutionGiven);
  EXPECT_EQ(scene->settings.width, 320);
  EXPECT_EQ(scene->settings.height, 240);
  EXPECT_EQ(scene->settings.spp, 64);
  EXPECT_EQ(scene->settings.maxDepth, 12);
  EXPECT_EQ(scene->settings.rouletteDepth, 6);
  EXPECT_EQ(scene->settings.wavelengths, 8);
  EXPECT_EQ(scene->settings.seed, 7u);
  EXPECT_EQ(scene->settings.integrator, "path");
}

TEST(SceneJson, GltfTransformsApplyToEveryNode) {
  std::vector<std::string> errors;
  auto scene = parse(R"({"gltf": [{"file": "quad.gltf", "transform": {"translate": [100, 0, 0]}}]})", errors);
  ASSERT_TRUE(scene) << errors[0];
  const Bounds3 b = worldBounds(*scene);
  EXPECT_NEAR(b.lower.x, 98.0f, 1e-4f);  // quad.gltf alone spans x in [-2, 2]
  EXPECT_NEAR(b.upper.x, 102.0f, 1e-4f);
  EXPECT_NEAR(b.lower.z, -3.0f, 1e-4f);
}

TEST(SceneJson, SyntaxErrorReportsLineAndColumn) {
  const std::string error = firstError("{\n  \"render\": {\n    \"spp\": 4,,\n  }\n}\n");
  EXPECT_EQ(error.rfind("scene.json:3:14: ", 0), 0u) << error;
  EXPECT_NE(error.find("syntax error"), std::string::npos) << error;
  // Columns count characters, not bytes.
  const std::string utf8 = firstError("{\"_c\": \"\xC3\xA9\xC3\xA9\", ]}");
  EXPECT_EQ(utf8.rfind("scene.json:1:14: ", 0), 0u) << utf8;  // 16 if bytes were counted
  EXPECT_EQ(firstError("").rfind("scene.json:1:1: ", 0), 0u) << firstError("");
}

// Nesting is bounded (a file 40000 deep took 3.3 GB: every level keeps its pointer), and a
// byte order mark is not a column of line 1.
TEST(SceneJson, DeepNestingIsAnErrorAndAByteOrderMarkIsNoColumn) {
  const std::string deep = firstError("{\"_c\": " + std::string(1000, '[') + std::string(1000, ']') + "}");
  EXPECT_NE(deep.find("levels deep"), std::string::npos) << deep;
  EXPECT_EQ(deep.rfind("scene.json:1:", 0), 0u) << deep;
  const std::string bom = firstError("\xEF\xBB\xBF{\"rendr\": {}}");
  EXPECT_EQ(bom.rfind("scene.json:1:2: ", 0), 0u) << bom;
}

// Keys starting with '_' are comments everywhere: in params, pbr_materials, match, and
// beside a matrix (each was an error).
// Positions come from checkpoints every 4 KB (a scan from the first byte per position made files
// of thousands of lights load in quadratic time); they must be what a scan from the start gives,
// across checkpoints, multi-byte characters and a byte order mark.
TEST(SceneJson, PositionsFromCheckpointsMatchAScanFromTheStart) {
  std::string text = "\xEF\xBB\xBF[";
  for (int i = 0; i < 3000; ++i) text += (i % 7 == 0 ? "\n" : "") + std::string(i % 5 == 0 ? "\"\xC3\xA9\xE2\x82\xAC\", " : "1, ");
  text += "0]";
  std::string error;
  const std::optional<LocatedJson> json = parseLocatedJson(text, error);
  ASSERT_TRUE(json) << error;
  size_t line = 1, column = 1;
  for (size_t offset = 3; offset <= text.size(); ++offset) {
    if (offset % 97 == 0 || (offset > 4090 && offset < 4200) || offset == text.size())
      ASSERT_EQ(json->lineColumn(offset), std::to_string(line) + ":" + std::to_string(column)) << offset;
    if (offset == text.size()) break;
    if (text[offset] == '\n') ++line, column = 1;
    else if ((static_cast<unsigned char>(text[offset]) & 0xC0) != 0x80) ++column;
  }
  EXPECT_EQ(json->lineColumn(0), "1:1");
  EXPECT_EQ(json->lineColumn(1), "1:1");  // inside the byte order mark
}

TEST(SceneJson, CommentKeysAreIgnoredAtEveryLevel) {
  std::vector<std::string> errors;
  const auto scene = parse(R"({
    "gltf": [{"file": "quad.gltf", "transform": {"_why": "identity", "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}}],
    "shapes": [{"type": "quad", "material": "M"}],
    "pbr_materials": {"_why": "a comment", "P": {"base_color": [0.5, 0.5, 0.5]}},
    "materials": [{"match": {"_why": "x", "material": "M"}, "file": "walls.tex", "entry": "white",
                   "params": {"_why": "a comment"}}]})", errors);
  ASSERT_TRUE(scene) << (errors.empty() ? "" : errors[0]);
  ASSERT_EQ(scene->texMaterials.size(), 1u);
  EXPECT_TRUE(scene->texMaterials[0].params.empty());
}

// An image environment ignores emission, so giving one is an error (it was accepted silently).
TEST(SceneJson, ImageEnvironmentWithEmissionIsAnError) {
  const std::string error =
      firstError(R"({"lights": [{"type": "environment", "image": "sky.exr", "emission": {"rgb": [1, 0, 0]}}]})");
  EXPECT_NE(error.find("takes its colour from the image"), std::string::npos) << error;
}

TEST(SceneJson, DuplicateKeyIsAnError) {
  const std::string error = firstError("{\"render\": {\"spp\": 4,\n \"spp\": 8}}");
  EXPECT_EQ(error.rfind("scene.json:2:2: ", 0), 0u) << error;
  EXPECT_NE(error.find("duplicate key \"spp\""), std::string::npos) << error;
}

// Values the renderer would not honour are errors, not silently replaced: an integrator it
// does not have, and an rgb "as" it does not know.
TEST(SceneJson, UnknownIntegratorAndRgbUseAreErrors) {
  const std::string integrator = firstError("{\"render\": {\"integrator\": \"bdpt\"}}");
  EXPECT_NE(integrator.find("unknown integrator \"bdpt\" (available: path)"), std::string::npos) << integrator;
  const std::string as = firstError(
      "{\"materials\": [{\"match\": {\"material\": \"m\"}, \"file\": \"walls.tex\", \"entry\": \"e\",\n"
      " \"params\": {\"s\": {\"rgb\": [1, 1, 1], \"as\": \"light\"}}}]}");
  EXPECT_EQ(as.rfind("scene.json:2:", 0), 0u) << as;
  EXPECT_NE(as.find("\"as\" must be"), std::string::npos) << as;
}

TEST(SceneJson, UnknownKeyNamesItsPositionAndSuggests) {
  const std::string error = firstError("{\n  \"camera\": {\"from\": [0, 0, 5],\n     \"fov_dg\": 40}\n}");
  EXPECT_EQ(error.rfind("scene.json:3:6: camera.fov_dg: unknown key", 0), 0u) << error;
  EXPECT_NE(error.find("did you mean \"fov_deg\"?"), std::string::npos) << error;
  const std::string top = firstError("{\"light\": []}");
  EXPECT_NE(top.find("did you mean \"lights\"?"), std::string::npos) << top;
  const std::string far = firstError("{\"zzzzzzzz\": 1}");
  EXPECT_NE(far.find("allowed:"), std::string::npos) << far;
}

TEST(SceneJson, WrongTypesAndRanges) {
  EXPECT_NE(firstError(R"({"render": {"spp": "many"}})").find("render.spp: expected an integer, got a string"),
            std::string::npos);
  EXPECT_NE(firstError(R"({"render": {"wavelengths": 5}})").find("must be 4 or 8"), std::string::npos);
  EXPECT_NE(firstError(R"({"render": {"roulette_depth": 0}})").find("render.roulette_depth"), std::string::npos);
  EXPECT_NE(firstError(R"({"render": {"roulette_depth": 2.5}})").find("render.roulette_depth: expected an integer"),
            std::string::npos);
  EXPECT_NE(firstError(R"({"render": {"resolution": [640]}})").find("[width, height]"), std::string::npos);
  EXPECT_NE(firstError(R"({"lights": [{"type": "point", "position": [0, 1]}]})").find("lights[0].position: expected an array of 3 numbers"),
            std::string::npos);
  EXPECT_NE(firstError(R"({"lights": [{"type": "laser"}]})").find("unknown light type \"laser\""), std::string::npos);
  EXPECT_NE(firstError(R"({"lights": [{"type": "point", "intensity": -1}]})").find("must be >= 0"), std::string::npos);
  EXPECT_NE(firstError(R"({"lights": [{"type": "point", "emission": -3}]})").find("must not be negative"), std::string::npos);
  EXPECT_NE(firstError(R"({"lights": [{"type": "point", "emission": {"rgb": [1, 1, 1], "scale": -1}}]})").find("must not be negative"),
            std::string::npos);
  EXPECT_NE(firstError(R"({"materials": [{"match": {"material": ""}, "file": "walls.tex", "entry": "white"}]})").find("the name is empty"),
            std::string::npos);
  // Beyond a float: said so, not "must be >= 0"; a documented minimum written in the file
  // is accepted (0.001 as a double is above the float 1e-3f it is compared with).
  EXPECT_NE(firstError(R"({"lights": [{"type": "point", "intensity": 1e39}]})").find("32-bit float"), std::string::npos);
  std::vector<std::string> errors;
  EXPECT_TRUE(parse(R"({"camera": {"fov_deg": 0.001}})", errors)) << (errors.empty() ? "" : errors[0]);
  EXPECT_NE(firstError(R"({"shapes": [{"type": "sphere", "radius": "big"}]})").find("expected a number"), std::string::npos);
  EXPECT_NE(firstError(R"({"shapes": [{"type": "torus"}]})").find("unknown shape type \"torus\""), std::string::npos);
  EXPECT_NE(firstError(R"({"camera": {"from": [0, 0, 0], "to": [0, 0, 0]}})").find("same point"), std::string::npos);
  EXPECT_NE(firstError(R"({"camera": {"from": [0, 0, 0], "to": [0, 1, 0]}})").find("parallel"), std::string::npos);
  EXPECT_NE(firstError(R"({"camera": {"lens_radius": 0.1}})").find("thinlens"), std::string::npos);
  EXPECT_NE(firstError(R"({"camera": {"type": "orthographic"}})").find("needs \"ymag\""), std::string::npos);
  EXPECT_NE(firstError(R"({"camera": {"type": "orthographic", "ymag": 1, "fov_deg": 30}})").find("no field of view"),
            std::string::npos);
  EXPECT_NE(firstError(R"({"camera": {"ymag": 1}})").find("ymag needs"), std::string::npos);
  EXPECT_NE(firstError(R"({"camera": {"type": "orthographic", "ymag": 0}})").find("ymag"), std::string::npos);
  EXPECT_NE(firstError(R"({"render": {"camera": 2}})").find("camera 2 does not exist"), std::string::npos);
  EXPECT_NE(firstError(R"([1, 2])").find("expected an object, got an array"), std::string::npos);
}

TEST(SceneJson, SpectraInEveryForm) {
  std::vector<std::string> errors;
  auto scene = parse(R"({"lights": [
    {"type": "environment", "emission": 0.5},
    {"type": "environment", "emission": {"rgb": [0.1, 0.2, 0.3], "scale": 4}},
    {"type": "environment", "emission": {"blackbody": 3000, "scale": 2}},
    {"type": "environment", "emission": {"named": "cornell-white"}},
    {"type": "environment", "emission": {"tabulated": [[400, 0.1], [500, 0.3], [600, 0.2]]}}]})",
                     errors);
  ASSERT_TRUE(scene) << errors[0];
  const auto& l = scene->lights;
  EXPECT_EQ(l[0].emission.kind, SpectrumDesc::Kind::Constant);
  EXPECT_EQ(l[0].emission.value, 0.5f);
  EXPECT_EQ(l[1].emission.kind, SpectrumDesc::Kind::Rgb);
  EXPECT_EQ(l[1].emission.rgb, Vec3(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(l[1].emission.scale, 4.0f);
  EXPECT_EQ(l[2].emission.kind, SpectrumDesc::Kind::Blackbody);
  EXPECT_EQ(l[2].emission.kelvin, 3000.0f);
  EXPECT_EQ(l[3].emission.name, "cornell-white");
  EXPECT_EQ(l[4].emission.values, (std::vector<float>{0.1f, 0.3f, 0.2f}));

  EXPECT_NE(firstError(R"({"lights": [{"type": "environment", "emission": {"rgb": [1, 1, 1], "named": "D65"}}]})")
                .find("exactly one of"),
            std::string::npos);
  EXPECT_NE(firstError(R"({"lights": [{"type": "environment", "emission": {"tabulated": [[500, 1], [400, 1]]}}]})")
                .find("wavelengths must increase"),
            std::string::npos);
  EXPECT_NE(firstError(R"({"lights": [{"type": "environment", "emission": {"rbg": [1, 1, 1]}}]})")
                .find("did you mean \"rgb\"?"),
            std::string::npos);
}

TEST(SceneJson, RelativePathsResolveAgainstTheSceneFileAndMissingFilesAreErrors) {
  const std::string missing = firstError("{\n\"gltf\": [\"nope.glb\"]}");
  EXPECT_EQ(missing.rfind("scene.json:2:10: gltf[0]: file \"nope.glb\" not found", 0), 0u) << missing;
  EXPECT_NE(missing.find(kFixtures), std::string::npos) << missing;
  const std::string tex = firstError(R"({"materials": [{"match": {"mesh": "m"}, "file": "none.tex", "entry": "f"}]})");
  EXPECT_NE(tex.find("materials[0].file: file \"none.tex\" not found"), std::string::npos) << tex;
  const std::string exr = firstError(R"({"lights": [{"type": "environment", "image": "sky.exr"}]})");
  EXPECT_NE(exr.find("not found"), std::string::npos) << exr;
  // A broken glTF file: the scene error points at the entry, and the glTF error follows.
  std::vector<std::string> errors;
  EXPECT_FALSE(parse(R"({"gltf": ["walls.tex"]})", errors));
  ASSERT_GE(errors.size(), 2u);
  EXPECT_NE(errors[0].find("could not load the glTF file"), std::string::npos) << errors[0];
}

TEST(SceneJson, BindingThatMatchesNothingIsAWarning) {
  std::vector<std::string> errors;
  auto scene = parse(R"({"materials": [{"match": {"material": "Nope"}, "file": "walls.tex", "entry": "white"}]})", errors);
  ASSERT_TRUE(scene) << errors[0];
  ASSERT_EQ(scene->warnings.size(), 1u);
  EXPECT_NE(scene->warnings[0].find("no material named \"Nope\""), std::string::npos) << scene->warnings[0];
  EXPECT_NE(firstError(R"({"materials": [{"match": {"material": "A", "mesh": "B"}, "file": "walls.tex", "entry": "w"}]})")
                .find("exactly one"),
            std::string::npos);
}

// From a hunt against scene-format.md: two bindings for one name are an error (the second had
// been dropped silently); "as" on a light's emission other than "illuminant" is an error (it
// had been accepted and ignored); a base_color above 1 is an error (clamped silently); an
// integer beyond 32 bits feeds a Float parameter (3000000000 had been refused, 3e9 taken);
// a scene file's light carries its line and column for later messages.
TEST(SceneJson, AmbiguousOrIgnoredSettingsAreErrors) {
  EXPECT_NE(firstError(R"({"materials": [{"match": {"material": "M"}, "file": "walls.tex", "entry": "white"},
                                        {"match": {"material": "M"}, "file": "walls.tex", "entry": "red"}]})")
                .find("a binding for the material \"M\" already exists (at scene.json:1:16)"),
            std::string::npos);
  EXPECT_NE(firstError(R"({"lights": [{"type": "environment", "emission": {"rgb": [1, 1, 1], "as": "reflectance"}}]})")
                .find("a light's rgb emission is an illuminant"),
            std::string::npos);
  EXPECT_NE(firstError(R"({"pbr_materials": {"M": {"base_color": [2, 0.5, 0.5]}}})").find("components must be in [0, 1]"),
            std::string::npos);
  // An environment's orientation from a matrix that shears: no rotation to take.
  EXPECT_NE(firstError(R"({"lights": [{"type": "environment", "transform": {"matrix": [1, 0, 0, 0, 1, 3, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}}]})")
                .find("an environment's transform must be a rotation"),
            std::string::npos);
  std::vector<std::string> errors;
  // A rotation with a scale and a translation is fine.
  ASSERT_TRUE(parse(R"({"lights": [{"type": "environment", "transform": {"rotate": [0, 1, 0, 40], "scale": [1, 3, 1], "translate": [1, 2, 3]}}]})",
                    errors))
      << errors[0];
  auto scene = parse(R"({"lights": [{"type": "environment", "emission": {"rgb": [1, 1, 1], "as": "illuminant"}}],
                         "materials": [{"match": {"material": "M"}, "file": "walls.tex", "entry": "white", "params": {"f": 3000000000}}]})",
                     errors);
  ASSERT_TRUE(scene) << errors[0];
  ASSERT_EQ(scene->texMaterials.size(), 1u);
  const TexParamValue& f = scene->texMaterials[0].params.at("f");
  EXPECT_EQ(f.kind, TexParamValue::Kind::Float);
  EXPECT_EQ(f.floats[0], 3.0e9f);
  ASSERT_EQ(scene->lights.size(), 1u);
  EXPECT_EQ(scene->lights[0].origin, "scene.json:1:13");
  // A light without emission is white, as glTF's default light and the default sky are (a
  // constant spectrum of 1 had developed to a pinkish (1.20, 0.95, 0.91)).
  scene = parse(R"({"lights": [{"type": "point", "position": [0, 1, 0]}]})", errors);
  ASSERT_TRUE(scene) << errors[0];
  EXPECT_EQ(scene->lights[0].emission.kind, SpectrumDesc::Kind::Rgb);
  EXPECT_EQ(scene->lights[0].emission.rgb, Vec3(1.0f));
  EXPECT_EQ(scene->lights[0].emission.rgbAs, SpectrumDesc::RgbAs::Illuminant);
}

TEST(SceneJson, OrthographicCamera) {
  std::vector<std::string> errors;
  auto scene = parse(R"({"camera": {"type": "orthographic", "from": [0, 0, 5], "ymag": 2.5, "aspect": 2}})", errors);
  ASSERT_TRUE(scene) << errors[0];
  ASSERT_EQ(scene->cameras.size(), 1u);
  EXPECT_EQ(scene->cameras[0].orthoHalfHeight, 2.5f);
  EXPECT_EQ(scene->cameras[0].aspect, 2.0f);
  EXPECT_EQ(scene->cameras[0].lensRadius, 0.0f);
}

TEST(SceneJson, SceneCamerasComeBeforeGltfCameras) {
  std::vector<std::string> errors;
  const std::string duck = TEX_SOURCE_DIR "/../shared/gltf/Duck/glTF-Binary/Duck.glb";
  if (!std::filesystem::exists(duck)) GTEST_SKIP() << "shared glTF models not found";
  auto scene = parse(R"({"gltf": [")" + duck + R"("], "camera": {"name": "mine", "from": [0, 0, 5]}})", errors);
  ASSERT_TRUE(scene) << errors[0];
  ASSERT_EQ(scene->cameras.size(), 2u);
  EXPECT_EQ(scene->cameras[0].name, "mine");
}

// ---- shapes ---------------------------------------------------------------------------

TEST(Shapes, SphereIsClosedWithOutwardNormalsOnTheSurface) {
  const Vec3 center(1, 2, 3);
  for (int segments : {3, 7, 32})
    for (int rings : {2, 5, 16}) {
      const MeshPrimitive s = makeSphere(center, 2.0f, segments, rings, false);
      ASSERT_EQ(triangles(s), size_t(2 * segments * (rings - 1)));
      for (size_t v = 0; v < s.positions.size(); ++v) {
        EXPECT_NEAR(glm::length(s.positions[v] - center), 2.0f, 1e-5f);
        EXPECT_NEAR(glm::dot(s.normals[v], (s.positions[v] - center) / 2.0f), 1.0f, 1e-5f);
      }
      // Every face's winding gives an outward geometric normal; the divergence theorem gives
      // the enclosed volume, which approaches 4/3 pi r^3 from below.
      double volume = 0;
      for (size_t t = 0; t < s.indices.size(); t += 3) {
        const Vec3 a = s.positions[s.indices[t]] - center, b = s.positions[s.indices[t + 1]] - center,
                   c = s.positions[s.indices[t + 2]] - center;
        const Vec3 n = glm::cross(b - a, c - a);
        EXPECT_GT(glm::dot(n, a + b + c), 0.0f);
        volume += glm::dot(a, glm::cross(b, c)) / 6.0;
      }
      EXPECT_GT(volume, 0.0);
      EXPECT_LT(volume, 4.0 / 3.0 * kPi * 8.0);
      if (segments == 32 && rings == 16) {
        EXPECT_NEAR(volume, 4.0 / 3.0 * kPi * 8.0, 0.05 * 4.0 / 3.0 * kPi * 8.0);
      }
    }
  const MeshPrimitive inward = makeSphere(center, 1.0f, 8, 4, true);
  for (size_t v = 0; v < inward.positions.size(); ++v) EXPECT_LT(glm::dot(inward.normals[v], inward.positions[v] - center), 0.0f);
}

TEST(Shapes, BoxAndQuad) {
  const MeshPrimitive box = makeBox(Vec3(1, 0, 0), Vec3(2, 4, 6), false);
  EXPECT_EQ(triangles(box), 12u);
  double volume = 0, area = 0;
  for (size_t t = 0; t < box.indices.size(); t += 3) {
    const Vec3 a = box.positions[box.indices[t]], b = box.positions[box.indices[t + 1]], c = box.positions[box.indices[t + 2]];
    const Vec3 n = glm::cross(b - a, c - a);
    area += 0.5 * glm::length(n);
    volume += glm::dot(a, glm::cross(b, c)) / 6.0;
    EXPECT_GT(glm::dot(n, box.normals[box.indices[t]]), 0.0f);  // winding agrees with the normal
  }
  EXPECT_NEAR(volume, 48.0, 1e-4);
  EXPECT_NEAR(area, 2 * (8 + 12 + 24), 1e-4);
  const MeshPrimitive quad = makeQuad(Vec3(0), Vec3(2, 0, 0), Vec3(0, 0, -3));
  EXPECT_EQ(triangles(quad), 2u);
  EXPECT_EQ(quad.normals[0], Vec3(0, 1, 0));
  const Vec3 n = glm::cross(quad.positions[1] - quad.positions[0], quad.positions[2] - quad.positions[0]);
  EXPECT_GT(n.y, 0.0f);
}

TEST(SceneJson, ShapeTransformsAndDefaults) {
  std::vector<std::string> errors;
  auto scene = parse(R"({"shapes": [
      {"type": "quad", "size": [4, 2], "transform": {"translate": [0, 1, 0]}},
      {"type": "sphere"},
      {"type": "box", "inward": true, "transform": {"matrix": [2,0,0,0, 0,2,0,0, 0,0,2,0, 0,0,0,1]}}]})",
                     errors);
  ASSERT_TRUE(scene) << errors[0];
  ASSERT_EQ(scene->primitives.size(), 3u);
  EXPECT_EQ(scene->primitives[0].meshName, "shape_0");
  EXPECT_EQ(scene->primitives[0].material, -1);
  EXPECT_EQ(triangles(scene->primitives[1]), 2u * 64u * 31u);
  EXPECT_EQ(scene->instances[2].objectToWorld[0][0], 2.0f);
  SceneDescription quadOnly = *scene;
  quadOnly.instances.resize(1);
  const Bounds3 b = worldBounds(quadOnly);
  EXPECT_EQ(b.lower, Vec3(-2, 1, -1));
  EXPECT_EQ(b.upper, Vec3(2, 1, 1));
  EXPECT_NE(firstError(R"({"shapes": [{"type": "quad", "size": [1, 1], "corner": [0, 0, 0]}]})").find("not both"),
            std::string::npos);
  EXPECT_NE(firstError(R"({"shapes": [{"type": "box", "transform": {"matrix": [1], "scale": 2}}]})").find("cannot be combined"),
            std::string::npos);
}

TEST(SceneJson, SphereIsSmoothUnlessAskedFlat) {
  std::vector<std::string> errors;
  auto scene = parse(R"({"shapes": [{"type": "sphere", "segments": 8, "rings": 4},
                                    {"type": "sphere", "segments": 8, "rings": 4, "smooth": false}]})",
                     errors);
  ASSERT_TRUE(scene) << errors[0];
  ASSERT_EQ(scene->primitives.size(), 2u);
  EXPECT_EQ(scene->primitives[0].normals.size(), scene->primitives[0].positions.size());
  EXPECT_TRUE(scene->primitives[1].normals.empty());  // face normals: flat facets
  EXPECT_EQ(scene->primitives[1].positions, scene->primitives[0].positions);
  EXPECT_EQ(scene->primitives[1].indices, scene->primitives[0].indices);
  EXPECT_NE(firstError(R"({"shapes": [{"type": "sphere", "smooth": 1}]})"), "");
}

}  // namespace
}  // namespace tex::render
