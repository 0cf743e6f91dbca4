// Hit geometry (renderer/geometry/scene_geometry.cpp): the geometric normal and the uv
// derivatives of a hit are its triangle's, bit for bit, whether they come from the per-triangle
// table of a baked primitive or are computed at the hit (instanced primitives), with mirrored
// transforms flipping the normal; equal triangles under different materials are built once
// and keep their materials; and closed meshes are watertight (no ray through an edge).
#include <gtest/gtest.h>

#include <cmath>

#include <cstring>
#include <memory>

#include "renderer/geometry/equal_primitives.h"
#include "renderer/geometry/scene_geometry.h"
#include "renderer/sampling/pcg.h"

namespace tex::render {
namespace {

// A soup of random triangles with random uv in a 2-unit cube around the origin.
MeshPrimitive randomSoup(uint64_t seed, int triangles) {
  MeshPrimitive m;
  for (int t = 0; t < triangles; ++t) {
    for (int k = 0; k < 3; ++k) {
      const uint64_t i = uint64_t(t * 3 + k);
      m.positions.push_back(Vec3(2.0f * sampling::randomUniform(seed, i, 0) - 1.0f, 2.0f * sampling::randomUniform(seed, i, 1) - 1.0f,
                                 2.0f * sampling::randomUniform(seed, i, 2) - 1.0f));
      m.uv0.push_back(Vec2(sampling::randomUniform(seed, i, 3), sampling::randomUniform(seed, i, 4)));
      m.indices.push_back(uint32_t(i));
    }
  }
  return m;
}

bool sameBits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Ray i of a set along +x from x = -10 toward the clusters of buildBakedAndInstanced: odd rays
// through the one at z = +4, even ones through z = -4, spread over z by `zSpread` and y by `ySpread`.
Ray rayAlongX(uint64_t seed, uint64_t i, float zSpread, float ySpread) {
  Ray ray;
  const float z = (i % 2 ? 4.0f : -4.0f) + zSpread * (sampling::randomUniform(seed, i, 0) - 0.5f);
  ray.origin = Vec3(-10.0f, ySpread * (sampling::randomUniform(seed, i, 1) - 0.5f), z);
  ray.direction = Vec3(1.0f, 0.0f, 0.0f);
  ray.tMax = 15.0f;  // short of the far instance
  return ray;
}

// Barycentrics (b1, b2) of a point on the triangle p[3], from the point (least squares).
Vec2 barycentricsOf(const Vec3 p[3], const Vec3& point) {
  const Vec3 e1 = p[1] - p[0], e2 = p[2] - p[0], d = point - p[0];
  const float a00 = dot3(e1, e1), a01 = dot3(e1, e2), a11 = dot3(e2, e2);
  const float det = a00 * a11 - a01 * a01;
  return Vec2((a11 * dot3(e1, d) - a01 * dot3(e2, d)) / det, (a00 * dot3(e2, d) - a01 * dot3(e1, d)) / det);
}

// Instances of a scene's primitives 0 and 1 and the geometry built from them: primitive 0 used
// once (baked into the top-level BVH, with the per-triangle table) with linear part `baked`
// moved to z = -4; primitive 1 used twice (an Embree instance, hit data computed per hit) with
// linear part `instanced`, at z = +4 and far away at x = +100 (out of the tests' rays).
std::unique_ptr<SceneGeometry> buildBakedAndInstanced(SceneDescription& scene, Mat4 baked, Mat4 instanced) {
  Mat4 instancedFar = instanced;
  baked[3] = Vec4(0.0f, 0.0f, -4.0f, 1.0f);
  instanced[3] = Vec4(0.0f, 0.0f, 4.0f, 1.0f);
  instancedFar[3] = Vec4(100.0f, 0.0f, 0.0f, 1.0f);
  scene.instances.push_back(MeshInstance{0, baked, "baked"});
  scene.instances.push_back(MeshInstance{1, instanced, "instanced"});
  scene.instances.push_back(MeshInstance{1, instancedFar, "instanced elsewhere"});
  std::string error;
  std::unique_ptr<SceneGeometry> geometry = SceneGeometry::build(scene, error, GeometryBuildOptions{0});
  EXPECT_TRUE(geometry) << error;
  return geometry;
}

TEST(SceneGeometry, HitNormalAndUvDerivativesAreTheTrianglesBitForBit) {
  SceneDescription scene;
  scene.primitives.push_back(randomSoup(1, 40));  // used once: baked, per-triangle table
  scene.primitives.push_back(randomSoup(2, 40));  // used twice: instanced, computed per hit
  Mat4 mirrored(1.0f);
  mirrored[0][0] = -1.0f;  // a mirroring transform flips the winding
  const auto geometry = buildBakedAndInstanced(scene, mirrored, Mat4(1.0f));
  ASSERT_TRUE(geometry);

  int hits[2] = {0, 0};
  for (uint64_t i = 0; i < 4000; ++i) {
    // Rays along x through both clusters' slabs (z in [-5, -3] and [3, 5]).
    const Ray ray = rayAlongX(9, i, 2.0f, 2.0f);
    SurfaceHit hit;
    if (!geometry->intersect(ray, hit)) continue;
    ASSERT_TRUE(hit.instance == 0 || hit.instance == 1);
    ++hits[hit.instance];
    Vec3 p[3];
    Vec2 uv[3];
    Vec3 ng;
    geometry->triangleWorld(hit.instance, hit.triangle, p, uv, ng);
    EXPECT_TRUE(sameBits(hit.ng, ng)) << "instance " << hit.instance << " triangle " << hit.triangle;
    const Vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
    const Vec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
    const float det = d1.x * d2.y - d1.y * d2.x;
    ASSERT_GT(std::fabs(det), 1e-12f);
    const float inv = 1.0f / det;
    EXPECT_TRUE(sameBits(hit.dpdu, (e1 * d2.y - e2 * d1.y) * inv));
    EXPECT_TRUE(sameBits(hit.dpdv, (e2 * d1.x - e1 * d2.x) * inv));
    // The normal faces the mirrored (baked) cluster's flipped side: n . (e1 x e2) < 0 there.
    EXPECT_EQ(dot3(hit.ng, glm::cross(e1, e2)) < 0.0f, hit.instance == 0);
  }
  EXPECT_GT(hits[0], 300);
  EXPECT_GT(hits[1], 300);
}

// Triangle normals and cross lengths (twice the area) stay exact at any scale: in double where
// the float square of the cross product overflows, underflows or is denormal (at edges of 5e-12
// a denormal square had given a "unit" normal of length 0.7 and an area 41 % off).
TEST(SceneGeometry, TriangleNormalsAndAreasAreExactAtAnyScale) {
  for (const float edge : {1e-20f, 5.15e-12f, 1e-11f, 3e-11f, 1e-6f, 1.0f, 1e9f, 1e12f, 1e15f}) {
    float crossLength = 0.0f;
    const Vec3 n = triangleUnitNormal(Vec3(edge, 0.0f, 0.0f), Vec3(0.3f * edge, edge, 0.0f), crossLength);
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f) << edge;
    EXPECT_NEAR(n.z, 1.0f, 1e-6f) << edge;
    EXPECT_NEAR(double(crossLength) / (double(edge) * double(edge)), 1.0, 1e-5) << edge;
  }
  float crossLength = 1.0f;
  EXPECT_EQ(triangleUnitNormal(Vec3(1, 0, 0), Vec3(2, 0, 0), crossLength), Vec3(0.0f));  // degenerate
  EXPECT_EQ(crossLength, 0.0f);
}

// A tangent's handedness turns under a mirroring transform, baked or instanced: the world
// bitangent cross(n, t) w must stay the transformed object bitangent (glTF: as an exporter that
// bakes the mirror writes w' = -w). It had kept w, and normal maps tilted the wrong way.
TEST(SceneGeometry, MirroringTransformsTurnTheTangentsHandedness) {
  for (const bool mirror : {false, true}) {
    SceneDescription scene;
    for (uint64_t seed : {3, 4}) {
      MeshPrimitive m = randomSoup(seed, 40);
      for (size_t v = 0; v < m.positions.size(); ++v) {
        m.normals.push_back(Vec3(0, 0, 1));
        m.tangents.push_back(Vec4(1, 0, 0, 1));
      }
      scene.primitives.push_back(m);
    }
    Mat4 linear(1.0f);
    if (mirror) linear[0][0] = -1.0f;
    const auto geometry = buildBakedAndInstanced(scene, linear, linear);
    ASSERT_TRUE(geometry);
    int hits = 0;
    for (uint64_t i = 0; i < 2000; ++i) {
      SurfaceHit hit;
      if (!geometry->intersect(rayAlongX(11, i, 2.0f, 2.0f), hit)) continue;
      ++hits;
      // Object frame: n = +z, t = +x, bitangent cross(n, t) w = +y; the mirror in x keeps +y.
      const Vec3 n = hit.ns, t = Vec3(hit.tangent);
      const Vec3 bitangent = glm::cross(n, t) * hit.tangent.w;
      EXPECT_NEAR(bitangent.y, 1.0f, 1e-5f) << (mirror ? "mirrored" : "plain") << " instance " << hit.instance;
    }
    EXPECT_GT(hits, 300);
  }
}

// Shading normals: a triangle whose three vertex normals are equal has that normal (in world
// space, unit) everywhere, exactly when baked (precomputed per triangle); one with different
// vertex normals interpolates them at the hit's barycentrics; both under a non-uniform scale.
TEST(SceneGeometry, ShadingNormalsAreFlatOrInterpolatedPerTriangle) {
  SceneDescription scene;
  for (uint64_t seed : {3u, 4u}) {
    MeshPrimitive m = randomSoup(seed, 40);
    for (int t = 0; t < 40; ++t) {
      const Vec3 flat = glm::normalize(Vec3(0.3f, -0.5f, 0.8f) + Vec3(sampling::randomUniform(seed, uint64_t(t), 7)));
      for (int k = 0; k < 3; ++k) {
        const Vec3 varying = glm::normalize(Vec3(sampling::randomUniform(seed, uint64_t(t * 3 + k), 5) - 0.5f,
                                                 sampling::randomUniform(seed, uint64_t(t * 3 + k), 6) - 0.5f, 1.0f));
        m.normals.push_back(t % 2 == 0 ? flat : varying);
      }
    }
    scene.primitives.push_back(m);
  }
  Mat4 stretched(1.0f);
  stretched[1][1] = 3.0f;
  stretched[2][2] = 0.5f;
  const auto geometry = buildBakedAndInstanced(scene, stretched, stretched);
  ASSERT_TRUE(geometry);
  const glm::mat3 normalToWorld = glm::transpose(glm::inverse(glm::mat3(stretched)));

  int flatHits = 0, smoothHits = 0;
  for (uint64_t i = 0; i < 4000; ++i) {
    const Ray ray = rayAlongX(11, i, 0.5f, 6.0f);
    SurfaceHit hit;
    if (!geometry->intersect(ray, hit)) continue;
    const MeshPrimitive& prim = scene.primitives[size_t(hit.primitive)];
    const uint32_t* vi = &prim.indices[size_t(hit.triangle) * 3];
    EXPECT_NEAR(glm::length(hit.ns), 1.0f, 1e-6f);
    if (hit.triangle % 2 == 0) {
      ++flatHits;
      const Vec3 w = normalToWorld * prim.normals[vi[0]];
      const Vec3 expected = w / glm::length(w);
      if (hit.instance == 0)
        EXPECT_TRUE(sameBits(hit.ns, expected)) << "triangle " << hit.triangle;
      else
        EXPECT_LT(glm::length(hit.ns - expected), 1e-6f);
    } else {
      ++smoothHits;
      // Barycentrics from the hit point, then the interpolated normal.
      Vec3 p[3];
      Vec2 uv[3];
      Vec3 ng;
      geometry->triangleWorld(hit.instance, hit.triangle, p, uv, ng);
      const Vec2 b = barycentricsOf(p, hit.p);
      const float b1 = b.x, b2 = b.y;
      const Vec3 n = prim.normals[vi[0]] * (1.0f - b1 - b2) + prim.normals[vi[1]] * b1 + prim.normals[vi[2]] * b2;
      EXPECT_LT(glm::length(hit.ns - glm::normalize(normalToWorld * n)), 2e-3f) << "triangle " << hit.triangle;
    }
  }
  EXPECT_GT(flatHits, 300);
  EXPECT_GT(smoothHits, 300);
}

// Meshes that differ only in material (glTF primitives over the same accessors) are one set of
// triangles: built once, instanced per use, each hit keeping its own primitive's material. A
// single changed bit, or a cut-out material (its alpha test belongs to its geometry), keeps a
// primitive to itself; and small sets are baked per use unless the options say otherwise.
TEST(SceneGeometry, EqualTrianglesUnderDifferentMaterialsAreBuiltOnce) {
  for (const bool cutOut : {false, true})
  for (const uint64_t maxBakedCopyTriangles : {uint64_t(0), uint64_t(39), uint64_t(40)}) {
    SCOPED_TRACE(std::string(cutOut ? "cut-out, " : "") + "max baked copies " + std::to_string(maxBakedCopyTriangles));
    SceneDescription scene;
    scene.materials.resize(3);
    scene.materials[2].alphaMode = GltfMaterial::AlphaMode::Mask;
    scene.materials[2].alphaCutoff = 0.0f;  // nothing is cut: only the geometry's sharing differs
    for (int material : {0, 1, 1}) {
      MeshPrimitive m = randomSoup(21, 40);
      m.material = material;
      scene.primitives.push_back(m);
    }
    if (cutOut) scene.primitives[1].material = 2;
    scene.primitives[2].positions[7].y = std::nextafter(scene.primitives[2].positions[7].y, 2.0f);
    scene.primitives.push_back(randomSoup(22, 40));  // different triangles
    const std::vector<int> first = firstEqualPrimitive(scene, {true, !cutOut, true, true});
    EXPECT_EQ(first, (std::vector<int>{0, cutOut ? 1 : 0, 2, 3}));

    for (int p = 0; p < 3; ++p) {
      Mat4 toWorld(1.0f);
      toWorld[3] = Vec4(0.0f, 0.0f, -4.0f + 4.0f * float(p), 1.0f);
      scene.instances.push_back(MeshInstance{p, toWorld, "row " + std::to_string(p)});
    }
    std::string error;
    const std::unique_ptr<SceneGeometry> geometry =
        SceneGeometry::build(scene, error, GeometryBuildOptions{maxBakedCopyTriangles});
    ASSERT_TRUE(geometry) << error;
    EXPECT_EQ(geometry->triangleCount(), 120u);
    // Rows 0 and 1 share 40 triangles: one extra copy of 40 when baked.
    EXPECT_EQ(geometry->storedTriangleCount(), cutOut || maxBakedCopyTriangles >= 40 ? 120u : 80u);

    int hits[3] = {0, 0, 0};
    for (uint64_t i = 0; i < 3000; ++i) {
      Ray ray;
      const int row = int(i % 3);
      ray.origin = Vec3(-10.0f, 2.0f * sampling::randomUniform(23, i, 1) - 1.0f,
                        -4.0f + 4.0f * float(row) + 2.0f * sampling::randomUniform(23, i, 0) - 1.0f);
      ray.direction = Vec3(1.0f, 0.0f, 0.0f);
      ray.tMax = 20.0f;
      SurfaceHit hit;
      if (!geometry->intersect(ray, hit)) continue;
      ASSERT_TRUE(hit.instance >= 0 && hit.instance < 3);
      ++hits[hit.instance];
      EXPECT_EQ(hit.primitive, hit.instance);
      EXPECT_EQ(hit.material, scene.primitives[size_t(hit.instance)].material);
      // The hit lies on its triangle of its own primitive, moved to its row.
      const MeshPrimitive& prim = scene.primitives[size_t(hit.primitive)];
      const Vec3 offset(0.0f, 0.0f, -4.0f + 4.0f * float(hit.instance));
      const Vec3 a = prim.positions[prim.indices[hit.triangle * 3]] + offset;
      const Vec3 b = prim.positions[prim.indices[hit.triangle * 3 + 1]] + offset;
      const Vec3 c = prim.positions[prim.indices[hit.triangle * 3 + 2]] + offset;
      const Vec3 n = glm::normalize(glm::cross(b - a, c - a));
      EXPECT_NEAR(dot3(hit.p - a, n), 0.0f, 1e-5f);
      EXPECT_NEAR(std::fabs(dot3(hit.ng, n)), 1.0f, 1e-5f);
    }
    for (int p = 0; p < 3; ++p) EXPECT_GT(hits[p], 300) << "row " << p;
  }
}

// A hit's second uv set and vertex colour (glTF TEXCOORD_1, COLOR_0) are its triangle's
// vertices' at the hit's barycentrics, baked or instanced; without them the hit has the first
// uv set and white.
TEST(SceneGeometry, SecondUvSetAndVertexColoursAreInterpolatedAtTheHit) {
  SceneDescription scene;
  for (uint64_t seed : {31u, 32u}) {
    MeshPrimitive m = randomSoup(seed, 40);
    if (seed == 31)
      for (size_t v = 0; v < m.positions.size(); ++v) {
        m.uv1.push_back(Vec2(sampling::randomUniform(seed, v, 8), sampling::randomUniform(seed, v, 9)));
        m.colors.push_back(Vec4(sampling::randomUniform(seed, v, 10), sampling::randomUniform(seed, v, 11),
                                sampling::randomUniform(seed, v, 12), sampling::randomUniform(seed, v, 13)));
      }
    scene.primitives.push_back(m);
  }
  const auto geometry = buildBakedAndInstanced(scene, Mat4(1.0f), Mat4(1.0f));
  ASSERT_TRUE(geometry);
  int hits[2] = {0, 0};
  for (uint64_t i = 0; i < 2000; ++i) {
    const Ray ray = rayAlongX(33, i, 2.0f, 2.0f);
    SurfaceHit hit;
    if (!geometry->intersect(ray, hit)) continue;
    ++hits[hit.instance];
    const MeshPrimitive& prim = scene.primitives[size_t(hit.primitive)];
    const uint32_t* vi = &prim.indices[size_t(hit.triangle) * 3];
    Vec3 p[3];
    Vec2 uv[3];
    Vec3 ng;
    geometry->triangleWorld(hit.instance, hit.triangle, p, uv, ng);
    const Vec2 b = barycentricsOf(p, hit.p);
    const float b1 = b.x, b2 = b.y, b0 = 1.0f - b1 - b2;
    if (prim.colors.empty()) {
      EXPECT_EQ(hit.color, Vec4(1.0f));
      EXPECT_EQ(hit.uv1, hit.uv);
    } else {
      const Vec4 c = prim.colors[vi[0]] * b0 + prim.colors[vi[1]] * b1 + prim.colors[vi[2]] * b2;
      const Vec2 t = prim.uv1[vi[0]] * b0 + prim.uv1[vi[1]] * b1 + prim.uv1[vi[2]] * b2;
      EXPECT_LT(glm::length(hit.color - c), 2e-3f) << "triangle " << hit.triangle;
      EXPECT_LT(glm::length(hit.uv1 - t), 2e-3f) << "triangle " << hit.triangle;
    }
  }
  EXPECT_GT(hits[0], 300);
  EXPECT_GT(hits[1], 300);
}

// A UV sphere whose rings share their vertices (no duplicated seam), so it is closed exactly.
MeshPrimitive closedSphere(int segments, int rings) {
  MeshPrimitive m;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double theta = M_PI * r / rings, phi = 2.0 * M_PI * s / segments;
      m.positions.push_back(Vec3(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)), float(std::cos(theta))));
    }
  const auto vertex = [&](int r, int s) { return uint32_t(r * segments + s % segments); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const uint32_t a = vertex(r, s), b = vertex(r + 1, s), c = vertex(r + 1, s + 1), d = vertex(r, s + 1);
      if (r != rings - 1) m.indices.insert(m.indices.end(), {a, b, c});
      if (r != 0) m.indices.insert(m.indices.end(), {a, c, d});
    }
  return m;
}

// Rays from inside a closed mesh aimed exactly at points on its edges (the float point on the
// segment between two shared vertices) must all hit it. This is what Embree's robust mode
// (RTC_SCENE_FLAG_ROBUST) buys: without it, 6% of such rays pass through this sphere and 0.1%
// through a cube (docs/renderer.md, "Robust traversal"), which would let paths escape closed
// objects and shadow rays pass through closed occluders.
TEST(SceneGeometry, ClosedMeshesAreWatertightAtTheirEdges) {
  MeshPrimitive cube;
  for (int c = 0; c < 8; ++c) cube.positions.push_back(Vec3(c & 1 ? 1.0f : -1.0f, c & 2 ? 1.0f : -1.0f, c & 4 ? 1.0f : -1.0f));
  const uint32_t faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& q : faces) cube.indices.insert(cube.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
  for (const MeshPrimitive& mesh : {closedSphere(48, 24), cube}) {
    SceneDescription scene;
    scene.primitives.push_back(mesh);
    scene.instances.push_back(MeshInstance{0, Mat4(1.0f), "closed"});
    std::string error;
    const std::unique_ptr<SceneGeometry> geometry = SceneGeometry::build(scene, error);
    ASSERT_TRUE(geometry) << error;
    const uint64_t triangles = mesh.indices.size() / 3;
    int misses = 0;
    const int rays = 200000;
    for (int i = 0; i < rays; ++i) {
      const uint64_t n = uint64_t(i);
      Ray ray;
      ray.origin = Vec3(sampling::randomUniform(5, n, 0), sampling::randomUniform(5, n, 1), sampling::randomUniform(5, n, 2)) * 0.2f - 0.1f;
      const uint64_t t = std::min<uint64_t>(uint64_t(sampling::randomUniform(5, n, 3) * float(triangles)), triangles - 1);
      const int e = std::min(int(sampling::randomUniform(5, n, 4) * 3.0f), 2);
      const Vec3 a = mesh.positions[mesh.indices[t * 3 + uint64_t(e)]];
      const Vec3 b = mesh.positions[mesh.indices[t * 3 + uint64_t((e + 1) % 3)]];
      const Vec3 onEdge = a + sampling::randomUniform(5, n, 5) * (b - a);
      ray.direction = glm::normalize(onEdge - ray.origin);
      SurfaceHit hit;
      misses += geometry->intersect(ray, hit) ? 0 : 1;
    }
    EXPECT_EQ(misses, 0) << "of " << rays << " rays aimed at the edges of a closed mesh of " << triangles << " triangles";
  }
}

}  // namespace
}  // namespace tex::render
