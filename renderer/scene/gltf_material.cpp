// glTF materials and texture references. Parameter meanings and defaults: glTF 2.0 section
// 3.9 and the Khronos extension specifications (KHR_materials_emissive_strength, _transmission,
// _ior, _dispersion, _volume, _clearcoat, _sheen, _specular, _anisotropy, _unlit,
// KHR_texture_transform).
#include <algorithm>
#include <cmath>
#include <limits>

#include "renderer/scene/gltf_import.h"

namespace tex::render {

namespace {

const tinygltf::Value* member(const tinygltf::Value& object, const char* key) {
  if (!object.IsObject() || !object.Has(key)) return nullptr;
  return &object.Get(key);
}

// Finite and within a float's range: a double such as 1e39 is finite but becomes inf as a float
// (an ior, emissive strength or factor of 1e39 had rendered black with no warning).
bool fitsFloat(double d) { return std::isfinite(d) && std::fabs(d) <= double(std::numeric_limits<float>::max()); }

// A member that must be a number: absent gives `fallback` silently; present but not a number
// that fits a float gives `fallback` with a warning (`"abc"` had been read as the default).
float numberOr(GltfImport& import, const std::string& where, const tinygltf::Value& object, const char* key,
               float fallback) {
  const tinygltf::Value* v = member(object, key);
  if (!v) return fallback;
  if (!v->IsNumber() || !fitsFloat(v->GetNumberAsDouble())) {
    import.warn(where + ": " + key + " is not a number within the range of a 32-bit float; using " +
                std::to_string(fallback));
    return fallback;
  }
  return float(v->GetNumberAsDouble());
}

// Reads n numbers into out[0..n) when the member is an array of exactly n numbers that fit a
// float; warns when it is present but is not.
bool numbersInto(GltfImport& import, const std::string& where, const tinygltf::Value& object, const char* key, int n,
                 float* out) {
  const tinygltf::Value* v = member(object, key);
  if (!v) return false;
  bool ok = v->IsArray() && v->ArrayLen() == size_t(n);
  for (int i = 0; ok && i < n; ++i) ok = v->Get(i).IsNumber() && fitsFloat(v->Get(i).GetNumberAsDouble());
  if (!ok) {
    import.warn(where + ": " + key + " is not " + std::to_string(n) + " numbers within the range of a 32-bit float; ignored");
    return false;
  }
  for (int i = 0; i < n; ++i) out[i] = float(v->Get(i).GetNumberAsDouble());
  return true;
}

template <int N>
bool doublesInto(const std::vector<double>& values, float* out) {
  if (values.size() != size_t(N)) return false;
  for (double d : values)
    if (!fitsFloat(d)) return false;
  for (int i = 0; i < N; ++i) out[i] = float(values[size_t(i)]);
  return true;
}

// A factor outside its range in the specification: clamped into it, with a warning (shading
// clamped most of them anyway, but silently; negative emission had counted as an emitter that
// emitted nothing, so a scene lit by nothing lost its default sky).
float clampedFactor(GltfImport& import, const std::string& where, const char* name, float value, float lo, float hi) {
  if (value >= lo && value <= hi) return value;
  const float clamped = std::clamp(value, lo, hi);
  import.warn(where + ": " + name + " " + std::to_string(value) + " is outside [" + std::to_string(lo) + ", " +
              (hi == std::numeric_limits<float>::max() ? std::string("inf") : std::to_string(hi)) + "]; clamped to " +
              std::to_string(clamped));
  return clamped;
}

WrapMode wrapMode(int glWrap) {
  switch (glWrap) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return WrapMode::ClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return WrapMode::MirroredRepeat;
    default: return WrapMode::Repeat;
  }
}

// A texture reference (textureInfo) given as index, texCoord and its extensions.
TextureRef textureRef(GltfImport& import, int textureIndex, int texCoord, const tinygltf::ExtensionMap& extensions,
                      const std::string& where) {
  TextureRef ref;
  if (textureIndex < 0) return ref;
  const tinygltf::Model& model = import.model;
  if (size_t(textureIndex) >= model.textures.size()) {
    import.warn(where + " uses texture " + std::to_string(textureIndex) + ", which does not exist; ignored");
    return ref;
  }
  const tinygltf::Texture& texture = model.textures[size_t(textureIndex)];
  const std::string textureName = "texture " + std::to_string(textureIndex);
  if (texture.source < 0 || size_t(texture.source) >= model.images.size()) {
    import.warnOnce(textureName + "/source",
                    textureName + " refers to image " + std::to_string(texture.source) + ", but the file has " +
                        std::to_string(model.images.size()) + " images; materials using it ignore it");
    return ref;
  }
  ref.image = import.sceneImage.at(size_t(texture.source));  // -1 (warned) when it has no pixels
  if (texture.sampler >= 0) {
    if (size_t(texture.sampler) < model.samplers.size()) {
      const tinygltf::Sampler& sampler = model.samplers[size_t(texture.sampler)];
      ref.wrapS = wrapMode(sampler.wrapS);
      ref.wrapT = wrapMode(sampler.wrapT);
      ref.nearest = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
    } else {
      import.warnOnce(textureName + "/sampler", textureName + " refers to sampler " + std::to_string(texture.sampler) +
                                                   ", which does not exist; using the default sampler");
    }
  }
  ref.texCoord = texCoord;
  auto transform = extensions.find("KHR_texture_transform");
  if (transform != extensions.end()) {
    const tinygltf::Value& t = transform->second;
    numbersInto(import, where + " KHR_texture_transform", t, "offset", 2, &ref.offset.x);
    numbersInto(import, where + " KHR_texture_transform", t, "scale", 2, &ref.scale.x);
    ref.rotation = numberOr(import, where + " KHR_texture_transform", t, "rotation", 0.0f);
    if (const tinygltf::Value* tc = member(t, "texCoord"); tc && tc->IsInt()) ref.texCoord = tc->GetNumberAsInt();
  }
  if (ref.texCoord != 0 && ref.texCoord != 1) {
    import.warn(where + " uses TEXCOORD_" + std::to_string(ref.texCoord) + "; only 0 and 1 are read, using 0");
    ref.texCoord = 0;
  }
  return ref;
}

// A textureInfo written inside an extension object (a tinygltf::Value, not parsed by tinygltf).
TextureRef textureRefFromValue(GltfImport& import, const tinygltf::Value& object, const char* key,
                               const std::string& where) {
  const tinygltf::Value* info = member(object, key);
  if (!info || !info->IsObject()) return {};
  const tinygltf::Value* index = member(*info, "index");
  if (!index || !index->IsInt()) {
    import.warn(where + ": " + key + " has no integer index; ignored");
    return {};
  }
  const tinygltf::Value* texCoord = member(*info, "texCoord");
  tinygltf::ExtensionMap extensions;
  if (const tinygltf::Value* ext = member(*info, "extensions"); ext && ext->IsObject())
    for (const std::string& name : ext->Keys()) extensions[name] = ext->Get(name);
  return textureRef(import, index->GetNumberAsInt(), texCoord && texCoord->IsInt() ? texCoord->GetNumberAsInt() : 0,
                    extensions, where + " " + key);
}

// A colour factor of three numbers in [0, 1] (sheenColorFactor): out of range clamped, with a
// warning; absent or malformed (warned) leaves `out` as it was.
void colourFactorInto(GltfImport& import, const std::string& at, const tinygltf::Value& ext, const char* key, float hi,
                      Vec3& out) {
  if (!numbersInto(import, at, ext, key, 3, &out.x)) return;
  for (int c = 0; c < 3; ++c)
    out[c] = clampedFactor(import, at, (std::string(key) + " component").c_str(), out[c], 0.0f, hi);
}

// A textureInfo with a normal map's scale (clearcoatNormalTexture).
TextureRef normalTextureFromValue(GltfImport& import, const tinygltf::Value& object, const char* key,
                                  const std::string& where, float& scale) {
  TextureRef ref = textureRefFromValue(import, object, key, where);
  if (const tinygltf::Value* info = member(object, key); info && info->IsObject())
    scale = numberOr(import, where + " " + key, *info, "scale", 1.0f);
  return ref;
}

// KHR_materials_clearcoat, _sheen, _specular and _anisotropy (the layers over the
// metallic-roughness base), and KHR_materials_unlit.
bool readLayerExtension(GltfImport& import, const std::string& name, const tinygltf::Value& ext,
                        const std::string& where, GltfMaterial& out) {
  const std::string at = where + " " + name;
  const float unbounded = std::numeric_limits<float>::max();
  if (name == "KHR_materials_clearcoat") {
    out.clearcoatFactor = clampedFactor(import, at, "clearcoatFactor", numberOr(import, at, ext, "clearcoatFactor", 0.0f), 0.0f, 1.0f);
    out.clearcoatTexture = textureRefFromValue(import, ext, "clearcoatTexture", where);
    out.clearcoatRoughnessFactor = clampedFactor(import, at, "clearcoatRoughnessFactor",
                                                 numberOr(import, at, ext, "clearcoatRoughnessFactor", 0.0f), 0.0f, 1.0f);
    out.clearcoatRoughnessTexture = textureRefFromValue(import, ext, "clearcoatRoughnessTexture", where);
    out.clearcoatNormalTexture =
        normalTextureFromValue(import, ext, "clearcoatNormalTexture", where, out.clearcoatNormalScale);
  } else if (name == "KHR_materials_sheen") {
    colourFactorInto(import, at, ext, "sheenColorFactor", 1.0f, out.sheenColorFactor);
    out.sheenColorTexture = textureRefFromValue(import, ext, "sheenColorTexture", where);
    out.sheenRoughnessFactor = clampedFactor(import, at, "sheenRoughnessFactor",
                                             numberOr(import, at, ext, "sheenRoughnessFactor", 0.0f), 0.0f, 1.0f);
    out.sheenRoughnessTexture = textureRefFromValue(import, ext, "sheenRoughnessTexture", where);
  } else if (name == "KHR_materials_anisotropy") {
    out.anisotropyStrength = clampedFactor(import, at, "anisotropyStrength",
                                           numberOr(import, at, ext, "anisotropyStrength", 0.0f), 0.0f, 1.0f);
    out.anisotropyRotationRad = numberOr(import, at, ext, "anisotropyRotation", 0.0f);
    out.anisotropyTexture = textureRefFromValue(import, ext, "anisotropyTexture", where);
  } else if (name == "KHR_materials_unlit") {
    out.unlit = true;  // the extension object has no properties
  } else if (name == "KHR_materials_specular") {
    out.specularFactor = clampedFactor(import, at, "specularFactor", numberOr(import, at, ext, "specularFactor", 1.0f), 0.0f, 1.0f);
    out.specularTexture = textureRefFromValue(import, ext, "specularTexture", where);
    // specularColorFactor may exceed 1 (the spec's range is [0, inf): F0 x colour is clamped to 1).
    colourFactorInto(import, at, ext, "specularColorFactor", unbounded, out.specularColorFactor);
    out.specularColorTexture = textureRefFromValue(import, ext, "specularColorTexture", where);
  } else {
    return false;
  }
  return true;
}

GltfMaterial convert(GltfImport& import, const tinygltf::Material& m, int index) {
  GltfMaterial out;
  out.name = m.name;
  const std::string where = "material " + std::to_string(index) + (m.name.empty() ? "" : " \"" + m.name + "\"");
  const auto& pbr = m.pbrMetallicRoughness;
  if (!doublesInto<4>(pbr.baseColorFactor, &out.baseColorFactor.x) && !pbr.baseColorFactor.empty())
    import.warn(where + ": baseColorFactor is not 4 finite numbers; using 1");
  // Kept as written, as other out-of-range values are, but a base colour is a reflectance:
  // shading clamps it to [0, 1], which is said rather than silent.
  if (out.baseColorFactor.x > 1.0f || out.baseColorFactor.y > 1.0f || out.baseColorFactor.z > 1.0f)
    import.warn(where + ": baseColorFactor above 1 (the spec's range is [0, 1]); shading clamps it to 1");
  out.baseColorTexture = textureRef(import, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                    pbr.baseColorTexture.extensions, where + " baseColorTexture");
  out.metallicFactor = clampedFactor(import, where, "metallicFactor", fitsFloat(pbr.metallicFactor) ? float(pbr.metallicFactor) : 1.0f, 0.0f, 1.0f);
  out.roughnessFactor = clampedFactor(import, where, "roughnessFactor", fitsFloat(pbr.roughnessFactor) ? float(pbr.roughnessFactor) : 1.0f, 0.0f, 1.0f);
  out.metallicRoughnessTexture =
      textureRef(import, pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                 pbr.metallicRoughnessTexture.extensions, where + " metallicRoughnessTexture");
  out.normalTexture = textureRef(import, m.normalTexture.index, m.normalTexture.texCoord, m.normalTexture.extensions,
                                 where + " normalTexture");
  out.normalScale = fitsFloat(m.normalTexture.scale) ? float(m.normalTexture.scale) : 1.0f;
  if (!doublesInto<3>(m.emissiveFactor, &out.emissiveFactor.x) && !m.emissiveFactor.empty())
    import.warn(where + ": emissiveFactor is not 3 finite numbers; using 0");
  for (int c = 0; c < 3; ++c)
    out.emissiveFactor[c] = clampedFactor(import, where, "emissiveFactor component", out.emissiveFactor[c], 0.0f,
                                          std::numeric_limits<float>::max());
  out.emissiveTexture = textureRef(import, m.emissiveTexture.index, m.emissiveTexture.texCoord,
                                   m.emissiveTexture.extensions, where + " emissiveTexture");
  if (m.alphaMode == "MASK") out.alphaMode = GltfMaterial::AlphaMode::Mask;
  else if (m.alphaMode == "BLEND") out.alphaMode = GltfMaterial::AlphaMode::Blend;
  else if (m.alphaMode != "OPAQUE") import.warn(where + ": unknown alphaMode \"" + m.alphaMode + "\"; using OPAQUE");
  out.alphaCutoff = clampedFactor(import, where, "alphaCutoff", fitsFloat(m.alphaCutoff) ? float(m.alphaCutoff) : 0.5f, 0.0f,
                                  std::numeric_limits<float>::max());
  out.doubleSided = m.doubleSided;

  for (const auto& [name, ext] : m.extensions) {
    const std::string at = where + " " + name;
    const float unbounded = std::numeric_limits<float>::max();
    if (name == "KHR_materials_emissive_strength") {
      out.emissiveStrength = clampedFactor(import, at, "emissiveStrength", numberOr(import, at, ext, "emissiveStrength", 1.0f), 0.0f, unbounded);
    } else if (name == "KHR_materials_transmission") {
      out.transmissionFactor = clampedFactor(import, at, "transmissionFactor", numberOr(import, at, ext, "transmissionFactor", 0.0f), 0.0f, 1.0f);
      out.transmissionTexture = textureRefFromValue(import, ext, "transmissionTexture", where);
    } else if (name == "KHR_materials_ior") {
      // 0 is valid: the specification's compatibility mode for specular-glossiness materials,
      // whose Fresnel term is 1 at every angle. Anything else below 1 is not.
      out.ior = numberOr(import, at, ext, "ior", 1.5f);
      if (out.ior != 0.0f && !(out.ior >= 1.0f)) {
        import.warn(at + ": ior " + std::to_string(out.ior) + " is neither 0 nor at least 1; using 1.5");
        out.ior = 1.5f;
      }
    } else if (name == "KHR_materials_dispersion") {
      out.dispersion = clampedFactor(import, at, "dispersion", numberOr(import, at, ext, "dispersion", 0.0f), 0.0f, unbounded);
    } else if (name == "KHR_materials_volume") {
      out.thicknessFactor = clampedFactor(import, at, "thicknessFactor", numberOr(import, at, ext, "thicknessFactor", 0.0f), 0.0f, unbounded);
      out.thicknessTexture = textureRefFromValue(import, ext, "thicknessTexture", where);
      if (member(ext, "attenuationDistance")) {
        const float distance = numberOr(import, at, ext, "attenuationDistance", 0.0f);
        if (distance > 0.0f) out.attenuationDistance = distance;
        else import.warn(at + ": attenuationDistance " + std::to_string(distance) + " is not positive; no attenuation");
      }
      if (numbersInto(import, at, ext, "attenuationColor", 3, &out.attenuationColor.x))
        for (int c = 0; c < 3; ++c)
          out.attenuationColor[c] = clampedFactor(import, at, "attenuationColor component", out.attenuationColor[c], 0.0f, 1.0f);
    } else if (!readLayerExtension(import, name, ext, where, out)) {
      import.warnOnce("ext/" + name, "material extension " + name + " is not supported; ignored");
    }
  }
  out.thinWalled = !(out.thicknessFactor > 0.0f);
  return out;
}

}  // namespace

void importMaterials(GltfImport& import) {
  // Report broken textures even when no material uses them (the shared CornellBox has one).
  for (size_t t = 0; t < import.model.textures.size(); ++t)
    textureRef(import, int(t), 0, {}, "texture " + std::to_string(t));
  import.materialOffset = int(import.scene.materials.size());
  for (size_t i = 0; i < import.model.materials.size(); ++i)
    import.scene.materials.push_back(convert(import, import.model.materials[i], int(i)));
}

}  // namespace tex::render
