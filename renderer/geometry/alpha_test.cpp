#include "renderer/geometry/alpha_test.h"

#include <cstring>

#include "renderer/material/texture_lookup.h"
#include "renderer/sampling/hash.h"

namespace tex::render {

// What shading's base colour has as its alpha: baseColorFactor.a x the texture's alpha x the
// vertex colour's (COLOR_0), uv sets interpolated as SceneGeometry::fillHit does.
float AlphaTest::alpha(uint32_t triangle, float b1, float b2) const {
  float a = material_.baseColorFactor.w;
  const uint32_t* idx = &primitive_.indices[size_t(triangle) * 3];
  const float b0 = 1.0f - b1 - b2;
  if (material_.baseColorTexture.image >= 0) {
    Vec2 uv0(0.0f);
    if (!primitive_.uv0.empty())
      uv0 = primitive_.uv0[idx[0]] * b0 + primitive_.uv0[idx[1]] * b1 + primitive_.uv0[idx[2]] * b2;
    Vec2 uv1 = uv0;
    if (!primitive_.uv1.empty())
      uv1 = primitive_.uv1[idx[0]] * b0 + primitive_.uv1[idx[1]] * b1 + primitive_.uv1[idx[2]] * b2;
    a *= lookupTexture(scene_, material_.baseColorTexture, uv0, uv1, false).w;
  }
  if (!primitive_.colors.empty())
    a *= primitive_.colors[idx[0]].w * b0 + primitive_.colors[idx[1]].w * b1 + primitive_.colors[idx[2]].w * b2;
  return a;
}

bool AlphaTest::opaque(uint32_t triangle, float b1, float b2, uint32_t rayHash) const {
  const float a = alpha(triangle, b1, b2);
  if (material_.alphaMode == GltfMaterial::AlphaMode::Mask) return a >= material_.alphaCutoff;
  if (!(a < 1.0f)) return true;
  if (!(a > 0.0f)) return false;
  return float(rayHash >> 8) * (1.0f / 16777216.0f) < a;
}

float AlphaTest::coverage(uint32_t triangle, float b1, float b2) const {
  const float a = alpha(triangle, b1, b2);
  if (material_.alphaMode == GltfMaterial::AlphaMode::Mask) return a >= material_.alphaCutoff ? 1.0f : 0.0f;
  if (!(a < 1.0f)) return 1.0f;
  return a > 0.0f ? a : 0.0f;
}

void AlphaTest::embreeFilter(const RTCFilterFunctionNArguments* args) {
  const auto* test = static_cast<const AlphaTest*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const uint32_t primID = RTCHitN_primID(args->hit, args->N, i);
    const float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    // The ray's own numbers and the triangle's identity make BLEND's choice: the same ray
    // decides the same way at the same triangle every time (closest-hit and shadow rays agree),
    // and independently at each triangle it meets. (Until round 18 the triangle's index went
    // into bits the choice never read: every BLEND surface along a ray decided alike, and no
    // ray passed one BLEND layer to stop at another.)
    float words[6] = {RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                      RTCRayN_org_z(args->ray, args->N, i), RTCRayN_dir_x(args->ray, args->N, i),
                      RTCRayN_dir_y(args->ray, args->N, i), RTCRayN_dir_z(args->ray, args->N, i)};
    uint32_t bits[6];
    std::memcpy(bits, words, sizeof bits);
    const uint64_t geometry =
        (uint64_t(RTCHitN_instID(args->hit, args->N, i, 0)) << 32) | RTCHitN_geomID(args->hit, args->N, i);
    const uint64_t hash = sampling::hashWords(
        sampling::hashWords((uint64_t(bits[0]) << 32) | bits[1], (uint64_t(bits[2]) << 32) | bits[3],
                            (uint64_t(bits[4]) << 32) | bits[5]),
        geometry, primID);
    if (!test->opaque(primID, u, v, uint32_t(hash >> 32))) args->valid[i] = 0;
  }
}

}  // namespace tex::render
