// Alpha for glTF materials (alphaMode MASK and BLEND), applied during ray traversal through
// Embree filter functions, so that camera, bounce and shadow rays all pass through the
// transparent parts. MASK: opaque where alpha >= alphaCutoff. BLEND: opaque with probability
// alpha (stochastic transparency), decided by a hash of the ray and the hit, so the same ray
// always makes the same choice (results stay a function of the sample index).
// alpha = baseColorFactor.a x the base colour texture's alpha at the hit's uv x the vertex colour's.
#pragma once
#include <embree3/rtcore.h>

#include "renderer/scene/scene_description.h"

namespace tex::render {

class AlphaTest {
 public:
  AlphaTest(const SceneDescription& scene, const MeshPrimitive& primitive, const GltfMaterial& material)
      : scene_(scene), primitive_(primitive), material_(material) {}

  // Alpha at barycentrics (b1, b2) of a triangle of the primitive.
  float alpha(uint32_t triangle, float b1, float b2) const;
  // Whether a ray hitting there stops (rayHash picks BLEND's random choice).
  bool opaque(uint32_t triangle, float b1, float b2, uint32_t rayHash) const;
  // The probability that it stops: MASK 1 or 0, BLEND alpha clamped to [0, 1] (what light
  // sampling multiplies an emitter's radiance by, so that it agrees with rays).
  float coverage(uint32_t triangle, float b1, float b2) const;

  static void embreeFilter(const RTCFilterFunctionNArguments* args);

 private:
  const SceneDescription& scene_;
  const MeshPrimitive& primitive_;
  const GltfMaterial& material_;
};

}  // namespace tex::render
