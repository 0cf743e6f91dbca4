// What a scene file says, after loading and validation, as plain data: meshes in object
// space with their instances, images, glTF materials, .tex material bindings, cameras, lights
// and render settings. Loaders (glTF, scene JSON) fill it; the renderer builds Embree
// geometry, compiled materials and lights from it. No renderer types in here.
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "renderer/core/geometry.h"

namespace tex::render {

// A spectrum as a scene file writes it (renderer/spectra/spectrum_desc.h evaluates it).
struct SpectrumDesc {
  enum class Kind : uint8_t {
    Constant,    // value
    Rgb,         // rgb, upsampled (Jakob & Hanika 2019); reflectance, unbounded or illuminant by use
    Blackbody,   // kelvin, normalised to peak 1, times scale
    Named,       // name from the built-in library ("cornell-white", "Au-eta", "D65", ...)
    Tabulated,   // (lambdaNm, value) pairs, linearly interpolated, 0 outside
  };
  Kind kind = Kind::Constant;
  float value = 0;
  Vec3 rgb{0.0f};
  float kelvin = 6500;
  float scale = 1;  // multiplies any kind
  std::string name;
  std::vector<float> lambdaNm, values;
  // How an Rgb given to a .tex Spectrum parameter is upsampled (scene JSON "as"). ByValue:
  // a reflectance when every component is at most 1, else an unbounded quantity. Lights and
  // environments always read their colour as an illuminant.
  enum class RgbAs : uint8_t { ByValue, Reflectance, Unbounded, Illuminant } rgbAs = RgbAs::ByValue;
};

enum class WrapMode : uint8_t { Repeat, ClampToEdge, MirroredRepeat };

// A decoded image, 1-4 channels, top row first, width * height * channels values in one of
// two stores: 8-bit sources keep their bytes (value = byte / 255; a quarter of the memory, and
// texture lookups decode a byte by table), others floats (16-bit sources: value in [0,1]).
// glTF colour textures are sRGB encoded: the loader keeps the encoded values and the lookup's
// `srgb` says how to decode them.
struct ImageData {
  std::string name;
  int width = 0, height = 0, channels = 0;
  std::vector<float> pixels;  // used when `bytes` is empty
  std::vector<uint8_t> bytes;

  size_t valueCount() const { return bytes.empty() ? pixels.size() : bytes.size(); }
  float value(size_t i) const { return bytes.empty() ? pixels[i] : float(bytes[i]) / 255.0f; }
};

struct TextureRef {
  int image = -1;  // index into SceneDescription::images; -1: none
  int texCoord = 0;
  WrapMode wrapS = WrapMode::Repeat, wrapT = WrapMode::Repeat;
  bool nearest = false;  // magnification filter NEAREST
  // KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) uv
  Vec2 offset{0.0f}, scale{1.0f};
  float rotation = 0;
};

// glTF 2.0 metallic-roughness material plus the extensions we read.
struct GltfMaterial {
  std::string name;
  Vec4 baseColorFactor{1.0f};
  TextureRef baseColorTexture;
  float metallicFactor = 1, roughnessFactor = 1;
  TextureRef metallicRoughnessTexture;
  TextureRef normalTexture;
  float normalScale = 1;
  Vec3 emissiveFactor{0.0f};
  float emissiveStrength = 1;  // KHR_materials_emissive_strength
  TextureRef emissiveTexture;
  float transmissionFactor = 0;  // KHR_materials_transmission
  TextureRef transmissionTexture;
  float ior = 1.5f;              // KHR_materials_ior
  float dispersion = 0;          // KHR_materials_dispersion (20 / Abbe number)
  float thicknessFactor = 0;     // KHR_materials_volume
  TextureRef thicknessTexture;   // KHR_materials_volume (G channel)
  float attenuationDistance = INFINITY;
  Vec3 attenuationColor{1.0f};
  float clearcoatFactor = 0;              // KHR_materials_clearcoat
  TextureRef clearcoatTexture;            // (R)
  float clearcoatRoughnessFactor = 0;
  TextureRef clearcoatRoughnessTexture;   // (G)
  TextureRef clearcoatNormalTexture;
  float clearcoatNormalScale = 1;
  Vec3 sheenColorFactor{0.0f};            // KHR_materials_sheen
  TextureRef sheenColorTexture;           // (RGB, sRGB)
  float sheenRoughnessFactor = 0;
  TextureRef sheenRoughnessTexture;       // (A)
  float specularFactor = 1;               // KHR_materials_specular
  TextureRef specularTexture;             // (A)
  Vec3 specularColorFactor{1.0f};
  TextureRef specularColorTexture;        // (RGB, sRGB)
  float anisotropyStrength = 0;           // KHR_materials_anisotropy, in [0, 1]
  float anisotropyRotationRad = 0;        // the direction's angle from the tangent toward the bitangent
  TextureRef anisotropyTexture;           // (RG: direction in tangent space, B: strength; linear)
  bool unlit = false;                     // KHR_materials_unlit: emits its base colour, scatters nothing
  enum class AlphaMode : uint8_t { Opaque, Mask, Blend } alphaMode = AlphaMode::Opaque;
  float alphaCutoff = 0.5f;
  bool doubleSided = false;
  // Transmission through an infinitely thin wall (no refraction): glTF's reading of a material
  // whose thickness is 0 (no KHR_materials_volume, or thicknessFactor 0). Scene-file
  // pbr_materials are solid unless they say "thin_walled".
  bool thinWalled = false;
};

// A parameter value given to a .tex material by the scene file.
struct TexParamValue {
  enum class Kind : uint8_t { Bool, Int, Float, Vec, Spectrum } kind = Kind::Float;
  bool boolValue = false;
  int32_t intValue = 0;
  std::vector<float> floats;  // Float: 1; Vec2/3/4 or Color: 2-4
  SpectrumDesc spectrum;      // Spectrum-typed parameters: evaluated per hit at the path's wavelengths
};

// Binds a .tex material to glTF materials or meshes by name.
struct TexMaterialBinding {
  std::string file;   // resolved path of the .tex module
  std::string entry;  // exported function (first parameter Hit, returns Material)
  std::map<std::string, TexParamValue> params;
  std::string matchMaterial, matchMesh;  // one of them set; matched against glTF names
  std::string origin;  // "scene.json:12:5", for messages
};

struct MeshPrimitive {
  std::string meshName;
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // empty: the renderer uses face normals
  std::vector<Vec2> uv0, uv1; // empty when absent
  std::vector<Vec4> tangents;
  std::vector<Vec4> colors;   // COLOR_0, RGBA (alpha 1 for RGB sources); empty when absent
  std::vector<uint32_t> indices;  // triangles (3 per face), validated against positions.size()
  int material = -1;              // index into SceneDescription::materials; -1: default material
};

struct MeshInstance {
  int primitive = 0;  // index into SceneDescription::primitives
  Mat4 objectToWorld{1.0f};
  std::string nodeName;
};

struct CameraDesc {
  std::string name;
  Mat4 cameraToWorld{1.0f};  // looks down local -z
  float yFovRadians = 0.8f;
  float aspect = 0;          // 0: from the render resolution
  float lensRadius = 0;
  float focusDistance = 1;
  float orthoHalfHeight = 0;  // > 0: orthographic (glTF ymag), yFovRadians unused
};

struct LightDesc {
  enum class Kind : uint8_t { Point, Spot, Directional, ConstantEnvironment, ImageEnvironment } kind = Kind::Point;
  std::string name;
  Vec3 position{0.0f};
  Vec3 direction{0.0f, 0.0f, -1.0f};  // spot / directional: direction light travels
  SpectrumDesc emission;              // colour x intensity (W/sr for point/spot: see docs/scene-format.md)
  float intensity = 1;                // point/spot: candela -> W/sr is the caller's concern; directional: irradiance
  float innerConeRadians = 0, outerConeRadians = 0.7853982f;
  std::string imagePath;              // ImageEnvironment: OpenEXR file
  Mat4 environmentToWorld{1.0f};
  std::string origin;                 // "scene.json:12:5" of a scene file's light, for messages ("" for glTF's)
};

struct RenderSettings {
  int width = 512, height = 512;
  int spp = 16;
  int maxDepth = 8;
  // Russian roulette may end a path after this many scattering events (Mitsuba 3's rr_depth
  // counts the same way: its default 5 is 5 here).
  int rouletteDepth = 3;
  int wavelengths = 4;
  uint64_t seed = 0;
  std::string integrator = "path";
  int camera = 0;  // index into cameras
};

struct SceneDescription {
  std::string sourcePath;
  std::vector<MeshPrimitive> primitives;
  std::vector<MeshInstance> instances;
  std::vector<ImageData> images;
  std::vector<GltfMaterial> materials;
  std::vector<TexMaterialBinding> texMaterials;
  std::vector<CameraDesc> cameras;
  std::vector<LightDesc> lights;
  RenderSettings settings;
  bool resolutionGiven = false;     // the file set render.resolution (CLI flags still override)
  std::vector<std::string> warnings;  // recoverable problems (missing image, unknown extension)
  // Every file the scene was read from (the scene file, glTF files and the buffers and images
  // they load, .tex binding files, environment images): outputs must not overwrite them.
  std::vector<std::string> inputFiles;
};

}  // namespace tex::render
