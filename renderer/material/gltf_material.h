// The built-in reading of a glTF 2.0 metallic-roughness material: the dielectric part is a
// Fresnel coat of the material's IOR (GGX, alpha = roughness^2) over a Lambertian base of the
// base colour (factor x sRGB texture); metalness is a GGX conductor whose complex IOR
// reproduces the base colour at normal incidence and its edge tint (Gulbrandsen 2014, "Artist
// Friendly Metallic Fresnel"); KHR_materials_transmission is a GGX dielectric with
// KHR_materials_ior and KHR_materials_dispersion (the extension's Abbe-number formula);
// emission is emissiveFactor x strength x sRGB texture, upsampled as an illuminant.
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
