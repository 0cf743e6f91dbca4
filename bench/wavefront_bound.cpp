// A bound for the redesign docs/renderer.md (round 9) discusses: what a wavefront path tracer
// costs per camera path on the benchmark scene (scenes/cornell-box-mitsuba.json, the scene of
// cornell_vs_mitsuba.sh) when paths advance in packets of 16 along an active list compacted at
// every bounce, closest and shadow rays as Embree packets (rtcIntersect16 / rtcOccluded16).
// Deliberately stripped: Lambertian surfaces with the scene's RGB reflectances and its one area
// light written in, counter-based random numbers instead of the Sobol sampler, no film (each
// finished path's luminance is summed). It traces the renderer's paths (max depth 7, roulette
// after 5 events, next-event estimation with the power heuristic: the same rays per path) and
// its mean luminance is the image's (the `meanY` counter against the mean Y of a tex render).
// Not a renderer: the figure is what the renderer's generality (closure trees, Bsdf, Sobol,
// film) costs on top, and how much of a path Embree takes when packets replace single rays.
// Args: robust 1 RTC_SCENE_FLAG_ROBUST (SceneGeometry's) or 0 fast (Mitsuba's); vector 0 shades
// one lane at a time, 1 computes the packet's shading 16 lanes per operation (compiled for the
// host's vector width, CMakeLists.txt), between a scalar gather and scatter.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "bench/cornell_bench_scene.h"
#include "renderer/color/spectral_to_rgb.h"
#include "renderer/core/warp.h"
#include "renderer/sampling/hash.h"
#include "renderer/spectra/rgb_spectrum.h"

namespace {

using namespace tex;
using namespace tex::render;

constexpr int W = 16;
constexpr int kMaxDepth = 7, kRouletteDepth = 5;

struct Tri {
  Vec3 p0, e1, e2, n;  // world, unit normal (front: counter-clockwise)
  int material;        // 0 white, 1 green, 2 red, 3 light
};

struct Scene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<Tri> tris;
  std::vector<int> lightTris;
  std::vector<float> lightCdf;  // by area
  float lightArea = 0;
  SigmoidPolynomial albedo[4];
  RgbUnbounded emission;
  const Camera* camera = nullptr;

  explicit Scene(RTCSceneFlags flags) {
    const bench::CornellBenchScene& cornell = bench::cornellBenchScene();
    camera = &cornell.scene->camera();
    // cornell_mitsuba.tex: white, green and red diffuse; the light is white-diffuse and emits.
    const Vec3 rgb[4] = {{0.885809f, 0.698859f, 0.666422f}, {0.105421f, 0.37798f, 0.076425f},
                         {0.570068f, 0.0430135f, 0.0443706f}, {0.885809f, 0.698859f, 0.666422f}};
    for (int m = 0; m < 4; ++m) albedo[m] = rgbToSigmoid(rgb[m]);
    emission = rgbToUnbounded(Vec3(18.387f, 13.9873f, 6.75357f));
    const bench::WorldTriangles world = bench::worldTriangles(cornell);
    for (size_t t = 0; t < world.normals.size(); ++t) {
      const std::string& name = world.materials[t];
      const int m = name == "white" ? 0 : name == "green" ? 1 : name == "red" ? 2 : name == "light" ? 3 : -1;
      if (m < 0) bench::CornellBenchScene::fail("wavefront_bound: unexpected material " + name);
      const Vec3* p = &world.vertices[3 * t];
      tris.push_back({p[0], p[1] - p[0], p[2] - p[0], world.normals[t], m});
      if (m == 3) {
        lightTris.push_back(int(t));
        lightArea += 0.5f * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
        lightCdf.push_back(lightArea);
      }
    }
    if (lightTris.size() != 2) bench::CornellBenchScene::fail("wavefront_bound: the light should be two triangles");
    for (float& v : lightCdf) v /= lightArea;
    device = rtcNewDevice(nullptr);
    scene = bench::buildEmbreeScene(device, world.vertices, flags);
  }
  ~Scene() {
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  }
};

const Scene& theScene(bool robust) {
  static const Scene robustScene(RTC_SCENE_FLAG_ROBUST), fastScene(RTC_SCENE_FLAG_NONE);
  return robust ? robustScene : fastScene;
}

// Counter-based uniform numbers (a path's stream): the (path, dimension) pair mixed into one word
// and finished with lowbias32, as sampling::randomUniform's 64-bit hashes would not vectorise.
// U: uint32_t or a vector of them.
template <class U>
U hashBits(U path, U dim) {
  return sampling::lowbias32<U>(path * 0x9E3779B9u ^ (dim + 0x7F4A7C15u) * 0x85EBCA6Bu);
}
inline float rnd(uint32_t path, uint32_t dim) {
  return sampling::bitsToUnitFloat(hashBits(path, dim));
}

// Path state, structure of arrays.
struct Paths {
  std::vector<float> ox, oy, oz, dx, dy, dz, prevPdf;
  std::vector<float> beta[4], L[4], lambda[4], pdfLambda[4], albedo[4][4], le[4];
  std::vector<uint32_t> id;
  std::vector<int> depth;
  explicit Paths(size_t n) {
    for (auto* v : {&ox, &oy, &oz, &dx, &dy, &dz, &prevPdf}) v->resize(n);
    for (int j = 0; j < 4; ++j) {
      beta[j].resize(n), L[j].resize(n), lambda[j].resize(n), pdfLambda[j].resize(n), le[j].resize(n);
      for (int m = 0; m < 4; ++m) albedo[m][j].resize(n);
    }
    id.resize(n);
    depth.resize(n);
  }
};

struct Result {
  double sumY = 0;
  uint64_t rays = 0;
};

// One lane at a time (branches as written).
void shadePacketScalar(const Scene& s, Paths& P, const uint32_t* lane, int lanes, const RTCRayHit16& rh, RTCRay16& sr,
                       int* shadowValid, float (*pending)[4], bool* alive) {
      for (int i = 0; i < W; ++i) {
        shadowValid[i] = 0;
        alive[i] = false;
        sr.org_x[i] = sr.org_y[i] = sr.org_z[i] = 0.0f;
        sr.dir_x[i] = sr.dir_y[i] = 0.0f, sr.dir_z[i] = 1.0f;
        sr.tnear[i] = 0.0f, sr.tfar[i] = 0.0f, sr.time[i] = 0.0f, sr.mask[i] = ~0u, sr.id[i] = 0, sr.flags[i] = 0;
        if (i >= lanes || rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
        const uint32_t k = lane[i];
        const uint32_t path = P.id[k];
        const int depth = P.depth[k];
        const Tri& tri = s.tris[rh.hit.primID[i]];
        const Vec3 d(P.dx[k], P.dy[k], P.dz[k]);
        const Vec3 p = tri.p0 + tri.e1 * rh.hit.u[i] + tri.e2 * rh.hit.v[i];
        const Vec3 pError = trianglePointError(tri.p0, tri.p0 + tri.e1, tri.p0 + tri.e2);
        const float cosIn = dot3(d, tri.n);
        const Vec3 n = cosIn < 0.0f ? tri.n : -tri.n;  // facing the incoming ray
        const float* a[4] = {&P.albedo[tri.material][0][k], &P.albedo[tri.material][1][k],
                             &P.albedo[tri.material][2][k], &P.albedo[tri.material][3][k]};
        if (tri.material == 3 && cosIn < 0.0f) {
          float w = 1.0f;
          if (depth > 0) {
            const float dist2 = rh.ray.tfar[i] * rh.ray.tfar[i];
            const float pdfLight = dist2 / (-cosIn * s.lightArea);
            const float pb = P.prevPdf[k];
            w = pb * pb / (pb * pb + pdfLight * pdfLight);
          }
          for (int j = 0; j < 4; ++j) P.L[j][k] += P.beta[j][k] * P.le[j][k] * w;
        }
        if (depth >= kMaxDepth) continue;
        // Next-event estimation: a point on the light by area.
        const float ul = rnd(path, 3 + 7 * uint32_t(depth));
        const int lt = ul < s.lightCdf[0] ? s.lightTris[0] : s.lightTris[1];
        const Vec2 b = sampleUniformTriangle(Vec2(rnd(path, 4 + 7 * uint32_t(depth)), rnd(path, 5 + 7 * uint32_t(depth))));
        const Tri& lightTri = s.tris[size_t(lt)];
        const Vec3 q = lightTri.p0 + lightTri.e1 * b.x + lightTri.e2 * b.y;
        const Vec3 toL = q - p;
        const float dist2 = dot3(toL, toL), dist = std::sqrt(dist2);
        const Vec3 wi = toL / dist;
        const float cosL = -dot3(wi, lightTri.n), cosS = dot3(wi, n);
        pending[i][0] = pending[i][1] = pending[i][2] = pending[i][3] = 0.0f;
        if (cosL > 0.0f && cosS > 0.0f) {
          const float pdfLight = dist2 / (cosL * s.lightArea);
          const float pdfBsdf = cosS * kInvPi;
          const float w = pdfLight * pdfLight / (pdfLight * pdfLight + pdfBsdf * pdfBsdf);
          const float scale = cosS * kInvPi * w / pdfLight;
          for (int j = 0; j < 4; ++j) pending[i][j] = P.beta[j][k] * *a[j] * P.le[j][k] * scale;
          const Vec3 o = offsetRayOrigin(p, n, wi, pError);
          sr.org_x[i] = o.x, sr.org_y[i] = o.y, sr.org_z[i] = o.z;
          sr.dir_x[i] = wi.x, sr.dir_y[i] = wi.y, sr.dir_z[i] = wi.z;
          sr.tfar[i] = dist * 0.999f;
          shadowValid[i] = -1;
        }
        // Continuation: cosine-weighted around n; f cos / pdf = albedo.
        const Vec3 local = sampleCosineHemisphere(Vec2(rnd(path, 6 + 7 * uint32_t(depth)), rnd(path, 7 + 7 * uint32_t(depth))));
        const Frame f = Frame::fromNormal(n);
        const Vec3 wo = f.toWorld(local);
        float maxBeta = 0.0f;
        for (int j = 0; j < 4; ++j) {
          P.beta[j][k] *= *a[j];
          maxBeta = std::max(maxBeta, P.beta[j][k]);
        }
        P.prevPdf[k] = local.z * kInvPi;
        if (depth + 1 >= kRouletteDepth) {
          const float survive = std::min(1.0f, maxBeta);
          if (rnd(path, 8 + 7 * uint32_t(depth)) >= survive) continue;
          for (int j = 0; j < 4; ++j) P.beta[j][k] /= survive;
        }
        const Vec3 o = offsetRayOrigin(p, n, wo, pError);
        P.ox[k] = o.x, P.oy[k] = o.y, P.oz[k] = o.z;
        P.dx[k] = wo.x, P.dy[k] = wo.y, P.dz[k] = wo.z;
        P.depth[k] = depth + 1;
        alive[i] = true;
      }
}

// 16-lane vectors (GCC vector extensions) for shadePacketVector.
typedef float vf __attribute__((vector_size(64)));
typedef int32_t vi __attribute__((vector_size(64)));
typedef uint32_t vu __attribute__((vector_size(64)));
inline vf splat(float x) { return vf{} + x; }
inline vf load(const float* p) { vf v; std::memcpy(&v, p, sizeof v); return v; }
inline vi loadi(const int* p) { vi v; std::memcpy(&v, p, sizeof v); return v; }
inline vu loadu(const uint32_t* p) { vu v; std::memcpy(&v, p, sizeof v); return v; }
inline void store(float* p, vf v) { std::memcpy(p, &v, sizeof v); }
inline void storei(int* p, vi v) { std::memcpy(p, &v, sizeof v); }
inline vf absv(vf v) { return v < 0.0f ? -v : v; }
inline vf maxv(vf a, vf b) { return a > b ? a : b; }
inline vf sqrtv(vf v) {
  vf r;
  for (int i = 0; i < W; ++i) r[i] = std::sqrt(v[i]);
  return r;
}
// rnd() for 16 (path, dimension) pairs.
inline vf rndv(vu path, vu dim) {
  const vi bits = vi(hashBits(path, dim) >> 8);
  return __builtin_convertvector(bits, vf) * 0x1p-24f;
}

// shadePacketScalar's arithmetic for all 16 lanes at once: a scalar gather into arrays, the
// computation on 16-lane vectors with selects instead of branches, a scalar scatter back.
void shadePacketVector(const Scene& s, Paths& P, const uint32_t* lane, int lanes, const RTCRayHit16& rh, RTCRay16& sr,
                       int* shadowValid, float (*pending)[4], bool* alive) {
  alignas(64) float px[W], py[W], pz[W], nx[W], ny[W], nz[W], dx[W], dy[W], dz[W], t[W], prevPdf[W];
  alignas(64) float beta[4][W], alb[4][W], le[4][W], Ladd[4][W];
  alignas(64) uint32_t path[W];
  alignas(64) int depth[W], mat[W], hit[W];
  const Tri& l0 = s.tris[size_t(s.lightTris[0])];
  const Tri& l1 = s.tris[size_t(s.lightTris[1])];
  for (int i = 0; i < W; ++i) {  // gather
    hit[i] = i < lanes && rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
    const uint32_t k = i < lanes ? lane[i] : lane[0];
    const Tri& tri = s.tris[hit[i] ? rh.hit.primID[i] : 0];
    px[i] = tri.p0.x + tri.e1.x * rh.hit.u[i] + tri.e2.x * rh.hit.v[i];
    py[i] = tri.p0.y + tri.e1.y * rh.hit.u[i] + tri.e2.y * rh.hit.v[i];
    pz[i] = tri.p0.z + tri.e1.z * rh.hit.u[i] + tri.e2.z * rh.hit.v[i];
    nx[i] = tri.n.x, ny[i] = tri.n.y, nz[i] = tri.n.z, mat[i] = tri.material;
    dx[i] = P.dx[k], dy[i] = P.dy[k], dz[i] = P.dz[k], t[i] = rh.ray.tfar[i], prevPdf[i] = P.prevPdf[k];
    path[i] = P.id[k], depth[i] = P.depth[k];
    for (int j = 0; j < 4; ++j) beta[j][i] = P.beta[j][k], alb[j][i] = P.albedo[tri.material][j][k], le[j][i] = P.le[j][k];
  }
  alignas(64) float ox[W], oy[W], oz[W], wx[W], wy[W], wz[W], sox[W], soy[W], soz[W], six[W], siy[W], siz[W], sfar[W];
  alignas(64) int shadow[W], live[W];
  alignas(64) float pend[4][W];
  {  // compute: 16 lanes per operation (GCC vector extensions)
    const vf lightArea = splat(s.lightArea), zero = splat(0.0f), one = splat(1.0f);
    const vf DX = load(dx), DY = load(dy), DZ = load(dz), NX = load(nx), NY = load(ny), NZ = load(nz);
    const vf PX = load(px), PY = load(py), PZ = load(pz), T = load(t), PB = load(prevPdf);
    const vi D = loadi(depth), HIT = loadi(hit), MAT = loadi(mat);
    const vf cosIn = DX * NX + DY * NY + DZ * NZ;
    const vf flip = cosIn < zero ? one : -one;
    const vf FX = NX * flip, FY = NY * flip, FZ = NZ * flip;
    const vf absCosIn = cosIn < zero ? -cosIn : cosIn;
    const vf lightPdfHit = T * T / (absCosIn * lightArea);
    const vf wHit = D > 0 ? PB * PB / (PB * PB + lightPdfHit * lightPdfHit) : one;
    const vf emits = (HIT != 0) & (MAT == 3) & (cosIn < zero) ? wHit : zero;
    const vi scatter = (HIT != 0) & (D < kMaxDepth);
    const vu dim = vu(D) * 7u, id = loadu(path);
    const vf ul = rndv(id, dim + 3u), ub1 = rndv(id, dim + 4u), ub2 = rndv(id, dim + 5u);
    const vi first = ul < splat(s.lightCdf[0]);
    const vf half = splat(0.5f);
    const vf bx = ub1 < ub2 ? ub1 * half : ub1 - ub2 * half, by = ub1 < ub2 ? ub2 - ub1 * half : ub2 * half;
    const auto pick = [&](float a, float b) { return first ? splat(a) : splat(b); };
    const vf qx = pick(l0.p0.x, l1.p0.x) + pick(l0.e1.x, l1.e1.x) * bx + pick(l0.e2.x, l1.e2.x) * by;
    const vf qy = pick(l0.p0.y, l1.p0.y) + pick(l0.e1.y, l1.e1.y) * bx + pick(l0.e2.y, l1.e2.y) * by;
    const vf qz = pick(l0.p0.z, l1.p0.z) + pick(l0.e1.z, l1.e1.z) * bx + pick(l0.e2.z, l1.e2.z) * by;
    const vf lnx = pick(l0.n.x, l1.n.x), lny = pick(l0.n.y, l1.n.y), lnz = pick(l0.n.z, l1.n.z);
    const vf tx = qx - PX, ty = qy - PY, tz = qz - PZ;
    const vf dist2 = tx * tx + ty * ty + tz * tz, dist = sqrtv(dist2), invDist = one / dist;
    const vf ix = tx * invDist, iy = ty * invDist, iz = tz * invDist;
    const vf cosL = -(ix * lnx + iy * lny + iz * lnz), cosS = ix * FX + iy * FY + iz * FZ;
    const vi shadowMask = scatter & (cosL > zero) & (cosS > zero);
    const vf pdfLight = dist2 / (cosL * lightArea), pdfBsdf = cosS * splat(kInvPi);
    const vf wNee = pdfLight * pdfLight / (pdfLight * pdfLight + pdfBsdf * pdfBsdf);
    const vf scale = shadowMask != 0 ? cosS * splat(kInvPi) * wNee / pdfLight : zero;
    const vf two = splat(2.0f);
    const vf u1 = rndv(id, dim + 6u) * two - one, u2 = rndv(id, dim + 7u) * two - one;
    const vf a1 = u1 < zero ? -u1 : u1, a2 = u2 < zero ? -u2 : u2;
    const vi bigX = a1 > a2;
    const vf r = bigX ? u1 : u2, other = bigX ? u2 : u1;
    const vf ratio = r != zero ? other / (r != zero ? r : one) : zero;
    const vf x = splat(kPi / 4.0f) * ratio, x2 = x * x;
    const vf sinX = ((splat(-1.9515295891e-4f) * x2 + splat(8.3321608736e-3f)) * x2 - splat(1.6666654611e-1f)) * x2 * x + x;
    const vf cosX = ((splat(2.443315711809948e-5f) * x2 - splat(1.388731625493765e-3f)) * x2 + splat(4.166664568298827e-2f)) *
                        (x2 * x2) - half * x2 + one;
    const vf lx = bigX ? r * cosX : r * sinX, ly = bigX ? r * sinX : r * cosX;
    const vf lz2 = one - lx * lx - ly * ly;
    const vf lz = sqrtv(lz2 > zero ? lz2 : zero);
    const vf sign = FZ < zero ? -one : one, a = -one / (sign + FZ), b = FX * FY * a;
    const vf sx = one + sign * FX * FX * a, sy = sign * b, sz = -sign * FX;
    const vf uy = sign + FY * FY * a, uz = -FY;
    const vf WX = sx * lx + b * ly + FX * lz, WY = sy * lx + uy * ly + FY * lz, WZ = sz * lx + uz * ly + FZ * lz;
    vf maxBeta = zero;
    vf B[4];
    for (int j = 0; j < 4; ++j) {
      const vf bj = load(beta[j]), aj = load(alb[j]), lej = load(le[j]);
      store(Ladd[j], bj * lej * emits);
      store(pend[j], bj * aj * lej * scale);
      B[j] = bj * aj;
      maxBeta = B[j] > maxBeta ? B[j] : maxBeta;
    }
    const vi roulette = D + 1 >= kRouletteDepth;
    const vf survive = roulette ? (maxBeta < one ? maxBeta : one) : one;
    const vi liveMask = scatter & ~(roulette & (rndv(id, dim + 8u) >= survive));
    for (int j = 0; j < 4; ++j) store(beta[j], roulette ? B[j] / survive : B[j]);
    store(prevPdf, lz * splat(kInvPi));
    const vf m = maxv(maxv(maxv(absv(PX), absv(PY)), absv(PZ)), splat(1e-3f));
    const vf eps = splat(1e-4f) * m + splat(1e-7f);
    const vf es = FX * ix + FY * iy + FZ * iz >= zero ? eps : -eps;
    const vf ew = FX * WX + FY * WY + FZ * WZ >= zero ? eps : -eps;
    store(sox, PX + FX * es), store(soy, PY + FY * es), store(soz, PZ + FZ * es);
    store(six, ix), store(siy, iy), store(siz, iz), store(sfar, dist * splat(0.999f));
    store(ox, PX + FX * ew), store(oy, PY + FY * ew), store(oz, PZ + FZ * ew);
    store(wx, WX), store(wy, WY), store(wz, WZ);
    storei(shadow, shadowMask), storei(live, liveMask);
  }
  for (int i = 0; i < W; ++i) {  // scatter
    shadowValid[i] = shadow[i] ? -1 : 0;
    alive[i] = live[i] != 0;
    for (int j = 0; j < 4; ++j) pending[i][j] = pend[j][i];
    sr.org_x[i] = sox[i], sr.org_y[i] = soy[i], sr.org_z[i] = soz[i];
    sr.dir_x[i] = six[i], sr.dir_y[i] = siy[i], sr.dir_z[i] = siz[i];
    sr.tnear[i] = 0.0f, sr.tfar[i] = sfar[i], sr.time[i] = 0.0f, sr.mask[i] = ~0u, sr.id[i] = 0, sr.flags[i] = 0;
    if (!hit[i]) continue;
    const uint32_t k = lane[i];
    for (int j = 0; j < 4; ++j) P.L[j][k] += Ladd[j][i];
    if (!live[i]) continue;
    for (int j = 0; j < 4; ++j) P.beta[j][k] = beta[j][i];
    P.prevPdf[k] = prevPdf[i];
    P.ox[k] = ox[i], P.oy[k] = oy[i], P.oz[k] = oz[i];
    P.dx[k] = wx[i], P.dy[k] = wy[i], P.dz[k] = wz[i];
    P.depth[k] = depth[i] + 1;
  }
}

// Traces paths [first, first + n) to the end, packets of W along an active list compacted at
// every bounce.
void tracePaths(const Scene& s, Paths& P, uint32_t first, size_t n, bool vectorShading, Result& res) {
  std::vector<uint32_t> active(n), next;
  next.reserve(n);
  for (size_t k = 0; k < n; ++k) {
    const uint32_t path = first + uint32_t(k);
    active[k] = uint32_t(k);
    P.id[k] = path;
    const Wavelengths g = color::sampleWavelengthGroup(rnd(path, 0), 4);
    for (int m = 0; m < 4; ++m) {
      const Spectrum a = reflectanceSpectrum(s.albedo[m], g);
      for (int j = 0; j < 4; ++j) P.albedo[m][j][k] = a.v[j];
    }
    const Spectrum e = illuminantSpectrum(s.emission, g);
    const CameraRay cr = s.camera->generateRay({rnd(path, 1), rnd(path, 2)}, Vec2(0.5f));
    P.ox[k] = cr.ray.origin.x, P.oy[k] = cr.ray.origin.y, P.oz[k] = cr.ray.origin.z;
    P.dx[k] = cr.ray.direction.x, P.dy[k] = cr.ray.direction.y, P.dz[k] = cr.ray.direction.z;
    for (int j = 0; j < 4; ++j) {
      P.lambda[j][k] = g.lambdaNm[size_t(j)];
      P.pdfLambda[j][k] = g.pdfLambda[size_t(j)];
      P.le[j][k] = e.v[j];
      P.beta[j][k] = 1.0f;
      P.L[j][k] = 0.0f;
    }
    P.prevPdf[k] = 0.0f;
    P.depth[k] = 0;
  }
  RTCIntersectContext ctx;
  while (!active.empty()) {
    next.clear();
    for (size_t base = 0; base < active.size(); base += W) {
      const int lanes = int(std::min<size_t>(W, active.size() - base));
      const uint32_t* lane = &active[base];
      alignas(64) int valid[W];
      alignas(64) RTCRayHit16 rh;
      for (int i = 0; i < W; ++i) {
        valid[i] = i < lanes ? -1 : 0;
        const uint32_t k = i < lanes ? lane[i] : lane[0];
        rh.ray.org_x[i] = P.ox[k], rh.ray.org_y[i] = P.oy[k], rh.ray.org_z[i] = P.oz[k];
        rh.ray.dir_x[i] = P.dx[k], rh.ray.dir_y[i] = P.dy[k], rh.ray.dir_z[i] = P.dz[k];
        rh.ray.tnear[i] = 0.0f, rh.ray.tfar[i] = INFINITY, rh.ray.time[i] = 0.0f;
        rh.ray.mask[i] = ~0u, rh.ray.id[i] = 0, rh.ray.flags[i] = 0;
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcInitIntersectContext(&ctx);
      rtcIntersect16(valid, s.scene, &ctx, &rh);
      res.rays += uint64_t(lanes);

      // Shading, next-event sample and continuation; shadow rays as one packet.
      alignas(64) int shadowValid[W];
      alignas(64) RTCRay16 sr;
      float pending[W][4];
      bool alive[W];
      if (vectorShading)
        shadePacketVector(s, P, lane, lanes, rh, sr, shadowValid, pending, alive);
      else
        shadePacketScalar(s, P, lane, lanes, rh, sr, shadowValid, pending, alive);
      bool anyShadow = false;
      for (int i = 0; i < W; ++i) anyShadow = anyShadow || shadowValid[i];
      if (anyShadow) {
        rtcInitIntersectContext(&ctx);
        rtcOccluded16(shadowValid, s.scene, &ctx, &sr);
        for (int i = 0; i < W; ++i) {
          if (!shadowValid[i]) continue;
          ++res.rays;
          if (sr.tfar[i] < 0.0f) continue;
          const uint32_t k = lane[i];
          for (int j = 0; j < 4; ++j) P.L[j][k] += pending[i][j];
        }
      }
      for (int i = 0; i < lanes; ++i) {
        const uint32_t k = lane[i];
        if (alive[i]) {
          next.push_back(k);
        } else {
          // Finished: its luminance (the film's Y).
          color::WavelengthGroup g;
          g.count = 4;
          float rad[4];
          for (int j = 0; j < 4; ++j) g.lambdaNm[size_t(j)] = P.lambda[j][k], g.pdfLambda[size_t(j)] = P.pdfLambda[j][k],
                                      rad[j] = P.L[j][k];
          res.sumY += color::radianceGroupToXyz(g, rad).y;
        }
      }
    }
    active.swap(next);
  }
}

constexpr size_t kBatch = 4096;

void BM_WavefrontCornellPaths(benchmark::State& state) {
  const Scene& s = theScene(state.range(0) != 0);
  Paths P(kBatch);
  Result res;
  uint32_t first = 0;
  uint64_t paths = 0;
  for (auto _ : state) {
    tracePaths(s, P, first, kBatch, state.range(1) != 0, res);
    first += kBatch;
    paths += kBatch;
  }
  state.SetItemsProcessed(int64_t(paths));
  state.counters["meanY"] = res.sumY / double(paths);
  state.counters["raysPerPath"] = double(res.rays) / double(paths);
}
BENCHMARK(BM_WavefrontCornellPaths)->ArgNames({"robust", "vector"})->ArgsProduct({{1, 0}, {0, 1}});

}  // namespace

BENCHMARK_MAIN();
