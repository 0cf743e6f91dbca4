// Spatial and directional bounds of a light's emission, for choosing lights by their likely
// contribution at a reference point (the light BVH, light_bvh.h). After Conty Estevez and
// Kulla 2018, "Importance Sampling of Many Lights with Adaptive Tree Splitting", section 4,
// and pbrt-v4's LightBounds: a box holding the emitter, a cone of its emitting normals (axis w,
// half-angle theta_o) and the spread of emission about each normal (theta_e: pi/2 for a
// Lambertian surface), a scalar power phi and whether it emits from both faces.
#pragma once
#include "renderer/core/geometry.h"
#include "renderer/scene/load_scene.h"

namespace tex::render {

// A cone of directions: axis w (unit), cosTheta the cosine of its half-angle (-1: every
// direction).
struct DirectionCone {
  Vec3 w{0.0f, 0.0f, 1.0f};
  float cosTheta = 1.0f;
  static DirectionCone entireSphere() { return {Vec3(0.0f, 0.0f, 1.0f), -1.0f}; }
};
// The smallest cone (up to a small widening against rounding) holding both.
DirectionCone unionCones(const DirectionCone& a, const DirectionCone& b);

// Where importance is judged: the shading point and the normal that bounds the receiver's
// cosine factor. n points to the side whose directions can contribute (a reflecting BSDF: wo's
// side); n = 0 means "no normal" (a transmitting BSDF, or a point in a medium).
struct LightSampleContext {
  Vec3 p{0.0f};
  Vec3 n{0.0f};
};

struct LightBounds {
  Bounds3 box;
  // A radiant-intensity-like scale (W/sr in the power() proxy's units): importance is
  // phi * cos bounds / distance^2, an estimate of irradiance. Triangles: radiance x area (one
  // face); point and spot lights: their intensity on the axis.
  float phi = 0.0f;
  DirectionCone normals;  // theta_o: bounds the emitting normals (spot: the axis)
  float cosThetaE = 0.0f;  // theta_e: emission spread about a normal (Lambertian: pi/2)
  bool twoSided = false;   // emits around -w too
};

LightBounds unionBounds(const LightBounds& a, const LightBounds& b);

// Cosine of the half-angle of a cone from p holding the box (its bounding sphere); -1 when p is
// inside the sphere.
float cosBoundSubtended(const Bounds3& box, const Vec3& p);

// An upper-bound-like estimate of what a light inside the bounds can contribute at ctx,
// relative to others (Conty Estevez and Kulla, eq. 3 with the receiver's cosine bound; pbrt-v4
// LightBounds::Importance, but one-sided in n). Conservative: positive whenever some point of
// the box, with a normal in the cone, emits toward p and lies on n's side of p (n = 0: any
// side). Its parameters are passed unpacked so that compact BVH nodes need not rebuild a
// LightBounds.
float lightImportance(const LightSampleContext& ctx, const Vec3& lower, const Vec3& upper, float phi, const Vec3& w,
                      float cosThetaO, float cosThetaE, bool twoSided);
inline float lightImportance(const LightSampleContext& ctx, const LightBounds& b) {
  return lightImportance(ctx, b.box.lower, b.box.upper, b.phi, b.normals.w, b.normals.cosTheta, b.cosThetaE, b.twoSided);
}

}  // namespace tex::render
