// Lights emit radiance (design contract 3). Each light samples an incident direction at a
// reference point (next-event estimation), evaluates the density of a direction that BSDF
// sampling found, and samples emitted rays (light tracing, BDPT, photon mapping), with the
// measure of every density explicit in its name:
//   pdfW   per solid angle at the reference point,
//   pdfPosA per unit area on the light (Dirac positions: 1, with the deltaPosition flag),
//   pdfDirW per solid angle at the emission point.
// Radiance values are spectral, evaluated at the path's wavelengths; each light owns a
// SpectrumSource for its emission (renderer/spectra/).
#pragma once
#include <algorithm>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "renderer/core/geometry.h"
#include "renderer/core/spectrum.h"
#include "renderer/lights/light_bounds.h"

namespace tex::render {

enum class LightKind : uint8_t { Point, Spot, Directional, Triangle, ConstantEnvironment, ImageEnvironment };

struct LightLiSample {
  // Member by member, without the block zeroing value-initialisation would add (a rep stos at
  // every light sample, built in place in the optional the lights return).
  LightLiSample() {}
  Spectrum L;          // radiance arriving at the reference point along -wi (before visibility)
  Vec3 wi{0.0f};       // toward the light
  Vec3 pLight{0.0f};   // point on the light (for shadow rays); far away for directional/environment
  Vec3 nLight{0.0f}; // light normal at pLight (0 for point-like lights)
  float pLightError = 0;  // bound on pLight's float error, every axis (area lights: trianglePointError's largest), for the shadow ray
  float distance = 0;  // shadow ray length (infinity for directional/environment)
  float pdfW = 0;      // solid angle (delta lights: 1)
  bool delta = false;  // a Dirac light: no MIS with BSDF sampling
  // From Light::sampleLiDeferred: L is not evaluated yet (Light::deferredRadiance gives it).
  bool radianceDeferred = false;
};

struct LightLeSample {
  Ray ray;             // emitted ray (origin on the light)
  Vec3 nLight{0.0f};   // normal at the origin (0 for point-like lights)
  Spectrum L;          // emitted radiance (intensity for point lights) along the ray
  float pdfPosA = 0;   // area density of the origin (Dirac: 1)
  float pdfDirW = 0;   // solid-angle density of the direction (Dirac: 1)
};

// The scene's extent, which distant lights need to aim emitted rays.
struct SceneSphere {
  Vec3 center{0.0f};
  float radius = 1.0f;
};

// Where an emitted radiance is evaluated: a point on an emissive surface with its geometry.
struct EmitterPoint {
  Vec3 p, n;   // position and the emitting side's normal
  int primitive = -1;
  // Where the point is on the scene's geometry (area lights), so that an emission that reads
  // its Hit sees what a ray hitting this point would: instance, triangle and the barycentrics
  // of its second and third vertices (SceneGeometry::surfaceAt). instance -1: not known.
  int instance = -1;
  uint32_t triangle = 0;
  Vec2 b12{0.0f};
  // The direction the radiance leaves in (unit, world), for emissions that depend on it (under
  // a clearcoat); 0: not known (an average over directions is wanted).
  Vec3 w{0.0f};
};

// The emission of area lights comes from the surface's material (a compiled .tex closure or a
// glTF emissive factor): the renderer evaluates it at a point through this interface.
class EmissionSource {
 public:
  virtual ~EmissionSource() = default;
  // Radiance leaving `point` (on its emitting side) at the group's wavelengths.
  virtual Spectrum radiance(const EmitterPoint& point, const Wavelengths& lambda) const = 0;
  // Luminance-like scalar for choosing lights by power (average over the surface).
  virtual float averageRadiance() const = 0;
  // Whether the radiance may depend on the shading point (then lights pass EmitterPoint's place
  // on the geometry, which costs a few operations; otherwise the point does not matter).
  virtual bool readsHit() const { return false; }
  // A luminance-like scalar of the radiance at one point (light selection by power for
  // emitters that vary over their surface); by default the surface's average.
  virtual float radianceEstimate(const EmitterPoint& point) const {
    (void)point;
    return averageRadiance();
  }
};

class Light {
 public:
  virtual ~Light() = default;
  virtual LightKind kind() const = 0;
  bool isDelta() const { return kind() == LightKind::Point || kind() == LightKind::Spot || kind() == LightKind::Directional; }
  bool isInfinite() const {
    return kind() == LightKind::Directional || kind() == LightKind::ConstantEnvironment || kind() == LightKind::ImageEnvironment;
  }
  // Called once after the scene's bounds are known.
  virtual void preprocess(const SceneSphere& sphere) { (void)sphere; }
  // Total emitted power (a scalar proxy, for choosing lights by power).
  virtual float power() const = 0;
  // Where and in which directions the light emits, for choosing it by its likely contribution
  // at a point (light_bvh.h); nullopt for lights without finite bounds (directional and
  // environment lights), which the light sampler chooses with a fixed probability.
  virtual std::optional<LightBounds> bounds() const { return std::nullopt; }

  virtual std::optional<LightLiSample> sampleLi(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const = 0;
  // sampleLi, except that a light whose radiance is costly (an area light runs its material's
  // emission) may leave L black and set radianceDeferred, so that an integrator evaluates it
  // (deferredRadiance) only for samples that turn out visible. Same sample, same values.
  virtual std::optional<LightLiSample> sampleLiDeferred(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const {
    return sampleLi(refPoint, u, lambda);
  }
  virtual Spectrum deferredRadiance(const LightLiSample& sample, const Wavelengths& lambda) const {
    (void)lambda;
    return sample.L;
  }
  // Area lights: density sampleLi would have had for reaching `onLight` from refPoint.
  // Environment lights: for the escaping direction wi. Delta lights: 0.
  virtual float pdfLi(const Vec3& refPoint, const Vec3& wi, const EmitterPoint* onLight) const = 0;

  // Emitted rays.
  virtual std::optional<LightLeSample> sampleLe(Vec2 uPos, Vec2 uDir, const Wavelengths& lambda) const = 0;
  virtual void pdfLe(const Ray& ray, const Vec3& nLight, float& pdfPosA, float& pdfDirW) const = 0;

  // Environment lights: radiance arriving along a ray that escapes the scene (direction of
  // travel ray.direction). Others: black.
  virtual Spectrum Le(const Ray& ray, const Wavelengths& lambda) const {
    (void)ray;
    (void)lambda;
    return Spectrum();
  }
};

}  // namespace tex::render
