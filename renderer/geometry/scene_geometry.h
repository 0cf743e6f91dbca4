// The scene's triangles in Embree 3: ray queries and the hit geometry the renderer shades.
// Triangles used once are baked into world space in the top-level BVH. Triangles used more
// than once (a primitive shared by several nodes, or equal primitives of meshes that differ
// only in material) are built once and instanced (Embree instances) when their copies would be
// large, so files such as MetalRoughSpheresNoTextures (1 M triangles, 12 k distinct) stay small
// (and trace faster: the copies' BVH missed the cache); small ones are baked per use, since a
// ray through an instance pays for a second BVH and a transform.
// Single rays for now; the interface leaves room for packets.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "renderer/core/geometry.h"
#include "renderer/scene/load_scene.h"
#include "renderer/scene/scene_description.h"

namespace tex::render {

inline Vec3 boundsCenter(const Bounds3& b) { return (b.lower + b.upper) * 0.5f; }
inline float boundsRadius(const Bounds3& b) { return b.empty() ? 0.0f : glm::length(b.upper - b.lower) * 0.5f; }

// What a ray hit, in world space.
struct SurfaceHit {
  // Member by member, without the block zeroing value-initialisation would add (a rep stos
  // at every path's hit).
  SurfaceHit() {}
  float t = 0;
  Vec3 p{0.0f};        // position (recomputed from barycentrics, not origin + t d)
  Vec3 pError{0.0f};   // bound on p's float error per coordinate (trianglePointError of the instance's extent), for ray offsets
  Vec3 ng{0.0f};       // unit geometric normal: the triangle's front side (counter-clockwise winding)
  Vec3 ns{0.0f};       // unit shading normal (interpolated vertex normals, or ng)
  Vec2 uv{0.0f};       // TEXCOORD_0 (0 when absent)
  Vec2 uv1{0.0f};      // TEXCOORD_1 (TEXCOORD_0's when absent)
  Vec4 color{1.0f};    // COLOR_0 (RGBA; 1 when absent)
  Vec3 dpdu{0.0f}, dpdv{0.0f};  // position derivatives w.r.t. uv (0 when uv is degenerate)
  Vec4 tangent{0.0f};  // glTF TANGENT interpolated (xyz world, w handedness); 0 when absent
  int instance = -1;   // SceneDescription::instances index
  int primitive = -1;  // SceneDescription::primitives index
  uint32_t triangle = 0;  // triangle within the primitive
  int material = -1;   // the primitive's glTF material (-1: default)
};

struct GeometryBuildOptions {
  // Triangles used n > 1 times are instanced when their extra copies, (n - 1) x their count,
  // would exceed this (about 10 MB of copies with their BVH; tests set 0 to instance all).
  // Measured on the shared glTF models: DispersionTest's 320-triangle prism used 25 times
  // traces 1.08x faster baked; MetalRoughSpheresNoTextures' 10.6 k-triangle sphere used 98
  // times 1.77x faster instanced (a baked copy per use missed the cache).
  uint64_t maxBakedCopyTriangles = 65536;
};

class SceneGeometry {
 public:
  // Builds the BVHs; returns null with `error` set if Embree fails or the scene is empty.
  static std::unique_ptr<SceneGeometry> build(const SceneDescription& scene, std::string& error,
                                              const GeometryBuildOptions& options = {});
  ~SceneGeometry();
  SceneGeometry(const SceneGeometry&) = delete;
  SceneGeometry& operator=(const SceneGeometry&) = delete;

  // Closest hit along the ray within (0, ray.tMax).
  bool intersect(const Ray& ray, SurfaceHit& hit) const;
  // Any hit within (0, ray.tMax).
  bool occluded(const Ray& ray) const;

  const Bounds3& bounds() const { return bounds_; }
  uint64_t triangleCount() const { return triangleCount_; }  // instanced, world
  uint64_t storedTriangleCount() const { return storedTriangleCount_; }  // distinct: each shared set once
  // Instances are numbered as in SceneDescription::instances; skipped ones (no triangles, a
  // degenerate transform) are not in the BVH.
  bool hasInstance(int instance) const;
  // World-space vertices of one triangle of an instance (for area lights), with their uv
  // (TEXCOORD_0) and the face normal.
  void triangleWorld(int instance, uint32_t triangle, Vec3 p[3], Vec2 uv[3], Vec3& ng) const;
  // What a ray hitting this instance's triangle at barycentrics (b1, b2) of its second and
  // third vertices would report (t = 0): for shading points sampled on lights.
  void surfaceAt(int instance, uint32_t triangle, float b1, float b2, SurfaceHit& hit) const {
    hit.t = 0.0f;
    fillHit(instance, triangle, b1, b2, hit);
  }

  // Alpha (glTF alphaMode) as light sampling must see it, the expectation of what rays see:
  // whether the instance's primitive is cut out or blended at all, and its coverage at a point:
  // MASK 1 or 0 (alpha against alphaCutoff), BLEND alpha (rays stop there with probability
  // alpha), 1 for opaque materials.
  bool cutOut(int instance) const;
  float coverage(int instance, uint32_t triangle, float b1, float b2) const;

  struct Impl;

 private:
  SceneGeometry() = default;
  // Fills `hit` for an instance, triangle and barycentrics (b1, b2).
  void fillHit(int instance, uint32_t triangle, float b1, float b2, SurfaceHit& hit) const;
  std::unique_ptr<Impl> impl_;
  Bounds3 bounds_;
  uint64_t triangleCount_ = 0;
  uint64_t storedTriangleCount_ = 0;
};

}  // namespace tex::render
