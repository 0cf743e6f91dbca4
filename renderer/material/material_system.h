// Materials at run time: for every scene material, what the renderer gets at a hit — a BSDF
// (a weighted mixture of native lobes) and emitted radiance — at the path's wavelengths.
// A material is either a compiled .tex closure bound by the scene file (the closure tree the
// JIT-compiled function returns is walked into lobes) or the built-in reading of a glTF
// metallic-roughness material (renderer/material/gltf_material.cpp).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "renderer/bsdf/bsdf.h"
#include "renderer/core/spectrum.h"
#include "renderer/geometry/scene_geometry.h"
#include "renderer/scene/scene_description.h"

namespace tex::render {

struct MaterialOptions {
  int wavelengths = 4;  // lanes the .tex code is compiled for (the path's group size)
  bool quickCompile = false;
  bool useCache = true;
};

// What shading a hit gives.
struct ShadingPoint {
  Vec3 p, ng, ns;  // position, geometric and shading normals (world, unit)
  Vec2 uv{0.0f};
  Vec2 uv1{0.0f};      // glTF's second texture coordinate set (the first's when the mesh has none)
  Vec4 color{1.0f};    // glTF vertex colour COLOR_0 (RGBA; 1 when the mesh has none)
  Vec3 dpdu{0.0f}, dpdv{0.0f};
  Vec4 tangent{0.0f};  // glTF tangent (w: handedness), 0 when the mesh has none
  // The footprint of one pixel at this point (ray differentials; 0 when unknown): position
  // and uv change per pixel step in x and y. Texture filtering in .tex reads them (Hit.dpdx...).
  Vec3 dpdx{0.0f}, dpdy{0.0f};
  Vec2 duvdx{0.0f}, duvdy{0.0f};
};

struct CompileReport {
  double compileMs = 0;
  bool cacheHit = false;
};

class MaterialSystem {
 public:
  // Compiles the scene's .tex bindings; on failure returns null and `error` holds rendered
  // diagnostics (file:line:col with carets).
  static std::unique_ptr<MaterialSystem> create(const SceneDescription& scene, const MaterialOptions& options,
                                                std::string& error);
  ~MaterialSystem();

  // The material slot a primitive's hits shade with: its glTF material, or a .tex binding
  // that matches its mesh name, or the default grey diffuse. The functions below take slots.
  int materialOfPrimitive(int primitive) const;
  // The BSDF and emitted radiance (toward the front side) at a point of `material` (a slot;
  // -1 or out of range: the default grey diffuse). Returns false if the material could not be evaluated (its closure
  // tree overflowed the arena or holds an unknown kind); the result is then black.
  bool shade(int material, const ShadingPoint& point, const Wavelengths& lambda, Bsdf& bsdf, Spectrum& emission) const;
  // Emitted radiance only (area lights).
  Spectrum emission(int material, const ShadingPoint& point, const Wavelengths& lambda) const;
  bool isEmissive(int material) const;
  // Whether shading `material` may read the pixel footprint (ShadingPoint's dpdx ... duvdy),
  // so that an integrator computes it only for those: true for a .tex material whose closure
  // tree may read the Hit; false for the others, the default grey and glTF materials (their
  // textures are looked up bilinearly at full resolution, without a footprint).
  bool readsPixelFootprint(int material) const;
  // Whether shading or emission of `material` may depend on the ShadingPoint at all (false for
  // Hit-independent .tex materials, glTF materials without textures and the default grey).
  bool readsHit(int material) const;
  // The fixed wavelength group materials are probed with (averageEmission, light power).
  const Wavelengths& probeWavelengths() const;
  bool emitsBothSides(int material) const;
  // Whether the emission leaves through a clearcoat (a glTF material, not bound to .tex, with
  // emission and KHR_materials_clearcoat, and an IOR other than 0), which darkens it by direction
  // (Bsdf::clearcoatEmissionFactor): a light sample of it then shades the whole material at the
  // point, and a path that hits it applies the factor; for every other material neither does.
  bool emissionUnderClearcoat(int material) const;
  // Beer-Lambert absorption inside a closed object of this material (KHR_materials_volume:
  // transmittance attenuationColor^(d / attenuationDistance)): the absorption coefficient per
  // wavelength, per metre of path. False for materials without a volume.
  bool interiorAbsorption(int material, const Wavelengths& lambda, Spectrum& sigmaA) const;
  // Whether a straight ray may pass through this material unbent: it may hold a smooth thin
  // wall (a .tex thin_dielectric, a glTF thin-walled transmissive material). Such surfaces
  // let point, spot and directional lights through (Bsdf::straightThrough); false for every
  // material means shadow rays need not look at what stops them.
  bool mayPassStraightRays(int material) const;
  bool anyMayPassStraightRays() const;
  // Whether light this material transmits enters a volume (a transmissive glTF or scene-file pbr
  // material that is not a thin wall), even one of index 1; .tex materials say so by refracting.
  bool transmitsIntoAVolume(int material) const;
  bool anyTransmitsIntoAVolume() const;
  // The IOR inside a volume of this material at each wavelength (glTF and scene-file pbr solids:
  // ior, with KHR_materials_dispersion's formula as std.gltf.dispersive_ior has it; an invalid
  // ior reads as 1.5 as there). False for others (.tex materials: their IOR is in their code).
  bool interiorIor(int material, const Wavelengths& lambda, Spectrum& eta) const;
  // A scalar proxy of the average emitted radiance (for choosing lights by power).
  float averageEmission(int material) const;

  const CompileReport& compileReport() const { return report_; }
  // Evaluation failures so far (arena overflow, unknown closure kinds), for the summary.
  uint64_t failures() const;

  struct Impl;

 private:
  MaterialSystem() = default;
  std::unique_ptr<Impl> impl_;
  CompileReport report_;
};

}  // namespace tex::render
