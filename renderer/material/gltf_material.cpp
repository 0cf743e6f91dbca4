#include "renderer/material/gltf_material.h"

#include <algorithm>
#include <cmath>

#include "renderer/material/texture_lookup.h"
#include "renderer/spectra/rgb_spectrum.h"

namespace tex::render {

float dispersiveIor(float iorD, float dispersion, float lambdaNm) {
  if (dispersion <= 0.0f) return iorD;
  const float abbe = 20.0f / dispersion;
  return std::max(iorD + (iorD - 1.0f) / abbe * (523655.0f / (lambdaNm * lambdaNm) - 1.5168f), 1.0f);
}

void gulbrandsenIor(float r, float g, float& eta, float& k) {
  r = std::clamp(r, 0.0f, 0.99f);
  g = std::clamp(g, 0.0f, 1.0f);
  const float sr = std::sqrt(r);
  eta = g * (1.0f - r) / (1.0f + r) + (1.0f - g) * (1.0f + sr) / (1.0f - sr);
  const float k2 = (r * (eta + 1.0f) * (eta + 1.0f) - (eta - 1.0f) * (eta - 1.0f)) / (1.0f - r);
  k = std::sqrt(std::max(k2, 0.0f));
}

namespace {

Vec3 baseColorAt(const SceneDescription& scene, const GltfMaterial& m, const ShadingPoint& point) {
  const Vec4 t = lookupTexture(scene, m.baseColorTexture, point.uv, point.uv, true);
  return Vec3(m.baseColorFactor) * Vec3(t);
}

}  // namespace

Spectrum gltfEmission(const SceneDescription& scene, const GltfMaterial& m, const ShadingPoint& point,
                      const Wavelengths& lambda) {
  Vec3 e = m.emissiveFactor * m.emissiveStrength;
  if (e == Vec3(0.0f)) return Spectrum();
  e *= Vec3(lookupTexture(scene, m.emissiveTexture, point.uv, point.uv, true));
  return rgbIlluminantSpectrum(e, lambda);
}

Vec3 normalMappedNormal(const SceneDescription& scene, const GltfMaterial& m, const ShadingPoint& point, Vec3& tangentOut) {
  const Vec3 n = point.ns;
  tangentOut = point.dpdu;
  if (m.normalTexture.image < 0) return n;
  // Tangent frame (glTF: bitangent = cross(normal, tangent) * w). Without a TANGENT attribute,
  // the tangent follows increasing u and the bitangent decreasing v (glTF's uv origin is the
  // image's top-left corner, and normal maps have +Y up).
  Vec3 t = Vec3(point.tangent);
  float w = point.tangent.w;
  if (w == 0.0f) {
    t = point.dpdu;
    w = dot3(glm::cross(n, t), -point.dpdv) >= 0.0f ? 1.0f : -1.0f;
  }
  t -= n * dot3(n, t);
  const float tl = glm::length(t);
  if (!(tl > 1e-8f)) return n;
  t /= tl;
  const Vec3 b = glm::cross(n, t) * w;
  const Vec4 texel = lookupTexture(scene, m.normalTexture, point.uv, point.uv, false, Vec4(0.5f, 0.5f, 1.0f, 1.0f));
  const Vec3 local = Vec3((texel.x * 2.0f - 1.0f) * m.normalScale, (texel.y * 2.0f - 1.0f) * m.normalScale, texel.z * 2.0f - 1.0f);
  Vec3 mapped = t * local.x + b * local.y + n * local.z;
  const float ml = glm::length(mapped);
  if (!(ml > 1e-8f) || !std::isfinite(ml)) return n;
  mapped /= ml;
  tangentOut = t;
  return mapped;
}

void shadeGltfMaterial(const SceneDescription& scene, const GltfMaterial& m, const ShadingPoint& point,
                       const Wavelengths& lambda, Bsdf& bsdf, Spectrum& emission) {
  emission = gltfEmission(scene, m, point, lambda);
  if (m.normalTexture.image >= 0) {
    Vec3 tangent;
    const Vec3 n = normalMappedNormal(scene, m, point, tangent);
    bsdf = Bsdf(Frame::fromNormalTangent(n, tangent), bsdf.geometricNormal());
  }
  const Vec3 base = glm::clamp(baseColorAt(scene, m, point), Vec3(0.0f), Vec3(1.0f));
  const Vec4 mr = lookupTexture(scene, m.metallicRoughnessTexture, point.uv, point.uv, false);
  const float metal = std::clamp(m.metallicFactor * mr.z, 0.0f, 1.0f);
  const float transmission =
      std::clamp(m.transmissionFactor * lookupTexture(scene, m.transmissionTexture, point.uv, point.uv, false).x, 0.0f, 1.0f);
  const Spectrum baseSpectrum = rgbReflectanceSpectrum(base, lambda);

  const float roughness = std::clamp(m.roughnessFactor * mr.y, 0.0f, 1.0f);
  // glTF's roughness is perceptual: the GGX alpha is its square. Below alpha 1e-3 the lobes are
  // treated as perfectly smooth (Dirac), as the GGX code would be numerically.
  const float alpha = roughness * roughness;
  const bool smooth = alpha < 1e-3f;

  if (metal > 0.0f) {
    Lobe conductor;
    conductor.kind = smooth ? LobeKind::SmoothConductor : LobeKind::RoughConductor;
    conductor.roughness = alpha;
    conductor.weight = Spectrum(metal);
    for (int i = 0; i < lambda.count; ++i) gulbrandsenIor(baseSpectrum[i], baseSpectrum[i], conductor.a.v[i], conductor.b.v[i]);
    bsdf.add(conductor);
  }
  const float dielectricShare = (1.0f - metal) * transmission;
  if (dielectricShare > 0.0f) {
    Lobe glass;
    glass.kind = smooth ? LobeKind::SmoothDielectric : LobeKind::RoughDielectric;
    glass.roughness = alpha;
    glass.weight = baseSpectrum * dielectricShare;
    for (int i = 0; i < lambda.count; ++i) glass.a.v[i] = dispersiveIor(m.ior, m.dispersion, lambda.lambdaNm[i]);
    glass.etaVaries = m.dispersion > 0.0f && m.ior != 1.0f;
    bsdf.add(glass);
  }
  const float diffuseShare = (1.0f - metal) * (1.0f - transmission);
  if (diffuseShare > 0.0f) {
    // The glTF dielectric: a specular coat of the material's IOR over the diffuse base.
    Lobe coat;
    coat.kind = smooth ? LobeKind::SmoothDielectric : LobeKind::RoughDielectric;
    coat.roughness = alpha;
    coat.weight = Spectrum(diffuseShare);
    for (int i = 0; i < lambda.count; ++i) coat.a.v[i] = m.ior > 1.0f ? m.ior : 1.5f;
    const bool coated = bsdf.setCoat(coat);
    Lobe diffuse;
    diffuse.kind = LobeKind::Lambertian;
    diffuse.weight = baseSpectrum * diffuseShare;
    diffuse.underCoat = coated;
    bsdf.add(diffuse);
  }
}

}  // namespace tex::render
