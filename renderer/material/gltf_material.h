// The built-in reading of a glTF 2.0 metallic-roughness material with the lobes the renderer
// has: base colour (factor x sRGB texture) as a Lambertian lobe, metalness as a smooth
// conductor whose complex IOR reproduces the base colour at normal incidence and its edge tint
// (Gulbrandsen 2014, "Artist Friendly Metallic Fresnel"), KHR_materials_transmission as a smooth
// dielectric with KHR_materials_ior and KHR_materials_dispersion (the extension's Abbe-number
// formula), and emission (emissiveFactor x strength x sRGB texture, upsampled as an illuminant).
// Roughness is not yet used: rough lobes come with the glossy model (docs/glossy-model.md).
#pragma once
#include "renderer/bsdf/bsdf.h"
#include "renderer/material/material_system.h"

namespace tex::render {

void shadeGltfMaterial(const SceneDescription& scene, const GltfMaterial& material, const ShadingPoint& point,
                       const Wavelengths& lambda, Bsdf& bsdf, Spectrum& emission);
Spectrum gltfEmission(const SceneDescription& scene, const GltfMaterial& material, const ShadingPoint& point,
                      const Wavelengths& lambda);
// The relative IOR of KHR_materials_dispersion at lambdaNm: n_d + (n_d - 1) / V_d (523655 /
// lambda^2 - 1.5168), V_d = 20 / dispersion, never below 1.
float dispersiveIor(float iorD, float dispersion, float lambdaNm);
// Gulbrandsen's complex IOR for a reflectance r at normal incidence and edge tint g (per lane).
void gulbrandsenIor(float r, float g, float& eta, float& k);

}  // namespace tex::render
