// The scene JSON format, section by section (docs/scene-format.md is the reference).
#include "renderer/scene/scene_json.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/scene_json_reader.h"
#include "renderer/scene/shapes.h"

namespace tex::render {

namespace {

constexpr float kDegrees = kPi / 180.0f;

class SceneJsonLoader {
 public:
  SceneJsonLoader(SceneJsonReader& reader, SceneDescription& scene) : r_(reader), scene_(scene) {}

  void load() {
    const JsonAt root = r_.root();
    if (!r_.checkKeys(root, {"gltf", "shapes", "pbr_materials", "materials", "camera", "cameras", "lights", "render"}))
      if (!root.j->is_object()) return;
    forEach("gltf", [&](const JsonAt& at) { gltf(at); });
    if (const JsonAt m = r_.child(root, "pbr_materials"); m && r_.isObject(m))
      for (auto it = m.j->begin(); it != m.j->end(); ++it)
        if (!SceneJsonReader::isCommentKey(it.key())) pbrMaterial(r_.child(m, it.key()), it.key());
    forEach("shapes", [&](const JsonAt& at) { shape(at); });
    forEach("materials", [&](const JsonAt& at) { binding(at); });
    std::vector<CameraDesc> cameras;
    if (const JsonAt c = r_.child(root, "camera")) {
      if (r_.child(root, "cameras")) r_.error(c, "give \"camera\" or \"cameras\", not both");
      camera(c, cameras);
    }
    forEach("cameras", [&](const JsonAt& at) { camera(at, cameras); });
    // Cameras written in the scene file come before those of its glTF files.
    scene_.cameras.insert(scene_.cameras.begin(), cameras.begin(), cameras.end());
    forEach("lights", [&](const JsonAt& at) { light(at); });
    if (const JsonAt render = r_.child(root, "render")) settings(render);
    checkBindingsMatch();
  }

 private:
  template <typename F>
  void forEach(const char* key, F&& f) {
    const JsonAt array = r_.child(r_.root(), key);
    if (!array || !r_.isArray(array)) return;
    for (size_t i = 0; i < array.j->size(); ++i) f(r_.element(array, i));
  }

  void gltf(const JsonAt& at) {
    std::string file;
    Mat4 transform(1.0f);
    JsonAt fileAt = at;
    if (at.j->is_string()) {
      file = at.j->get<std::string>();
    } else if (at.j->is_object()) {
      if (!r_.checkKeys(at, {"file", "transform"})) return;
      fileAt = r_.child(at, "file");
      if (!fileAt) return r_.error(at, "missing \"file\"");
      if (!r_.string(at, "file", file)) return;
      if (const JsonAt t = r_.child(at, "transform"); t && !r_.transform(t, transform)) return;
    } else {
      return r_.error(at, "expected a file name or {\"file\": ..., \"transform\": ...}, got " +
                              SceneJsonReader::typeName(*at.j));
    }
    std::string resolved;
    if (!r_.existingFile(fileAt, file, resolved)) return;
    std::vector<std::string> errors;
    if (!appendGltf(resolved, transform, scene_, errors)) {
      r_.error(fileAt, "could not load the glTF file:");
      for (const std::string& e : errors) r_.error(fileAt, "  " + e);
    }
  }

  // The first material of that name, or -1. By a map extended as materials are appended (glTF
  // files, pbr_materials, shapes): a scan per shape and per binding made scenes of 10^5 named
  // shapes load in time quadratic in their count.
  int materialNamed(const std::string& name) {
    if (scene_.materials.size() < indexedMaterials_) {  // cut back after a failed glTF file
      materialIndex_.clear();
      indexedMaterials_ = 0;
    }
    for (; indexedMaterials_ < scene_.materials.size(); ++indexedMaterials_)
      materialIndex_.emplace(scene_.materials[indexedMaterials_].name, int(indexedMaterials_));
    const auto it = materialIndex_.find(name);
    return it == materialIndex_.end() ? -1 : it->second;
  }

  void pbrMaterial(const JsonAt& at, const std::string& name) {
    if (!r_.checkKeys(at, {"base_color", "metallic", "roughness", "emissive", "emissive_strength", "transmission",
                           "ior", "dispersion", "double_sided", "thin_walled"}))
      return;
    GltfMaterial m;
    m.name = name;
    m.metallicFactor = 0;  // a scene file's material is a dielectric unless it says otherwise
    if (const JsonAt c = r_.child(at, "base_color")) {
      std::vector<float> v;
      if (!r_.vector(c, 3, 4, v)) return;
      // A reflectance (and alpha): above 1 it was clamped silently, where metallic 2 is an error.
      for (float x : v)
        if (!(x >= 0.0f && x <= 1.0f)) return r_.error(c, "components must be in [0, 1] (a reflectance and an alpha)");
      m.baseColorFactor = Vec4(v[0], v[1], v[2], v.size() == 4 ? v[3] : 1.0f);
    }
    bool ok = r_.number(at, "metallic", m.metallicFactor, 0, 1) && r_.number(at, "roughness", m.roughnessFactor, 0, 1) &&
              r_.vec3(at, "emissive", m.emissiveFactor) && r_.number(at, "emissive_strength", m.emissiveStrength, 0) &&
              r_.number(at, "transmission", m.transmissionFactor, 0, 1) && r_.number(at, "ior", m.ior, 1) &&
              r_.number(at, "dispersion", m.dispersion, 0) && r_.boolean(at, "double_sided", m.doubleSided) &&
              r_.boolean(at, "thin_walled", m.thinWalled);
    if (!ok) return;
    if (materialNamed(name) >= 0) return r_.error(at, "a material named \"" + name + "\" already exists");
    scene_.materials.push_back(m);
  }

  void shape(const JsonAt& at) {
    if (!r_.isObject(at)) return;
    std::string type;
    if (!r_.string(at, "type", type)) return;
    MeshPrimitive mesh;
    if (type == "sphere") {
      if (!r_.checkKeys(at, {"type", "name", "material", "transform", "center", "radius", "segments", "rings", "inward",
                             "smooth"}))
        return;
      Vec3 center(0.0f);
      float radius = 1;
      int segments = 64, rings = 32;
      bool inward = false, smooth = true;
      if (!r_.vec3(at, "center", center) || !r_.number(at, "radius", radius, 1e-30f) ||
          !r_.integer(at, "segments", segments, 3, 4096) || !r_.integer(at, "rings", rings, 2, 4096) ||
          !r_.boolean(at, "inward", inward) || !r_.boolean(at, "smooth", smooth))
        return;
      mesh = makeSphere(center, radius, segments, rings, inward);
      if (!smooth) mesh.normals.clear();  // flat facets: the renderer shades with face normals
    } else if (type == "quad") {
      if (!r_.checkKeys(at, {"type", "name", "material", "transform", "size", "corner", "edge1", "edge2"})) return;
      Vec3 corner(0.0f), edge1(0.0f), edge2(0.0f);
      if (r_.child(at, "corner") || r_.child(at, "edge1") || r_.child(at, "edge2")) {
        if (r_.child(at, "size")) return r_.error(r_.child(at, "size"), "give \"size\" or corner/edge1/edge2, not both");
        for (const char* k : {"corner", "edge1", "edge2"})
          if (!r_.child(at, k)) return r_.error(at, std::string("missing \"") + k + "\"");
        if (!r_.vec3(at, "corner", corner) || !r_.vec3(at, "edge1", edge1) || !r_.vec3(at, "edge2", edge2)) return;
        float crossLength = 0.0f;  // in double where a float's square would underflow or overflow
        triangleUnitNormal(edge1, edge2, crossLength);
        if (!(crossLength > 0)) return r_.error(r_.child(at, "edge2"), "the edges are parallel");
      } else {
        // Default: centred on the origin in the xz plane, facing +y.
        Vec2 size(1.0f);
        if (const JsonAt s = r_.child(at, "size")) {
          std::vector<float> v;
          if (!r_.vector(s, 2, 2, v)) return;
          if (!(v[0] > 0 && v[1] > 0)) return r_.error(s, "sizes must be > 0");
          size = Vec2(v[0], v[1]);
        }
        corner = Vec3(-0.5f * size.x, 0, 0.5f * size.y);
        edge1 = Vec3(size.x, 0, 0);
        edge2 = Vec3(0, 0, -size.y);
      }
      mesh = makeQuad(corner, edge1, edge2);
    } else if (type == "box") {
      if (!r_.checkKeys(at, {"type", "name", "material", "transform", "center", "size", "inward"})) return;
      Vec3 center(0.0f), size(1.0f);
      bool inward = false;
      if (!r_.vec3(at, "center", center) || !r_.vec3(at, "size", size) || !r_.boolean(at, "inward", inward)) return;
      if (!(size.x > 0 && size.y > 0 && size.z > 0)) return r_.error(r_.child(at, "size"), "sizes must be > 0");
      mesh = makeBox(center, size, inward);
    } else {
      return r_.error(r_.child(at, "type"), type.empty() ? "missing \"type\" (sphere, quad or box)"
                                                         : "unknown shape type \"" + type + "\" (sphere, quad or box)");
    }
    std::string name = "shape_" + at.pointer.substr(at.pointer.find_last_of('/') + 1);  // shape_<index>
    std::string material;
    Mat4 transform(1.0f);
    if (!r_.string(at, "name", name) || !r_.string(at, "material", material)) return;
    if (const JsonAt t = r_.child(at, "transform"); t && !r_.transform(t, transform)) return;
    if (!material.empty()) {
      mesh.material = materialNamed(material);
      if (mesh.material < 0) {  // a name for bindings to match; unbound, a grey rough glTF dielectric
        GltfMaterial m;
        m.name = material;
        m.baseColorFactor = Vec4(0.8f, 0.8f, 0.8f, 1.0f);
        m.metallicFactor = 0;
        mesh.material = int(scene_.materials.size());
        scene_.materials.push_back(m);
      }
    }
    mesh.meshName = name;
    scene_.instances.push_back(MeshInstance{int(scene_.primitives.size()), transform, name});
    scene_.primitives.push_back(std::move(mesh));
  }

  void binding(const JsonAt& at) {
    if (!r_.checkKeys(at, {"match", "file", "entry", "params"})) return;
    TexMaterialBinding b;
    b.origin = r_.where(at);
    const JsonAt match = r_.child(at, "match");
    if (!match) return r_.error(at, "missing \"match\" ({\"material\": name} or {\"mesh\": name})");
    if (!r_.checkKeys(match, {"material", "mesh"})) return;
    if (SceneJsonReader::keyCount(match) != 1) return r_.error(match, "give exactly one of \"material\" and \"mesh\"");
    if (!r_.string(match, "material", b.matchMaterial) || !r_.string(match, "mesh", b.matchMesh)) return;
    if (b.matchMaterial.empty() && b.matchMesh.empty()) return r_.error(match, "the name is empty (it would match nothing)");
    // Two bindings for one name: only the first would ever be used (the second was dropped
    // silently). A binding by mesh name over one by material name is the documented precedence.
    if (const auto earlier = bindingOrigins_.find({b.matchMaterial, b.matchMesh}); earlier != bindingOrigins_.end())
      return r_.error(match, std::string("a binding for the ") + (b.matchMesh.empty() ? "material" : "mesh") + " \"" +
                                 (b.matchMesh.empty() ? b.matchMaterial : b.matchMesh) + "\" already exists (at " +
                                 earlier->second + ")");
    std::string file;
    if (!r_.child(at, "file")) return r_.error(at, "missing \"file\" (a .tex module)");
    if (!r_.child(at, "entry")) return r_.error(at, "missing \"entry\" (the exported material function)");
    if (!r_.string(at, "file", file) || !r_.string(at, "entry", b.entry)) return;
    if (!r_.existingFile(r_.child(at, "file"), file, b.file)) return;
    scene_.inputFiles.push_back(b.file);
    if (const JsonAt params = r_.child(at, "params")) {
      if (!r_.isObject(params)) return;
      for (auto it = params.j->begin(); it != params.j->end(); ++it) {
        if (SceneJsonReader::isCommentKey(it.key())) continue;
        TexParamValue value;
        if (!r_.texParam(r_.child(params, it.key()), value)) return;
        b.params[it.key()] = std::move(value);
      }
    }
    bindingAt_.push_back(at);
    bindingOrigins_.emplace(std::make_pair(b.matchMaterial, b.matchMesh), b.origin);
    scene_.texMaterials.push_back(std::move(b));
  }

  void checkBindingsMatch() {
    std::unordered_set<std::string> meshNames;
    for (const MeshPrimitive& p : scene_.primitives) meshNames.insert(p.meshName);
    for (size_t i = 0; i < scene_.texMaterials.size(); ++i) {
      const TexMaterialBinding& b = scene_.texMaterials[i];
      const bool found = b.matchMaterial.empty() ? meshNames.count(b.matchMesh) > 0 : materialNamed(b.matchMaterial) >= 0;
      if (!found)
        r_.warn(scene_, r_.child(bindingAt_[i], "match"),
                "matches nothing (no " + std::string(b.matchMaterial.empty() ? "mesh" : "material") + " named \"" +
                    (b.matchMaterial.empty() ? b.matchMesh : b.matchMaterial) + "\")");
    }
  }

  void camera(const JsonAt& at, std::vector<CameraDesc>& out) {
    if (!r_.checkKeys(at, {"type", "name", "from", "to", "up", "fov_deg", "aspect", "lens_radius", "focus_distance", "ymag"}))
      return;
    std::string type = "perspective";
    CameraDesc c;
    Vec3 from(0, 0, 0), to(0, 0, -1), up(0, 1, 0);
    float fovDeg = 40;
    if (!r_.string(at, "type", type) || !r_.string(at, "name", c.name) || !r_.vec3(at, "from", from) ||
        !r_.vec3(at, "to", to) || !r_.vec3(at, "up", up) || !r_.number(at, "fov_deg", fovDeg, 1e-3f, 179.0f) ||
        !r_.number(at, "aspect", c.aspect, 0))
      return;
    if (type != "perspective" && type != "thinlens" && type != "orthographic")
      return r_.error(r_.child(at, "type"), "unknown camera type \"" + type + "\" (perspective, thinlens or orthographic)");
    if (type != "thinlens" && (r_.child(at, "lens_radius") || r_.child(at, "focus_distance")))
      return r_.error(at, "lens_radius and focus_distance need \"type\": \"thinlens\"");
    if (type == "orthographic") {
      if (r_.child(at, "fov_deg")) return r_.error(r_.child(at, "fov_deg"), "an orthographic camera has no field of view (use ymag)");
      if (!r_.child(at, "ymag")) return r_.error(at, "an orthographic camera needs \"ymag\" (half the film's height, world units)");
      if (!r_.number(at, "ymag", c.orthoHalfHeight, 1e-30f)) return;
    } else if (r_.child(at, "ymag")) {
      return r_.error(r_.child(at, "ymag"), "ymag needs \"type\": \"orthographic\"");
    }
    // Camera looks down its local -z (glTF convention).
    const Vec3 back = from - to;
    if (!(glm::length(back) > 0)) return r_.error(r_.child(at, "to"), "\"from\" and \"to\" are the same point");
    const Vec3 z = glm::normalize(back);
    const Vec3 xUnnormalised = glm::cross(up, z);
    if (!(glm::length(xUnnormalised) > 1e-6f * glm::length(up))) return r_.error(r_.child(at, "up"), "\"up\" is parallel to the view direction");
    const Vec3 x = glm::normalize(xUnnormalised), y = glm::cross(z, x);
    c.cameraToWorld = Mat4(Vec4(x, 0), Vec4(y, 0), Vec4(z, 0), Vec4(from, 1));
    c.yFovRadians = fovDeg * kDegrees;
    c.focusDistance = glm::length(back);
    if (type == "thinlens" &&
        (!r_.number(at, "lens_radius", c.lensRadius, 0) || !r_.number(at, "focus_distance", c.focusDistance, 1e-30f)))
      return;
    out.push_back(c);
  }

  void light(const JsonAt& at) {
    if (!r_.isObject(at)) return;
    std::string type;
    if (!r_.string(at, "type", type)) return;
    LightDesc l;
    l.origin = r_.where(at);
    // Without "emission" a light is white: rgb (1, 1, 1) read as an illuminant, as glTF's
    // default light colour and the default sky are. (A constant spectrum of 1, the earlier
    // default, develops to a pinkish (1.20, 0.95, 0.91).)
    l.emission.kind = SpectrumDesc::Kind::Rgb;
    l.emission.rgb = Vec3(1.0f);
    l.emission.rgbAs = SpectrumDesc::RgbAs::Illuminant;
    if (type == "point") {
      l.kind = LightDesc::Kind::Point;
      if (!r_.checkKeys(at, {"type", "name", "emission", "intensity", "position"}) || !r_.vec3(at, "position", l.position)) return;
    } else if (type == "spot") {
      l.kind = LightDesc::Kind::Spot;
      if (!r_.checkKeys(at, {"type", "name", "emission", "intensity", "position", "direction", "to", "inner_cone_deg",
                             "outer_cone_deg"}))
        return;
      float innerDeg = 0, outerDeg = 45;
      if (!r_.vec3(at, "position", l.position) || !direction(at, l) || !r_.number(at, "inner_cone_deg", innerDeg, 0, 90) ||
          !r_.number(at, "outer_cone_deg", outerDeg, 1e-3f, 90))
        return;
      if (!(innerDeg < outerDeg)) return r_.error(r_.child(at, "inner_cone_deg"), "must be less than outer_cone_deg");
      l.innerConeRadians = innerDeg * kDegrees;
      l.outerConeRadians = outerDeg * kDegrees;
    } else if (type == "directional") {
      l.kind = LightDesc::Kind::Directional;
      if (!r_.checkKeys(at, {"type", "name", "emission", "intensity", "direction"}) || !direction(at, l)) return;
    } else if (type == "environment") {
      if (!r_.checkKeys(at, {"type", "name", "emission", "intensity", "image", "transform"})) return;
      // An image environment's colour is its image's (times intensity): an emission would be
      // ignored, so it is an error rather than a silent no-op.
      if (r_.child(at, "image") && r_.child(at, "emission"))
        return r_.error(r_.child(at, "emission"), "an image environment takes its colour from the image; scale it with \"intensity\"");
      l.kind = LightDesc::Kind::ConstantEnvironment;
      if (const JsonAt image = r_.child(at, "image")) {
        std::string file;
        if (!r_.string(at, "image", file) || !r_.existingFile(image, file, l.imagePath)) return;
        scene_.inputFiles.push_back(l.imagePath);
        l.kind = LightDesc::Kind::ImageEnvironment;
      }
      if (const JsonAt t = r_.child(at, "transform"); t) {
        if (!r_.transform(t, l.environmentToWorld)) return;
        // Only the orientation of a sky means anything; a matrix that shears has none (its
        // directions would not map back the way they came: light samples and rays saw two
        // different skies, the sun 10 degrees apart).
        const Mat4& m = l.environmentToWorld;
        for (int a = 0; a < 3; ++a)
          for (int b = a + 1; b < 3; ++b) {
            const Vec3 ca(m[a]), cb(m[b]);
            const float la = glm::length(ca), lb = glm::length(cb);
            if (!(la > 0.0f && lb > 0.0f) || std::fabs(glm::dot(ca, cb)) > 1e-3f * la * lb)
              return r_.error(t, "an environment's transform must be a rotation (scale and translation are ignored); "
                                 "this matrix shears or collapses directions");
          }
      }
    } else {
      return r_.error(r_.child(at, "type"), type.empty() ? "missing \"type\" (point, spot, directional or environment)"
                                                         : "unknown light type \"" + type + "\" (point, spot, directional or environment)");
    }
    if (!r_.string(at, "name", l.name) || !r_.number(at, "intensity", l.intensity, 0)) return;
    if (const JsonAt e = r_.child(at, "emission"); e) {
      // A light's rgb is an illuminant (docs/scene-format.md): "as" saying otherwise had been
      // accepted and ignored.
      if (e.j->is_object() && r_.child(e, "as")) {
        std::string use;
        if (!r_.string(e, "as", use)) return;
        if (use != "illuminant")
          return r_.error(r_.child(e, "as"), "a light's rgb emission is an illuminant; \"as\": \"" + use + "\" does not apply");
      }
      if (!r_.spectrum(e, l.emission)) return;
      // Negative emission rendered black silently, where a negative intensity is an error.
      const SpectrumDesc& s = l.emission;
      bool negative = s.scale < 0 || (s.kind == SpectrumDesc::Kind::Constant && s.value < 0) ||
                      (s.kind == SpectrumDesc::Kind::Rgb && (s.rgb.x < 0 || s.rgb.y < 0 || s.rgb.z < 0));
      for (float v : s.values) negative = negative || v < 0;
      if (negative) return r_.error(e, "a light's emission must not be negative");
    }
    scene_.lights.push_back(l);
  }

  // "direction" (the way light travels) or "to" (a point it shines at, spot lights).
  bool direction(const JsonAt& at, LightDesc& l) {
    const JsonAt d = r_.child(at, "direction"), to = r_.child(at, "to");
    if (d && to) return r_.error(to, "give \"direction\" or \"to\", not both"), false;
    if (!d && !to) return r_.error(at, "missing \"direction\""), false;
    Vec3 v;
    if (d ? !r_.vec3(at, "direction", v) : !r_.vec3(at, "to", v)) return false;
    if (to) v -= l.position;
    if (!(glm::length(v) > 0)) return r_.error(d ? d : to, "the direction is zero"), false;
    l.direction = glm::normalize(v);
    return true;
  }

  void settings(const JsonAt& at) {
    if (!r_.checkKeys(at, {"resolution", "spp", "max_depth", "roulette_depth", "wavelengths", "seed", "integrator", "camera"})) return;
    RenderSettings& s = scene_.settings;
    if (const JsonAt res = r_.child(at, "resolution")) {
      scene_.resolutionGiven = true;
      if (!res.j->is_array() || res.j->size() != 2 || !(*res.j)[0].is_number_integer() || !(*res.j)[1].is_number_integer())
        return r_.error(res, "expected [width, height] as integers");
      const int64_t w = (*res.j)[0].get<int64_t>(), h = (*res.j)[1].get<int64_t>();
      if (w < 1 || h < 1 || w > 65536 || h > 65536) return r_.error(res, "width and height must be in [1, 65536]");
      s.width = int(w);
      s.height = int(h);
    }
    if (!r_.integer(at, "spp", s.spp, 1, 1 << 30) || !r_.integer(at, "max_depth", s.maxDepth, 0, 1000) ||
        !r_.integer(at, "roulette_depth", s.rouletteDepth, 1, 1 << 16) ||
        !r_.integer(at, "wavelengths", s.wavelengths, 1, 8) || !r_.unsigned64(at, "seed", s.seed) ||
        !r_.string(at, "integrator", s.integrator) || !r_.integer(at, "camera", s.camera, 0, 1 << 20))
      return;
    if (s.wavelengths != 4 && s.wavelengths != 8) return r_.error(r_.child(at, "wavelengths"), "must be 4 or 8");
    if (s.integrator.empty()) return r_.error(r_.child(at, "integrator"), "must not be empty");
    if (s.integrator != "path")  // as `tex render --integrator`
      return r_.error(r_.child(at, "integrator"), "unknown integrator \"" + s.integrator + "\" (available: path)");
    if (r_.child(at, "camera") && size_t(s.camera) >= scene_.cameras.size())
      return r_.error(r_.child(at, "camera"), "camera " + std::to_string(s.camera) + " does not exist (the scene has " +
                                                   std::to_string(scene_.cameras.size()) + ")");
  }

  SceneJsonReader& r_;
  SceneDescription& scene_;
  std::vector<JsonAt> bindingAt_;
  std::map<std::pair<std::string, std::string>, std::string> bindingOrigins_;  // (material, mesh) -> origin
  std::unordered_map<std::string, int> materialIndex_;  // materialNamed's map
  size_t indexedMaterials_ = 0;
};

}  // namespace

std::optional<SceneDescription> parseSceneJson(const std::string& text, const std::string& displayName,
                                               const std::string& baseDirectory, std::vector<std::string>& errors) {
  std::string syntaxError;
  std::optional<LocatedJson> doc = parseLocatedJson(text, syntaxError);
  if (!doc) {
    errors.push_back(displayName + ":" + syntaxError);
    return std::nullopt;
  }
  SceneDescription scene;
  scene.sourcePath = displayName;
  const size_t before = errors.size();
  SceneJsonReader reader(*doc, displayName, baseDirectory, errors);
  SceneJsonLoader(reader, scene).load();
  if (errors.size() != before) return std::nullopt;
  return scene;
}

std::optional<SceneDescription> loadSceneJson(const std::string& path, std::vector<std::string>& errors) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    errors.push_back(path + ": cannot open the file");
    return std::nullopt;
  }
  std::stringstream text;
  text << file.rdbuf();
  const std::string directory = std::filesystem::path(path).parent_path().string();
  return parseSceneJson(text.str(), path, directory.empty() ? "." : directory, errors);
}

}  // namespace tex::render
