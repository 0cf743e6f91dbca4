#include "renderer/geometry/scene_geometry.h"

#include <embree3/rtcore.h>

#include "renderer/geometry/alpha_test.h"
#include "renderer/geometry/equal_primitives.h"

#include <cmath>
#include <cstddef>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <mutex>

namespace tex::render {

namespace {

void embreeError(void* userPtr, RTCError code, const char* message) {
  auto* sink = static_cast<std::string*>(userPtr);
  if (sink->empty()) *sink = "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "");
}

Vec3 transformPoint(const Mat4& m, const Vec3& p) { return Vec3(m * Vec4(p, 1.0f)); }

// What a hit takes from its triangle alone: the unit geometric normal (front side) and the
// uv parametrisation's position derivatives. One function for the per-hit computation and the
// per-triangle table of baked instances, so both give the same bits.
struct TriangleFrame {
  Vec3 ng{0.0f};
  Vec3 dpdu{0.0f}, dpdv{0.0f};  // 0 without uv or when it is degenerate
  // The shading normal when it is the same over the whole triangle (world, unit; baked
  // instances): its three vertex normals are equal, as on flat-shaded meshes whose vertices
  // are split per face. Interpolating them would only add rounding and cost a hit a square
  // root and a division. Without vertex normals it is ng. 0: it varies (interpolate).
  Vec3 flatNs{0.0f};
};

// The shading normal of a normal in object space (ng when it does not transform to a finite,
// non-zero vector).
Vec3 worldShadingNormal(const glm::mat3& normalToWorld, const Vec3& nObject, const Vec3& ng) {
  const Vec3 nWorld = normalToWorld * nObject;
  const float nl = glm::length(nWorld);
  return nl > 0.0f && std::isfinite(nl) ? nWorld / nl : ng;
}
TriangleFrame triangleFrame(const Vec3 p[3], const Vec2* uv /* 3 or null */, bool flipWinding) {
  TriangleFrame f;
  const Vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
  float len = 0.0f;
  const Vec3 n = triangleUnitNormal(e1, e2, len);
  f.ng = len > 0.0f ? n : Vec3(0.0f, 0.0f, 1.0f);
  if (flipWinding) f.ng = -f.ng;
  if (uv) {
    // Solve [e1 e2] = [dpdu dpdv] [duv1 duv2] for the uv parametrisation's derivatives.
    const Vec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
    const float det = d1.x * d2.y - d1.y * d2.x;
    if (std::fabs(det) > 1e-12f) {
      const float inv = 1.0f / det;
      f.dpdu = (e1 * d2.y - e2 * d1.y) * inv;
      f.dpdv = (e2 * d1.x - e1 * d2.x) * inv;
    }
  }
  return f;
}

// Our ray as Embree's: over (0, tMax), every geometry mask. Written as three 16-byte stores:
// Embree loads origin + tnear and direction + time as vectors, which stalled on store
// forwarding when the fields were written one by one (8-, 4- and 4-byte stores).
void writeEmbreeRay(const Ray& ray, RTCRay& r) {
#if defined(__SSE2__)
  static_assert(offsetof(RTCRay, tnear) == 12 && offsetof(RTCRay, time) == 28 && offsetof(RTCRay, flags) == 44);
  _mm_storeu_ps(&r.org_x, _mm_setr_ps(ray.origin.x, ray.origin.y, ray.origin.z, 0.0f));
  _mm_storeu_ps(&r.dir_x, _mm_setr_ps(ray.direction.x, ray.direction.y, ray.direction.z, 0.0f));
  uint32_t tFarBits;
  std::memcpy(&tFarBits, &ray.tMax, sizeof(tFarBits));
  // tfar, mask (every geometry), id, flags
  _mm_storeu_si128(reinterpret_cast<__m128i*>(&r.tfar), _mm_setr_epi32(int(tFarBits), -1, 0, 0));
#else
  r.org_x = ray.origin.x;
  r.org_y = ray.origin.y;
  r.org_z = ray.origin.z;
  r.dir_x = ray.direction.x;
  r.dir_y = ray.direction.y;
  r.dir_z = ray.direction.z;
  r.tnear = 0.0f;
  r.tfar = ray.tMax;
  r.time = 0.0f;
  r.mask = 0xFFFFFFFFu;
  r.id = 0;
  r.flags = 0;
#endif
}

}  // namespace

struct SceneGeometry::Impl {
  struct Instance {
    int primitive = 0;      // SceneDescription::primitives index: its material
    int triangleData = 0;   // the first primitive with the same triangles: vertex data read from it
    Mat4 toWorld{1.0f};
    glm::mat3 normalToWorld{1.0f};
    bool flipWinding = false;
    std::vector<Vec3> worldPositions;  // baked instances only
    // Baked instances: each triangle's frame, computed once (a hit would otherwise spend a
    // square root and four divisions on it); 36 bytes a triangle.
    std::vector<TriangleFrame> triangleFrames;
    bool valid = false;                // false: skipped (no triangles, degenerate transform)
    // Every hit point's float error bound (SurfaceHit::pError): trianglePointError of the
    // instance's largest world coordinates, per axis (at least each triangle's own bound, and
    // no work per hit); instanced geometry takes the largest axis on every axis, for the
    // rounding of its transform and of Embree's ray in object space.
    Vec3 pointError{0.0f};
  };
  const SceneDescription* scene = nullptr;
  std::string error;
  RTCDevice device = nullptr;
  RTCScene top = nullptr;
  std::vector<RTCScene> childScenes;  // per primitive (the first of equal ones, instanced ones only)
  std::vector<Instance> instances;
  std::vector<int> instanceOfTopGeometry;  // Embree top-level geomID -> instance
  std::vector<std::unique_ptr<AlphaTest>> alphaTests;  // per primitive with a cut-out material

  ~Impl() {
    for (RTCScene s : childScenes)
      if (s) rtcReleaseScene(s);
    if (top) rtcReleaseScene(top);
    if (device) rtcReleaseDevice(device);
  }

  // A triangle geometry over the given vertices (Embree copies them into its own buffers,
  // which it pads for 16-byte reads).
  RTCGeometry makeTriangles(const std::vector<Vec3>& positions, const std::vector<uint32_t>& indices) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size()));
    auto* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(uint32_t), indices.size() / 3));
    if (!v || !idx) {
      rtcReleaseGeometry(g);
      return nullptr;
    }
    std::memcpy(v, positions.data(), positions.size() * sizeof(Vec3));
    std::memcpy(idx, indices.data(), indices.size() * sizeof(uint32_t));
    return g;
  }

  // Cut-out (alphaMode MASK) and blended (BLEND) glTF materials: Embree's filter functions
  // make rays (closest-hit and shadow alike) pass through the transparent parts.
  bool needsAlphaTest(int primitive) const {
    const MeshPrimitive& prim = scene->primitives[size_t(primitive)];
    if (prim.material < 0 || size_t(prim.material) >= scene->materials.size()) return false;
    return scene->materials[size_t(prim.material)].alphaMode != GltfMaterial::AlphaMode::Opaque;
  }
  void attachAlphaTest(RTCGeometry g, int primitive) {
    if (!needsAlphaTest(primitive)) return;
    const MeshPrimitive& prim = scene->primitives[size_t(primitive)];
    const GltfMaterial& m = scene->materials[size_t(prim.material)];
    auto test = std::make_unique<AlphaTest>(*scene, prim, m);
    rtcSetGeometryUserData(g, test.get());
    rtcSetGeometryIntersectFilterFunction(g, AlphaTest::embreeFilter);
    rtcSetGeometryOccludedFilterFunction(g, AlphaTest::embreeFilter);
    alphaTests.push_back(std::move(test));
  }

  const Vec3* positionsOf(const Instance& inst) const {
    return inst.worldPositions.empty() ? nullptr : inst.worldPositions.data();
  }
  void worldVertices(const Instance& inst, uint32_t triangle, Vec3 p[3], uint32_t vi[3]) const {
    const MeshPrimitive& prim = scene->primitives[size_t(inst.triangleData)];
    for (int k = 0; k < 3; ++k) {
      vi[k] = prim.indices[size_t(triangle) * 3 + size_t(k)];
      p[k] = inst.worldPositions.empty() ? transformPoint(inst.toWorld, prim.positions[vi[k]]) : inst.worldPositions[vi[k]];
    }
  }
};

SceneGeometry::~SceneGeometry() = default;

std::unique_ptr<SceneGeometry> SceneGeometry::build(const SceneDescription& scene, std::string& error,
                                                    const GeometryBuildOptions& options) {
  std::unique_ptr<SceneGeometry> geometry(new SceneGeometry());
  geometry->impl_ = std::make_unique<Impl>();
  Impl& im = *geometry->impl_;
  im.scene = &scene;
  im.device = rtcNewDevice(nullptr);
  if (!im.device) {
    error = "cannot create the Embree device";
    return nullptr;
  }
  rtcSetDeviceErrorFunction(im.device, embreeError, &im.error);
  im.top = rtcNewScene(im.device);
  rtcSetSceneFlags(im.top, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(im.top, RTC_BUILD_QUALITY_HIGH);

  // Equal triangles are one geometry whoever uses them (a primitive per material, or per node).
  std::vector<bool> shareable(scene.primitives.size());
  for (size_t p = 0; p < scene.primitives.size(); ++p) shareable[p] = !im.needsAlphaTest(int(p));
  const std::vector<int> triangleData = firstEqualPrimitive(scene, shareable);
  std::vector<int> usesOfTriangles(scene.primitives.size(), 0);
  for (const MeshInstance& inst : scene.instances)
    if (inst.primitive >= 0 && size_t(inst.primitive) < scene.primitives.size())
      ++usesOfTriangles[size_t(triangleData[size_t(inst.primitive)])];
  im.childScenes.assign(scene.primitives.size(), nullptr);
  im.instances.resize(scene.instances.size());

  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const MeshInstance& desc = scene.instances[i];
    if (desc.primitive < 0 || size_t(desc.primitive) >= scene.primitives.size()) {
      error = "instance " + std::to_string(i) + " refers to a missing primitive";
      return nullptr;
    }
    const MeshPrimitive& prim = scene.primitives[size_t(desc.primitive)];
    if (prim.indices.empty()) continue;
    Impl::Instance inst;
    inst.primitive = desc.primitive;
    inst.triangleData = triangleData[size_t(desc.primitive)];
    inst.toWorld = desc.objectToWorld;
    const glm::mat3 linear(desc.objectToWorld);
    const float det = glm::determinant(linear);
    if (std::isfinite(det) && det != 0.0f) {
      inst.normalToWorld = glm::transpose(glm::inverse(linear));
      inst.flipWinding = det < 0.0f;
    } else {
      // In double when the float determinant overflows or underflows (a uniform scale above
      // about 7e12 or below 1e-13: the instance had been dropped silently as degenerate).
      const glm::dmat3 linearD(linear);
      const double detD = glm::determinant(linearD);
      if (!std::isfinite(detD) || detD == 0.0) continue;  // a degenerate transform: nothing to hit
      inst.normalToWorld = glm::mat3(glm::transpose(glm::inverse(linearD)));
      inst.flipWinding = detD < 0.0;
    }
    inst.valid = true;
    const int instanceIndex = int(i);
    unsigned geomId = RTC_INVALID_GEOMETRY_ID;
    const uint64_t extraCopies = uint64_t(usesOfTriangles[size_t(inst.triangleData)] - 1) * (prim.indices.size() / 3);
    if (extraCopies == 0 || extraCopies <= options.maxBakedCopyTriangles) {
      inst.worldPositions.resize(prim.positions.size());
      for (size_t v = 0; v < prim.positions.size(); ++v) {
        inst.worldPositions[v] = transformPoint(desc.objectToWorld, prim.positions[v]);
        geometry->bounds_.extend(inst.worldPositions[v]);
        inst.pointError = absMaxPerAxis(inst.pointError, inst.worldPositions[v]);
      }
      inst.triangleFrames.resize(prim.indices.size() / 3);
      for (size_t t = 0; t < inst.triangleFrames.size(); ++t) {
        Vec3 p[3];
        Vec2 uv[3];
        for (int k = 0; k < 3; ++k) {
          const uint32_t v = prim.indices[t * 3 + size_t(k)];
          p[k] = inst.worldPositions[v];
          if (!prim.uv0.empty()) uv[k] = prim.uv0[v];
        }
        TriangleFrame& frame = inst.triangleFrames[t];
        frame = triangleFrame(p, prim.uv0.empty() ? nullptr : uv, inst.flipWinding);
        if (prim.normals.empty()) {
          frame.flatNs = frame.ng;
        } else {
          const Vec3& n0 = prim.normals[prim.indices[t * 3]];
          if (n0 == prim.normals[prim.indices[t * 3 + 1]] && n0 == prim.normals[prim.indices[t * 3 + 2]])
            frame.flatNs = worldShadingNormal(inst.normalToWorld, n0, frame.ng);
        }
      }
      geometry->storedTriangleCount_ += prim.indices.size() / 3;
      RTCGeometry g = im.makeTriangles(inst.worldPositions, prim.indices);
      if (!g) break;
      im.attachAlphaTest(g, desc.primitive);
      rtcCommitGeometry(g);
      geomId = rtcAttachGeometry(im.top, g);
      rtcReleaseGeometry(g);
    } else {
      RTCScene& child = im.childScenes[size_t(inst.triangleData)];
      if (!child) {
        child = rtcNewScene(im.device);
        rtcSetSceneFlags(child, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(child, RTC_BUILD_QUALITY_HIGH);
        RTCGeometry g = im.makeTriangles(prim.positions, prim.indices);
        if (!g) break;
        im.attachAlphaTest(g, desc.primitive);
        rtcCommitGeometry(g);
        rtcAttachGeometry(child, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(child);
        geometry->storedTriangleCount_ += prim.indices.size() / 3;
      }
      RTCGeometry g = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(g, child);
      rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &desc.objectToWorld[0][0]);
      rtcCommitGeometry(g);
      geomId = rtcAttachGeometry(im.top, g);
      rtcReleaseGeometry(g);
      for (const Vec3& p : prim.positions) {
        const Vec3 world = transformPoint(desc.objectToWorld, p);
        geometry->bounds_.extend(world);
        inst.pointError = absMaxPerAxis(inst.pointError, world);
      }
      inst.pointError = Vec3(maxAbsComponent(inst.pointError));
    }
    if (geomId == RTC_INVALID_GEOMETRY_ID) break;
    inst.pointError *= kTrianglePointRelativeError;  // trianglePointError of the extent
    // Embree's triangle test multiplies an origin's offset by products of edges (about the
    // square of the extent): with every vertex on a coordinate plane (a floor at y = 0) the
    // bound on that axis is 0, the 1e-30 the offset adds underflowed there in scenes of about
    // 1e-8 units, and shadow rays hit the surface they left (the floor went black). Kept
    // above 1e-36 / extent^2 where that exceeds 1e-31 (extents below about 3e-3; others keep
    // their bounds bit for bit).
    if (const float extent = maxAbsComponent(inst.pointError) / kTrianglePointRelativeError; extent > 0.0f) {
      // At most 2^-20 of the extent: below about 1e-9 units float precision runs out anyway
      // (docs/renderer.md), and an offset as large as the scene would leave it.
      const float minimum = std::min(1e-36f / (extent * extent), extent * 0x1p-20f);
      if (minimum > 1e-31f && std::isfinite(minimum)) inst.pointError = glm::max(inst.pointError, Vec3(minimum));
    }
    if (im.instanceOfTopGeometry.size() <= geomId) im.instanceOfTopGeometry.resize(geomId + 1, -1);
    im.instanceOfTopGeometry[geomId] = instanceIndex;
    geometry->triangleCount_ += prim.indices.size() / 3;
    im.instances[i] = std::move(inst);
  }
  if (!im.error.empty()) {
    error = im.error;
    return nullptr;
  }
  rtcCommitScene(im.top);
  if (!im.error.empty()) {
    error = im.error;
    return nullptr;
  }
  if (geometry->triangleCount_ == 0) {
    error = "the scene has no triangles";
    return nullptr;
  }
  return geometry;
}

bool SceneGeometry::intersect(const Ray& ray, SurfaceHit& hit) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  writeEmbreeRay(ray, rh.ray);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->top, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  const unsigned topId = rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID ? rh.hit.instID[0] : rh.hit.geomID;
  const int instance = impl_->instanceOfTopGeometry[topId];
  fillHit(instance, rh.hit.primID, rh.hit.u, rh.hit.v, hit);
  hit.t = rh.ray.tfar;
  return true;
}

bool SceneGeometry::occluded(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r;
  writeEmbreeRay(ray, r);
  rtcOccluded1(impl_->top, &context, &r);
  return r.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

bool SceneGeometry::cutOut(int instance) const {
  const SceneDescription& scene = *impl_->scene;
  if (instance < 0 || size_t(instance) >= scene.instances.size()) return false;
  return impl_->needsAlphaTest(scene.instances[size_t(instance)].primitive);
}

float SceneGeometry::coverage(int instance, uint32_t triangle, float b1, float b2) const {
  if (!cutOut(instance)) return 1.0f;
  const SceneDescription& scene = *impl_->scene;
  const MeshPrimitive& prim = scene.primitives[size_t(scene.instances[size_t(instance)].primitive)];
  return AlphaTest(scene, prim, scene.materials[size_t(prim.material)]).coverage(triangle, b1, b2);
}

bool SceneGeometry::hasInstance(int instance) const {
  return instance >= 0 && size_t(instance) < impl_->instances.size() && impl_->instances[size_t(instance)].valid;
}

void SceneGeometry::triangleWorld(int instance, uint32_t triangle, Vec3 p[3], Vec2 uv[3], Vec3& ng) const {
  const Impl::Instance& inst = impl_->instances[size_t(instance)];
  uint32_t vi[3];
  impl_->worldVertices(inst, triangle, p, vi);
  const MeshPrimitive& prim = impl_->scene->primitives[size_t(inst.triangleData)];
  for (int k = 0; k < 3; ++k) uv[k] = prim.uv0.empty() ? Vec2(0.0f) : prim.uv0[vi[k]];
  float len = 0.0f;
  const Vec3 n = triangleUnitNormal(p[1] - p[0], p[2] - p[0], len);
  ng = len > 0.0f ? n : Vec3(0.0f, 0.0f, 1.0f);
  if (inst.flipWinding) ng = -ng;
}

void SceneGeometry::fillHit(int instance, uint32_t triangle, float b1, float b2, SurfaceHit& hit) const {
  const Impl::Instance& inst = impl_->instances[size_t(instance)];
  // Vertex data from the first primitive with these triangles (equal bits, and one copy in
  // the cache however many materials share it); the material is the instance's own.
  const MeshPrimitive& prim = impl_->scene->primitives[size_t(inst.triangleData)];
  Vec3 p[3];
  uint32_t vi[3];
  impl_->worldVertices(inst, triangle, p, vi);
  const float b0 = 1.0f - b1 - b2;
  hit.instance = instance;
  hit.primitive = inst.primitive;
  hit.triangle = triangle;
  hit.material = impl_->scene->primitives[size_t(inst.primitive)].material;
  hit.p = p[0] * b0 + p[1] * b1 + p[2] * b2;
  hit.pError = inst.pointError;
  Vec2 uv[3];
  if (!prim.uv0.empty())
    for (int k = 0; k < 3; ++k) uv[k] = prim.uv0[vi[k]];
  // The triangle's frame read in place from the baked table (or computed): a copy on the
  // stack, written in 16-byte pieces, was read back with narrower loads and stalled on store
  // forwarding (a fifth of this function's time).
  const auto takeFrame = [&hit](const TriangleFrame& frame) {
    hit.ng = frame.ng;
    hit.dpdu = frame.dpdu;
    hit.dpdv = frame.dpdv;
    return frame.flatNs;
  };
  const Vec3 flatNs = inst.triangleFrames.empty()
                          ? takeFrame(triangleFrame(p, prim.uv0.empty() ? nullptr : uv, inst.flipWinding))
                          : takeFrame(inst.triangleFrames[triangle]);
  if (flatNs != Vec3(0.0f)) {
    hit.ns = flatNs;
  } else if (!prim.normals.empty()) {
    const Vec3 nObject = prim.normals[vi[0]] * b0 + prim.normals[vi[1]] * b1 + prim.normals[vi[2]] * b2;
    hit.ns = worldShadingNormal(inst.normalToWorld, nObject, hit.ng);
  } else {
    hit.ns = hit.ng;
  }
  hit.tangent = Vec4(0.0f);
  if (!prim.tangents.empty()) {
    const Vec4 t = prim.tangents[vi[0]] * b0 + prim.tangents[vi[1]] * b1 + prim.tangents[vi[2]] * b2;
    const Vec3 tw = glm::mat3(inst.toWorld) * Vec3(t);
    const float tl = glm::length(tw);
    // A mirroring transform turns the frame's handedness: cross(M^-T n, M t) = -M cross(n, t)
    // for a mirror M, so the bitangent cross(n, t) w needs w times sign(det M), as an exporter
    // baking the mirror into the vertices writes it (normal maps had tilted the wrong way).
    const float handedness = (prim.tangents[vi[0]].w < 0.0f) != inst.flipWinding ? -1.0f : 1.0f;
    if (tl > 0.0f && std::isfinite(tl)) hit.tangent = Vec4(tw / tl, handedness);
  }
  hit.uv = prim.uv0.empty() ? Vec2(0.0f) : uv[0] * b0 + uv[1] * b1 + uv[2] * b2;
  hit.uv1 = prim.uv1.empty() ? hit.uv : prim.uv1[vi[0]] * b0 + prim.uv1[vi[1]] * b1 + prim.uv1[vi[2]] * b2;
  hit.color = prim.colors.empty() ? Vec4(1.0f)
                                  : prim.colors[vi[0]] * b0 + prim.colors[vi[1]] * b1 + prim.colors[vi[2]] * b2;
}

}  // namespace tex::render
