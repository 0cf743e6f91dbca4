// Hand-written C++ equivalents of bench/textures.tex (see native_textures.h). Written as a
// C++ programmer would write a texture library: small inline value types and functions, the
// noise octaves as plain loops (frequency and amplitude doubled and halved, which is exactly
// tex's pow(2, i) and pow(0.5, i)), unsigned 32-bit hashing (tex's Int wraps, and its
// `(x >> k) & mask` is a logical shift). Compiled with -O2 -march=native -ffp-contract=off.
#include "bench/native_textures.h"

#include <cmath>
#include <cstdint>
#include <limits>

#include "renderer/sampling/hash.h"

namespace tex::bench {
namespace {

constexpr float kTau = 6.28318530717958647692f;
constexpr float kInf = std::numeric_limits<float>::infinity();

// --- scalars: tex semantics ----------------------------------------------------------------

// C's fminf/fmaxf (the non-NaN operand wins), which tex's min/max/clamp are.
inline float fmin_(float a, float b) { return (a < b || b != b) ? a : b; }
inline float fmax_(float a, float b) { return (a > b || b != b) ? a : b; }
inline float clamp_(float x, float lo, float hi) { return fmin_(fmax_(x, lo), hi); }
inline float saturate(float x) { return clamp_(x, 0.0f, 1.0f); }
inline float mix(float a, float b, float t) { return a + (b - a) * t; }
inline float fract(float x) { return x - std::floor(x); }
inline float step(float edge, float x) { return x < edge ? 0.0f : 1.0f; }
inline float smoothstep(float e0, float e1, float x) {
  float t = clamp_((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}
inline float mod(float x, float y) { return x - y * std::floor(x / y); }

// tex's int(x): truncation, NaN -> 0, saturating at the Int range.
inline uint32_t to_int(float x) {
  if (x != x) return 0;
  if (x >= 2147483648.0f) return 0x7fffffffu;
  if (x <= -2147483648.0f) return 0x80000000u;
  return uint32_t(int32_t(x));
}

// --- small vectors --------------------------------------------------------------------------

struct V2 {
  float x, y;
};
struct V3 {
  float x, y, z;
};
inline V2 operator+(V2 a, V2 b) { return {a.x + b.x, a.y + b.y}; }
inline V2 operator-(V2 a, V2 b) { return {a.x - b.x, a.y - b.y}; }
inline V2 operator*(V2 a, V2 b) { return {a.x * b.x, a.y * b.y}; }
inline V2 operator/(V2 a, V2 b) { return {a.x / b.x, a.y / b.y}; }
inline V2 operator+(V2 a, float s) { return {a.x + s, a.y + s}; }
inline V2 operator-(V2 a, float s) { return {a.x - s, a.y - s}; }
inline V2 operator*(V2 a, float s) { return {a.x * s, a.y * s}; }
inline V2 operator*(float s, V2 a) { return {s * a.x, s * a.y}; }
inline V2 floor(V2 a) { return {std::floor(a.x), std::floor(a.y)}; }
inline float dot(V2 a, V2 b) { return a.x * b.x + a.y * b.y; }

inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator*(V3 a, V3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline V3 operator+(V3 a, float s) { return {a.x + s, a.y + s, a.z + s}; }
inline V3 operator-(V3 a, float s) { return {a.x - s, a.y - s, a.z - s}; }
inline V3 operator*(V3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline V3 operator*(float s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline V3 floor(V3 a) { return {std::floor(a.x), std::floor(a.y), std::floor(a.z)}; }
inline float dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float length(V3 a) { return std::sqrt(dot(a, a)); }
inline V3 normalize(V3 a) {
  float len = length(a);
  return len > 0.0f ? V3{a.x / len, a.y / len, a.z / len} : V3{0.0f, 0.0f, 0.0f};
}
inline V3 mix(V3 a, V3 b, float t) { return {mix(a.x, b.x, t), mix(a.y, b.y, t), mix(a.z, b.z, t)}; }

using Rgb = V3;
inline void store(Rgb c, float* out) {
  out[0] = c.x;
  out[1] = c.y;
  out[2] = c.z;
}
inline V3 hitP(const HitAbi& h) { return {h.p[0], h.p[1], h.p[2]}; }
inline V2 hitUv(const HitAbi& h) { return {h.uv[0], h.uv[1]}; }

// --- std.math hashes ------------------------------------------------------------------------

// std.math's hash is lowbias32.
inline uint32_t hash(uint32_t x) { return sampling::lowbias32(x); }
inline uint32_t hash2i(uint32_t x, uint32_t y, uint32_t seed = 0) {
  return hash(x * 0x1b873593u + y * 0x5bd1e995u + seed * 0x27d4eb2du + 0x165667b1u);
}
inline uint32_t hash3i(uint32_t x, uint32_t y, uint32_t z, uint32_t seed = 0) {
  return hash(x * 0x1b873593u + y * 0x5bd1e995u + z * 0x68e31da5u + seed * 0x27d4eb2du + 0x165667b1u);
}
inline float unit_float(uint32_t h) { return float(h >> 8) * (1.0f / 16777216.0f); }
inline V2 hash22(V2 p) {
  uint32_t h = hash2i(to_int(std::floor(p.x)), to_int(std::floor(p.y)));
  return {unit_float(h), unit_float(hash(h + 0x632be5abu))};
}
inline V3 hash23(V2 p) {
  uint32_t h = hash2i(to_int(std::floor(p.x)), to_int(std::floor(p.y)));
  uint32_t h2 = hash(h + 0x632be5abu);
  return {unit_float(h), unit_float(h2), unit_float(hash(h2 + 0x632be5abu))};
}
inline V3 hash33(V3 p) {
  uint32_t h = hash3i(to_int(std::floor(p.x)), to_int(std::floor(p.y)), to_int(std::floor(p.z)));
  uint32_t h2 = hash(h + 0x632be5abu);
  return {unit_float(h), unit_float(h2), unit_float(hash(h2 + 0x632be5abu))};
}

// --- std.noise ------------------------------------------------------------------------------

inline float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
inline float cubic(float t) { return t * t * (3.0f - 2.0f * t); }

// Improved-Perlin gradients as coefficient tables (-1, 0, 1), so the selection is branch-free
// (GCC turns the reference's ternaries into unpredictable branches). gx*x + gy*y + gz*z equals
// the reference's (+-u) + (+-v) exactly: the zero term adds nothing (up to the sign of a zero)
// and float addition is commutative.
//   g:   0  1  2  3  4  5  6  7  8  9 10 11 12 13 14 15
//   u:   x  x  x  x  x  x  x  x  y  y  y  y  y  y  y  y
//   v:   y  y  y  y  z  z  z  z  z  z  z  z  x  z  x  z
constexpr float kG3x[16] = {1, -1, 1, -1, 1, -1, 1, -1, 0, 0, 0, 0, 1, 0, -1, 0};
constexpr float kG3y[16] = {1, 1, -1, -1, 0, 0, 0, 0, 1, -1, 1, -1, 1, -1, 1, -1};
constexpr float kG3z[16] = {0, 0, 0, 0, 1, 1, -1, -1, 1, 1, -1, -1, 0, 1, 0, -1};
inline float grad3(uint32_t h, float x, float y, float z) {
  uint32_t g = h & 15;
  return kG3x[g] * x + kG3y[g] * y + kG3z[g] * z;
}

// 2-D: (+-1, +-2) and (+-2, +-1) by the low 3 bits, likewise as tables.
//   g:   0  1  2  3  4  5  6  7
//   u:   x  x  x  x  y  y  y  y   (sign from bit 0)
//   v:  2y 2y 2y 2y 2x 2x 2x 2x   (sign from bit 1)
constexpr float kG2x[8] = {1, -1, 1, -1, 2, 2, -2, -2};
constexpr float kG2y[8] = {2, 2, -2, -2, 1, -1, 1, -1};
inline float grad2(uint32_t h, float x, float y) {
  uint32_t g = h & 7;
  return kG2x[g] * x + kG2y[g] * y;
}

inline float perlin(V3 p) {
  V3 i = floor(p);
  V3 f = p - i;
  uint32_t x = to_int(i.x), y = to_int(i.y), z = to_int(i.z);
  float ux = fade(f.x), uy = fade(f.y), uz = fade(f.z);
  float n000 = grad3(hash3i(x, y, z), f.x, f.y, f.z);
  float n100 = grad3(hash3i(x + 1, y, z), f.x - 1.0f, f.y, f.z);
  float n010 = grad3(hash3i(x, y + 1, z), f.x, f.y - 1.0f, f.z);
  float n110 = grad3(hash3i(x + 1, y + 1, z), f.x - 1.0f, f.y - 1.0f, f.z);
  float n001 = grad3(hash3i(x, y, z + 1), f.x, f.y, f.z - 1.0f);
  float n101 = grad3(hash3i(x + 1, y, z + 1), f.x - 1.0f, f.y, f.z - 1.0f);
  float n011 = grad3(hash3i(x, y + 1, z + 1), f.x, f.y - 1.0f, f.z - 1.0f);
  float n111 = grad3(hash3i(x + 1, y + 1, z + 1), f.x - 1.0f, f.y - 1.0f, f.z - 1.0f);
  float nx00 = mix(n000, n100, ux);
  float nx10 = mix(n010, n110, ux);
  float nx01 = mix(n001, n101, ux);
  float nx11 = mix(n011, n111, ux);
  return mix(mix(nx00, nx10, uy), mix(nx01, nx11, uy), uz);
}

inline float perlin2(V2 p) {
  V2 i = floor(p);
  V2 f = p - i;
  uint32_t x = to_int(i.x), y = to_int(i.y);
  float ux = fade(f.x), uy = fade(f.y);
  float n00 = grad2(hash2i(x, y), f.x, f.y);
  float n10 = grad2(hash2i(x + 1, y), f.x - 1.0f, f.y);
  float n01 = grad2(hash2i(x, y + 1), f.x, f.y - 1.0f);
  float n11 = grad2(hash2i(x + 1, y + 1), f.x - 1.0f, f.y - 1.0f);
  return 0.66f * mix(mix(n00, n10, ux), mix(n01, n11, ux), uy);
}

inline float value_noise(V3 p) {
  V3 i = floor(p);
  V3 f = p - i;
  uint32_t x = to_int(i.x), y = to_int(i.y), z = to_int(i.z);
  float ux = cubic(f.x), uy = cubic(f.y), uz = cubic(f.z);
  float v000 = unit_float(hash3i(x, y, z, 7));
  float v100 = unit_float(hash3i(x + 1, y, z, 7));
  float v010 = unit_float(hash3i(x, y + 1, z, 7));
  float v110 = unit_float(hash3i(x + 1, y + 1, z, 7));
  float v001 = unit_float(hash3i(x, y, z + 1, 7));
  float v101 = unit_float(hash3i(x + 1, y, z + 1, 7));
  float v011 = unit_float(hash3i(x, y + 1, z + 1, 7));
  float v111 = unit_float(hash3i(x + 1, y + 1, z + 1, 7));
  float v = mix(mix(mix(v000, v100, ux), mix(v010, v110, ux), uy),
                mix(mix(v001, v101, ux), mix(v011, v111, ux), uy), uz);
  return 2.0f * v - 1.0f;
}

// Worley F1 over the 27 neighbouring cells (jitter 1).
inline float worley(V3 p) {
  V3 c = floor(p);
  float best = kInf;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        V3 cell = c + V3{float(dx), float(dy), float(dz)};
        V3 q = cell + 0.5f + (hash33(cell) - 0.5f);
        V3 d = q - p;
        best = fmin_(best, dot(d, d));
      }
  return std::sqrt(best);
}

// Worley F2 - F1 in 2-D (jitter 1).
inline float worley_edge2(V2 p) {
  V2 c = floor(p);
  float f1 = kInf, f2 = kInf;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      V2 cell = c + V2{float(dx), float(dy)};
      V2 q = cell + 0.5f + (hash22(cell) - 0.5f);
      V2 d = q - p;
      float e = dot(d, d);
      if (e < f1) {
        f2 = f1;
        f1 = e;
      } else if (e < f2) {
        f2 = e;
      }
    }
  return std::sqrt(f2) - std::sqrt(f1);
}

// Fractal sum: octave i samples noise at p * 2^i with weight 0.5^i.
template <class Noise>
inline float fbm(int octaves, Noise noise, V3 p) {
  float sum = 0.0f, freq = 1.0f, amp = 1.0f;
  for (int i = 0; i < octaves; ++i) {
    sum += noise(p * freq) * amp;
    freq *= 2.0f;
    amp *= 0.5f;
  }
  return sum;
}
template <class Noise>
inline float fbm2(int octaves, Noise noise, V2 p) {
  float sum = 0.0f, freq = 1.0f, amp = 1.0f;
  for (int i = 0; i < octaves; ++i) {
    sum += noise(p * freq) * amp;
    freq *= 2.0f;
    amp *= 0.5f;
  }
  return sum;
}
inline float fbm_perlin(int octaves, V3 p) { return fbm(octaves, [](V3 q) { return perlin(q); }, p); }

// --- std.patterns ---------------------------------------------------------------------------

struct Brick {
  float mortar;
  V2 id;
};
inline Brick brick(V2 uv, V2 size, float mortar, float offset) {
  V2 s = uv / size;
  float row = std::floor(s.y);
  float x = s.x + offset * row;
  V2 f{fract(x), s.y - row};
  V2 e{fmin_(f.x, 1.0f - f.x) * size.x, fmin_(f.y, 1.0f - f.y) * size.y};
  return {1.0f - step(0.5f * mortar, fmin_(e.x, e.y)), {std::floor(x), row}};
}

inline float checker(V2 uv, float n) {
  V2 c = floor(uv * n);
  return mod(c.x + c.y, 2.0f);
}

// --- spectra --------------------------------------------------------------------------------

inline float planck(float l, float t) {
  return 1.191042972e-16f / (l * l * l * l * l * (std::exp(0.01438776877f / (l * t)) - 1.0f));
}

template <int N>
void blackbody(const HitAbi& h, const float* lambda, float* out) {
  float t = 1200.0f + 1800.0f * saturate(0.5f + 0.6f * fbm_perlin(4, hitP(h) * 3.0f));
  float peak = 0.002897771955f / t;
  float norm = planck(peak, t);
  for (int i = 0; i < N; ++i) out[i] = planck(lambda[i] * 1.0e-9f, t) / norm;
}

template <int N>
void thin_film(const HitAbi& h, const float* lambda, float* out) {
  float d = 400.0f + 200.0f * perlin(hitP(h) * 4.0f);
  float k = kTau * 2.0f * 1.33f * d;
  for (int i = 0; i < N; ++i) out[i] = 0.5f + 0.5f * std::cos(k / lambda[i]);
}

template <int N>
void ior_cauchy(const HitAbi&, const float* lambda, float* out) {
  for (int i = 0; i < N; ++i) out[i] = 1.5046f + 4200.0f / (lambda[i] * lambda[i]);
}

}  // namespace

// --- the textures ---------------------------------------------------------------------------

void native_perlin_tex(const HitAbi& h, const float*, float* out) { out[0] = perlin(hitP(h) * 8.0f); }

void native_fbm_tex(const HitAbi& h, const float*, float* out) { out[0] = fbm_perlin(6, hitP(h) * 4.0f); }

void native_value_tex(const HitAbi& h, const float*, float* out) {
  out[0] = 0.5f + 0.5f * fbm(4, [](V3 q) { return value_noise(q); }, hitP(h) * 8.0f);
}

void native_worley_tex(const HitAbi& h, const float*, float* out) { out[0] = worley(hitP(h) * 6.0f); }

void native_marble(const HitAbi& h, const float*, float* out) {
  V3 hp = hitP(h);
  V3 p = hp * 2.0f;
  float x = (hp.x + 0.5f * hp.y) * 10.0f + 2.5f * fbm_perlin(6, p);
  float s = 1.0f - std::fabs(std::sin(x));
  float vein = std::pow(s, 16.0f);
  float halo = s * s * s;
  float fine = std::pow(1.0f - std::fabs(std::sin(2.3f * x + 1.5f * fbm_perlin(4, p * 2.0f + 5.0f))), 40.0f);
  float cloud = fbm_perlin(4, p * 1.5f + V3{3.1f, 7.2f, 1.3f});
  Rgb ground = mix(Rgb{0.93f, 0.91f, 0.87f}, Rgb{0.80f, 0.78f, 0.74f}, saturate(0.5f + 0.8f * cloud));
  Rgb c1 = mix(ground, Rgb{0.62f, 0.60f, 0.58f}, 0.3f * halo);
  Rgb c2 = mix(c1, Rgb{0.45f, 0.43f, 0.42f}, 0.5f * fine);
  store(mix(c2, Rgb{0.25f, 0.24f, 0.24f}, vein), out);
}

void native_marble_classic(const HitAbi& h, const float*, float* out) {
  V3 hp = hitP(h);
  float t = fbm(6, [](V3 q) { return std::fabs(perlin(q)); }, hp * 4.0f);
  const float n = 1.0f / kTau;
  float stripes = 0.5f + 0.5f * std::cos(kTau * n * (hp.x + 8.0f * t));
  store(mix(Rgb{0.92f, 0.90f, 0.85f}, Rgb{0.35f, 0.32f, 0.30f}, stripes), out);
}

void native_wood(const HitAbi& h, const float*, float* out) {
  V3 q = hitP(h);
  V3 p = q + V3{0.0f, 0.02f * fbm_perlin(3, q * V3{1.5f, 6.0f, 6.0f}), 0.0f};
  // distance from p to the log's axis
  V3 d = p - V3{0.0f, 0.35f, -0.25f};
  V3 k = normalize(V3{1.0f, 0.12f, 0.2f});
  float r = length(d - k * dot(d, k)) + 0.03f * fbm_perlin(4, q * V3{2.0f, 8.0f, 8.0f} + V3{2.0f, 4.0f, 1.0f});
  float f = fract(r * 18.0f);
  float late = smoothstep(0.55f, 0.95f, f) * (1.0f - smoothstep(0.95f, 1.0f, f));
  float grain = fbm_perlin(3, q * V3{3.0f, 120.0f, 120.0f});
  Rgb c = mix(Rgb{0.62f, 0.40f, 0.22f}, Rgb{0.36f, 0.20f, 0.09f}, saturate(late + 0.25f * grain));
  store(c * (0.9f + 0.2f * fbm_perlin(3, q * V3{1.0f, 30.0f, 30.0f})), out);
}

void native_bricks_tex(const HitAbi& h, const float*, float* out) {
  V2 uv = hitUv(h);
  V2 size{0.25f, 0.0833f};
  Brick b = brick(uv, size, 0.012f, 0.5f);
  V2 uv40 = uv * 40.0f;
  float grit = fbm_perlin(4, V3{uv40.x, uv40.y, 0.0f});
  // per-brick tint (std.patterns.brick_color with variation 0.25)
  const float variation = 0.25f;
  V3 r = hash23(b.id + V2{17.0f, 31.0f});
  float k = 1.0f + variation * (2.0f * r.x - 1.0f);
  float a = 0.25f * variation;
  Rgb tint{1.0f + a * (2.0f * r.y - 1.0f), 1.0f + a * (2.0f * r.z - 1.0f), 1.0f + a * (2.0f * (1.0f - r.y) - 1.0f)};
  Rgb face = Rgb{0.50f, 0.20f, 0.12f} * k * tint * (0.9f + 0.15f * grit);
  Rgb mortar = Rgb{0.70f, 0.68f, 0.64f} * (0.92f + 0.1f * grit);
  store(mix(face, mortar, b.mortar), out);
}

void native_checker_tex(const HitAbi& h, const float*, float* out) {
  store(mix(Rgb{0.8f, 0.8f, 0.8f}, Rgb{0.05f, 0.05f, 0.05f}, checker(hitUv(h), 8.0f)), out);
}

void native_cells_tex(const HitAbi& h, const float*, float* out) {
  V2 uv = hitUv(h);
  auto p2 = [](V2 q) { return perlin2(q); };
  V2 warp{fbm2(3, p2, uv * 5.0f), fbm2(3, p2, uv * 5.0f + 7.3f)};
  V2 q = uv * 6.0f + 0.15f * warp;
  float d = worley_edge2(q);
  float shade = 0.85f + 0.3f * fbm_perlin(4, hitP(h) * 10.0f);
  store(mix(Rgb{0.15f, 0.13f, 0.12f}, Rgb{0.70f, 0.66f, 0.58f} * shade, smoothstep(0.02f, 0.08f, d)), out);
}

void native_ior_cauchy(const HitAbi& h, const float* lambda, float* out) { ior_cauchy<4>(h, lambda, out); }
void native_blackbody(const HitAbi& h, const float* lambda, float* out) { blackbody<4>(h, lambda, out); }
void native_thin_film(const HitAbi& h, const float* lambda, float* out) { thin_film<4>(h, lambda, out); }

const NativeTexture* nativeTextures(int& count) {
  static const NativeTexture table[] = {
      {"perlin_tex", native_perlin_tex, nullptr, 1, false},
      {"fbm_tex", native_fbm_tex, nullptr, 1, false},
      {"value_tex", native_value_tex, nullptr, 1, false},
      {"worley_tex", native_worley_tex, nullptr, 1, false},
      {"marble", native_marble, nullptr, 3, false},
      {"marble_classic", native_marble_classic, nullptr, 3, false},
      {"wood", native_wood, nullptr, 3, false},
      {"bricks_tex", native_bricks_tex, nullptr, 3, false},
      {"checker_tex", native_checker_tex, nullptr, 3, false},
      {"cells_tex", native_cells_tex, nullptr, 3, false},
      {"ior_cauchy", native_ior_cauchy, ior_cauchy<1>, 4, true},
      {"blackbody", native_blackbody, blackbody<1>, 4, true},
      {"thin_film", native_thin_film, thin_film<1>, 4, true},
  };
  count = int(sizeof(table) / sizeof(table[0]));
  return table;
}

}  // namespace tex::bench
