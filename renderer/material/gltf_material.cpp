#include "renderer/material/gltf_material.h"

#include <algorithm>
#include <cmath>

#include "renderer/material/texture_lookup.h"
#include "renderer/spectra/rgb_spectrum.h"

namespace tex::render {

namespace {

// baseColorFactor x the sRGB-decoded texture x the vertex colour (glTF 2.0 3.9.2).
Vec3 baseColorAt(const SceneDescription& scene, const GltfMaterial& m, const ShadingPoint& point) {
  const Vec4 t = lookupTexture(scene, m.baseColorTexture, point.uv, point.uv1, true);
  return Vec3(m.baseColorFactor) * Vec3(t) * Vec3(point.color);
}


// emissiveFactor x strength x the sRGB-decoded emissive texture (no lookup when black); an unlit
// material's (KHR_materials_unlit) is its base colour, clamped to [0, 1] as a reflectance is.
Vec3 emissionRgb(const SceneDescription& scene, const GltfMaterial& m, const ShadingPoint& point) {
  if (m.unlit) return glm::clamp(baseColorAt(scene, m, point), Vec3(0.0f), Vec3(1.0f));
  const Vec3 e = m.emissiveFactor * m.emissiveStrength;
  return e == Vec3(0.0f) ? e : e * Vec3(lookupTexture(scene, m.emissiveTexture, point.uv, point.uv1, true));
}

// KHR_texture_transform on the normal texture: the map's +x points along increasing u', the
// transformed coordinate, so the tangent turns with the texture. With uv' = R(rotation) S uv
// (+ offset), dp/du' = dp/du du/du' + dp/dv dv/du' = dp/du cos/sx + dp/dv sin/sy, and in the
// unit frame dp/du ~ t, dp/dv ~ -b. A mirroring scale (sx sy < 0) flips the handedness.
void turnTangentWithTextureTransform(const TextureRef& ref, Vec3 n, Vec3& t, float& w) {
  if (ref.rotation == 0.0f && ref.scale == Vec2(1.0f)) return;
  const float su = ref.scale.x, sv = ref.scale.y;
  if (su == 0.0f || sv == 0.0f) return;  // the texture is constant along one axis: keep the frame
  const Vec3 b = glm::cross(n, t) * w;
  const Vec3 turned = t * (std::cos(ref.rotation) / su) - b * (std::sin(ref.rotation) / sv);
  const float length = glm::length(turned);
  if (!(length > 1e-8f) || !std::isfinite(length)) return;
  t = turned / length;
  if (su * sv < 0.0f) w = -w;
}

// glTF's tangent frame at the point (glTF 2.0 3.7.2.1: bitangent = cross(normal, tangent) w;
// without a TANGENT attribute the tangent follows increasing u and the bitangent decreasing v).
// False when the tangent is degenerate.
bool gltfTangentFrame(const ShadingPoint& point, const Vec3& n, Vec3& t, float& w) {
  t = Vec3(point.tangent);
  w = point.tangent.w;
  if (w == 0.0f) {
    t = point.dpdu;
    w = dot3(glm::cross(n, t), -point.dpdv) >= 0.0f ? 1.0f : -1.0f;
  }
  t -= n * dot3(n, t);
  const float tl = glm::length(t);
  if (!(tl > 1e-8f)) return false;
  t /= tl;
  return true;
}

// The shading normal perturbed by a normal texture `map` of scale `scale` (glTF 2.0 3.9.3).
Vec3 normalMappedNormal(const SceneDescription& scene, const TextureRef& map, float scale, const ShadingPoint& point,
                        Vec3& tangentOut) {
  const Vec3 n = point.ns;
  tangentOut = point.dpdu;
  if (map.image < 0) return n;
  // Tangent frame (glTF: bitangent = cross(normal, tangent) * w). Without a TANGENT attribute,
  // the tangent follows increasing u and the bitangent decreasing v (glTF's uv origin is the
  // image's top-left corner, and normal maps have +Y up).
  Vec3 t;
  float w;
  if (!gltfTangentFrame(point, n, t, w)) return n;
  turnTangentWithTextureTransform(map, n, t, w);
  const Vec3 b = glm::cross(n, t) * w;
  const Vec4 texel = lookupTexture(scene, map, point.uv, point.uv1, false, Vec4(0.5f, 0.5f, 1.0f, 1.0f));
  const Vec3 local = Vec3((texel.x * 2.0f - 1.0f) * scale, (texel.y * 2.0f - 1.0f) * scale, texel.z * 2.0f - 1.0f);
  Vec3 mapped = t * local.x + b * local.y + n * local.z;
  const float ml = glm::length(mapped);
  if (!(ml > 1e-8f) || !std::isfinite(ml)) return n;
  mapped /= ml;
  tangentOut = t;
  return mapped;
}

}  // namespace

Spectrum gltfEmission(const SceneDescription& scene, const GltfMaterial& m, const ShadingPoint& point,
                      const Wavelengths& lambda) {
  const Vec3 e = emissionRgb(scene, m, point);
  return e == Vec3(0.0f) ? Spectrum() : rgbIlluminantSpectrum(e, lambda);
}

bool gltfReadsHit(const SceneDescription& scene, const GltfMaterial& m) {
  // The anisotropy's direction is turned into each point's shading frame (gltfAnisotropyInto).
  if (m.anisotropyStrength > 0.0f) return true;
  for (const TextureRef* t : {&m.baseColorTexture, &m.metallicRoughnessTexture, &m.transmissionTexture,
                              &m.emissiveTexture, &m.normalTexture, &m.clearcoatTexture, &m.clearcoatRoughnessTexture,
                              &m.clearcoatNormalTexture, &m.sheenColorTexture, &m.sheenRoughnessTexture,
                              &m.specularTexture, &m.specularColorTexture})
    if (textureHasImage(scene, *t)) return true;
  return false;
}

void applyGltfNormalMap(const SceneDescription& scene, const GltfMaterial& m, const ShadingPoint& point, Bsdf& bsdf) {
  if (m.normalTexture.image < 0) return;
  Vec3 tangent;
  const Vec3 n = normalMappedNormal(scene, m.normalTexture, m.normalScale, point, tangent);
  bsdf = Bsdf(Frame::fromNormalTangent(n, tangent), bsdf.geometricNormal());
}

void applyGltfClearcoatNormal(const SceneDescription& scene, const GltfMaterial& m, const ShadingPoint& point,
                              Bsdf& bsdf) {
  if (!bsdf.hasClearcoat() || (m.normalTexture.image < 0 && m.clearcoatNormalTexture.image < 0)) return;
  Vec3 tangent;
  const Vec3 n = normalMappedNormal(scene, m.clearcoatNormalTexture, m.clearcoatNormalScale, point, tangent);
  bsdf.setClearcoatFrame(Frame::fromNormalTangent(n, tangent));
}

GltfInputs gltfInputs(const SceneDescription& scene, const GltfMaterial& m, const ShadingPoint& point) {
  GltfInputs in;
  in.baseColor = glm::clamp(baseColorAt(scene, m, point), Vec3(0.0f), Vec3(1.0f));
  const Vec4 mr = lookupTexture(scene, m.metallicRoughnessTexture, point.uv, point.uv1, false);
  in.metallic = std::clamp(m.metallicFactor * mr.z, 0.0f, 1.0f);
  in.roughness = std::clamp(m.roughnessFactor * mr.y, 0.0f, 1.0f);
  in.transmission =
      std::clamp(m.transmissionFactor * lookupTexture(scene, m.transmissionTexture, point.uv, point.uv1, false).x, 0.0f, 1.0f);
  in.ior = m.ior;
  in.dispersion = m.dispersion;
  in.thinWalled = m.thinWalled ? 1.0f : 0.0f;
  in.emission = emissionRgb(scene, m, point);
  // The layers, each looked up only when its factor can make a difference.
  const auto channel = [&](const TextureRef& t, int c) { return lookupTexture(scene, t, point.uv, point.uv1, false)[c]; };
  if (m.clearcoatFactor > 0.0f) {
    in.clearcoat = std::clamp(m.clearcoatFactor * channel(m.clearcoatTexture, 0), 0.0f, 1.0f);
    in.clearcoatRoughness = std::clamp(m.clearcoatRoughnessFactor * channel(m.clearcoatRoughnessTexture, 1), 0.0f, 1.0f);
  }
  if (m.sheenColorFactor != Vec3(0.0f)) {
    const Vec3 colour = m.sheenColorFactor * Vec3(lookupTexture(scene, m.sheenColorTexture, point.uv, point.uv1, true));
    in.sheenColor = glm::clamp(colour, Vec3(0.0f), Vec3(1.0f));
    in.sheenRoughness = std::clamp(m.sheenRoughnessFactor * channel(m.sheenRoughnessTexture, 3), 0.0f, 1.0f);
  }
  in.specular = std::clamp(m.specularFactor * channel(m.specularTexture, 3), 0.0f, 1.0f);
  in.specularColor = glm::max(m.specularColorFactor * Vec3(lookupTexture(scene, m.specularColorTexture, point.uv, point.uv1, true)),
                              Vec3(0.0f));
  return in;
}

void gltfAnisotropyInto(const SceneDescription& scene, const GltfMaterial& m, const ShadingPoint& point,
                        const Frame& shading, GltfInputs& in) {
  if (!(m.anisotropyStrength > 0.0f)) return;
  // The texture's default is direction (1, 0) at strength 1: texel (1, 0.5, 1).
  const Vec4 texel = lookupTexture(scene, m.anisotropyTexture, point.uv, point.uv1, false, Vec4(1.0f, 0.5f, 1.0f, 1.0f));
  in.anisotropyStrength = std::clamp(m.anisotropyStrength * texel.z, 0.0f, 1.0f);
  const Vec2 texDir(texel.x * 2.0f - 1.0f, texel.y * 2.0f - 1.0f);
  const float texAngle = texDir == Vec2(0.0f) ? 0.0f : std::atan2(texDir.y, texDir.x);
  Vec3 t;
  float w;
  if (!gltfTangentFrame(point, shading.n, t, w)) {
    // No tangent: the shading frame's own x axis stands in.
    in.anisotropyRotationRad = m.anisotropyRotationRad + texAngle;
    return;
  }
  // The texel's direction lies in the texture's own tangent frame, which its
  // KHR_texture_transform turns (as a normal map's; without one it is the mesh's);
  // anisotropyRotation then turns it about the normal in the mesh's tangent frame.
  Vec3 textureT = t;
  float textureW = w;
  if (m.anisotropyTexture.image >= 0) turnTangentWithTextureTransform(m.anisotropyTexture, shading.n, textureT, textureW);
  const Vec3 fromTexture = textureT * std::cos(texAngle) + glm::cross(shading.n, textureT) * textureW * std::sin(texAngle);
  const float r = m.anisotropyRotationRad;
  const Vec3 direction = fromTexture * std::cos(r) + glm::cross(shading.n, fromTexture) * w * std::sin(r);
  in.anisotropyRotationRad = std::atan2(dot3(direction, shading.t), dot3(direction, shading.s));
}

float gltfDispersiveIor(float ior, float dispersion, float lambdaNm) {
  if (!(dispersion > 0.0f)) return ior;
  return std::max(ior + (ior - 1.0f) * dispersion / 20.0f * (523655.0f / (lambdaNm * lambdaNm) - 1.5168f), 1.0f);
}

}  // namespace tex::render
