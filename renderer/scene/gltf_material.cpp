// glTF materials and texture references. Parameter meanings and defaults: glTF 2.0 section
// 3.9 and the Khronos extension specifications (KHR_materials_emissive_strength, _transmission,
// _ior, _dispersion, _volume, KHR_texture_transform).
#include <cmath>

#include "renderer/scene/gltf_import.h"

namespace tex::render {

namespace {

const tinygltf::Value* member(const tinygltf::Value& object, const char* key) {
  if (!object.IsObject() || !object.Has(key)) return nullptr;
  return &object.Get(key);
}

float numberOr(const tinygltf::Value& object, const char* key, float fallback) {
  const tinygltf::Value* v = member(object, key);
  if (!v || !v->IsNumber()) return fallback;
  const double d = v->GetNumberAsDouble();
  return std::isfinite(d) ? float(d) : fallback;
}

// Reads n numbers into out[0..n) when the member is an array of exactly n finite numbers.
bool numbersInto(const tinygltf::Value& object, const char* key, int n, float* out) {
  const tinygltf::Value* v = member(object, key);
  if (!v || !v->IsArray() || v->ArrayLen() != size_t(n)) return false;
  for (int i = 0; i < n; ++i)
    if (!v->Get(i).IsNumber() || !std::isfinite(v->Get(i).GetNumberAsDouble())) return false;
  for (int i = 0; i < n; ++i) out[i] = float(v->Get(i).GetNumberAsDouble());
  return true;
}

template <int N>
bool doublesInto(const std::vector<double>& values, float* out) {
  if (values.size() != size_t(N)) return false;
  for (double d : values)
    if (!std::isfinite(d)) return false;
  for (int i = 0; i < N; ++i) out[i] = float(values[size_t(i)]);
  return true;
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
    numbersInto(t, "offset", 2, &ref.offset.x);
    numbersInto(t, "scale", 2, &ref.scale.x);
    ref.rotation = numberOr(t, "rotation", 0.0f);
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
  out.metallicFactor = std::isfinite(pbr.metallicFactor) ? float(pbr.metallicFactor) : 1.0f;
  out.roughnessFactor = std::isfinite(pbr.roughnessFactor) ? float(pbr.roughnessFactor) : 1.0f;
  out.metallicRoughnessTexture =
      textureRef(import, pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                 pbr.metallicRoughnessTexture.extensions, where + " metallicRoughnessTexture");
  out.normalTexture = textureRef(import, m.normalTexture.index, m.normalTexture.texCoord, m.normalTexture.extensions,
                                 where + " normalTexture");
  out.normalScale = std::isfinite(m.normalTexture.scale) ? float(m.normalTexture.scale) : 1.0f;
  if (!doublesInto<3>(m.emissiveFactor, &out.emissiveFactor.x) && !m.emissiveFactor.empty())
    import.warn(where + ": emissiveFactor is not 3 finite numbers; using 0");
  out.emissiveTexture = textureRef(import, m.emissiveTexture.index, m.emissiveTexture.texCoord,
                                   m.emissiveTexture.extensions, where + " emissiveTexture");
  if (m.alphaMode == "MASK") out.alphaMode = GltfMaterial::AlphaMode::Mask;
  else if (m.alphaMode == "BLEND") out.alphaMode = GltfMaterial::AlphaMode::Blend;
  else if (m.alphaMode != "OPAQUE") import.warn(where + ": unknown alphaMode \"" + m.alphaMode + "\"; using OPAQUE");
  out.alphaCutoff = std::isfinite(m.alphaCutoff) ? float(m.alphaCutoff) : 0.5f;
  out.doubleSided = m.doubleSided;

  for (const auto& [name, ext] : m.extensions) {
    if (name == "KHR_materials_emissive_strength") {
      out.emissiveStrength = numberOr(ext, "emissiveStrength", 1.0f);
    } else if (name == "KHR_materials_transmission") {
      out.transmissionFactor = numberOr(ext, "transmissionFactor", 0.0f);
      out.transmissionTexture = textureRefFromValue(import, ext, "transmissionTexture", where);
    } else if (name == "KHR_materials_ior") {
      out.ior = numberOr(ext, "ior", 1.5f);
    } else if (name == "KHR_materials_dispersion") {
      out.dispersion = numberOr(ext, "dispersion", 0.0f);
    } else if (name == "KHR_materials_volume") {
      out.thicknessFactor = numberOr(ext, "thicknessFactor", 0.0f);
      out.thicknessTexture = textureRefFromValue(import, ext, "thicknessTexture", where);
      const tinygltf::Value* distance = member(ext, "attenuationDistance");
      if (distance && distance->IsNumber() && distance->GetNumberAsDouble() > 0)
        out.attenuationDistance = float(distance->GetNumberAsDouble());
      numbersInto(ext, "attenuationColor", 3, &out.attenuationColor.x);
    } else {
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
