// glTF 2.0 metallic-roughness materials: what the renderer reads natively at a hit (factors
// times textures, the normal map's shading frame, emission for area lights); how the material
// scatters is the tex function std.gltf.metallic_roughness (stdlib/std/gltf.tex), called with
// these inputs (renderer/material/material_system.cpp).
#pragma once
#include <array>
#include "renderer/bsdf/bsdf.h"
#include "renderer/material/material_system.h"

namespace tex::render {

// The arguments of std.gltf.metallic_roughness_anisotropic at a point (in its parameter order).
struct GltfInputs {
  Vec3 baseColor{1.0f};  // baseColorFactor x sRGB-decoded texture x COLOR_0, clamped to [0, 1]
  float metallic = 0, roughness = 1, transmission = 0, ior = 1.5f, dispersion = 0;
  float thinWalled = 0;  // 1: GltfMaterial::thinWalled
  Vec3 emission{0.0f};   // emissiveFactor x strength x sRGB-decoded texture
  // The layers' factors times their textures, clamped to their ranges.
  float clearcoat = 0, clearcoatRoughness = 0;  // KHR_materials_clearcoat (R, G)
  Vec3 sheenColor{0.0f};                        // KHR_materials_sheen (sRGB-decoded RGB)
  float sheenRoughness = 0;                     // (A)
  float specular = 1;                           // KHR_materials_specular (A)
  Vec3 specularColor{1.0f};                     // (sRGB-decoded RGB; may exceed 1)
  // KHR_materials_anisotropy: strength x texture B in [0, 1], and the direction's angle in the
  // Bsdf's shading frame (radians from its x axis toward y; gltfAnisotropyInto).
  float anisotropyStrength = 0, anisotropyRotationRad = 0;
  // The entry's arguments after the Hit, in std.gltf's order (tex_binding.h, CompiledGltf).
  std::array<float, 24> words() const {
    return {baseColor.x,     baseColor.y,     baseColor.z,     metallic,        roughness,          transmission,
            ior,             dispersion,      thinWalled,      emission.x,      emission.y,         emission.z,
            clearcoat,       clearcoatRoughness, sheenColor.x, sheenColor.y,    sheenColor.z,       sheenRoughness,
            specular,        specularColor.x, specularColor.y, specularColor.z, anisotropyStrength, anisotropyRotationRad};
  }
};
GltfInputs gltfInputs(const SceneDescription& scene, const GltfMaterial& material, const ShadingPoint& point);
// KHR_materials_anisotropy's strength and direction at the point: the direction (cos, sin of
// anisotropyRotation turned by the texture's RG direction) lies in the glTF tangent frame
// (TANGENT, or increasing u and decreasing v without one, as for normal maps) and is expressed
// as an angle in `shading`, the Bsdf's frame (its x axis need not be the glTF tangent).
void gltfAnisotropyInto(const SceneDescription& scene, const GltfMaterial& material, const ShadingPoint& point,
                        const Frame& shading, GltfInputs& in);

// Whether shading reads the point: some texture gltfInputs or the normal map looks up has an
// image. Without one the inputs, and so the closure tree, are the same at every hit of a mesh
// without vertex colours (MaterialSystem checks the meshes).
bool gltfReadsHit(const SceneDescription& scene, const GltfMaterial& material);

// KHR_materials_dispersion's IOR at one wavelength, as std.gltf.dispersive_ior computes it in
// the material (the renderer needs it outside the material too: a volume's medium, for the
// surfaces inside it). Test ClosureLobes.GltfDispersiveIorIsStdGltfs keeps the two equal.
float gltfDispersiveIor(float ior, float dispersion, float lambdaNm);

// Replaces the Bsdf's shading frame by the normal map's (no-op without a normal texture).
void applyGltfNormalMap(const SceneDescription& scene, const GltfMaterial& material, const ShadingPoint& point,
                        Bsdf& bsdf);
// Gives a Bsdf with a clearcoat its own frame where it differs from the Bsdf's: the
// clearcoatNormalTexture's, or the unmapped shading normal under a base normal map (the
// clearcoat does not follow the base's normal map; KHR_materials_clearcoat).
void applyGltfClearcoatNormal(const SceneDescription& scene, const GltfMaterial& material, const ShadingPoint& point,
                              Bsdf& bsdf);

// Emitted radiance (emissive factor x strength x texture, upsampled as an illuminant): what
// std.gltf's emission closure gives, evaluated natively for area lights. An unlit material
// (KHR_materials_unlit) emits its base colour instead and scatters nothing
// (docs/gltf-extensions.md).
Spectrum gltfEmission(const SceneDescription& scene, const GltfMaterial& material, const ShadingPoint& point,
                      const Wavelengths& lambda);

}  // namespace tex::render
