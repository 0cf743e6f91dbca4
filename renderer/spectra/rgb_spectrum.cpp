#include <cstring>
#include "renderer/spectra/rgb_spectrum.h"

#include "lang/rgb_upsampling.h"

#include <emmintrin.h>

#include <algorithm>
#include <cmath>

#include "renderer/color/cie_tables.h"
#include "renderer/color/color.h"
#include "renderer/spectra/rgb_table.h"

namespace tex::render {

namespace {

float sigmoid(float x) {
  // Beyond 1e18 x*x overflows; the limits are exact 0 and 1 (black and white use +-inf).
  if (std::abs(x) > 1e18f) return x > 0.0f ? 1.0f : 0.0f;
  return 0.5f + 0.5f * x / std::sqrt(1.0f + x * x);
}

float sanitise(float v) { return std::isnan(v) ? 0.0f : v; }

// The flat spectrum of value v in [0,1]: sigmoid(c2) = v for c2 = (v - 1/2) / sqrt(v (1 - v)).
SigmoidPolynomial flat(float v) {
  SigmoidPolynomial p;
  if (v <= 0.0f) {
    p.c2 = -INFINITY;
  } else if (v >= 1.0f) {
    p.c2 = INFINITY;
  } else {
    p.c2 = float((double(v) - 0.5) / std::sqrt(double(v) * (1.0 - double(v))));
  }
  return p;
}

}  // namespace

float SigmoidPolynomial::operator()(float lambdaNm) const {
  return sigmoid((c0 * lambdaNm + c1) * lambdaNm + c2);  // (std::fma is a libm call without -mfma)
}

float SigmoidPolynomial::maxValue() const {
  // The sigmoid is increasing, so the maximum is the quadratic's: at an end or at its vertex.
  float m = std::max((*this)(360.0f), (*this)(830.0f));
  if (c0 != 0.0f) {
    const float vertexNm = -c1 / (2.0f * c0);
    if (vertexNm > 360.0f && vertexNm < 830.0f) m = std::max(m, (*this)(vertexNm));
  }
  return m;
}

namespace {
SigmoidPolynomial rgbToSigmoidUncached(const Vec3& rgbIn);
}  // namespace

// Materials ask for the same few colours at every hit (constant base colours, folded .tex
// constants), and the table lookup costs three binary searches and 24 scattered reads: a small
// per-thread direct-mapped cache keyed by the exact bits of the colour answers most of them.
SigmoidPolynomial rgbToSigmoid(const Vec3& rgb) {
  struct Entry {
    uint32_t key[3];
    SigmoidPolynomial value;
    bool valid;
  };
  thread_local Entry cache[64] = {};
  uint32_t k[3];
  std::memcpy(k, &rgb, sizeof k);
  const uint32_t slot = ((k[0] * 0x9E3779B1u) ^ (k[1] * 0x85EBCA77u) ^ (k[2] * 0xC2B2AE3Du)) >> 26;
  Entry& e = cache[slot];
  if (e.valid && e.key[0] == k[0] && e.key[1] == k[1] && e.key[2] == k[2]) return e.value;
  const SigmoidPolynomial value = rgbToSigmoidUncached(rgb);
  e = {{k[0], k[1], k[2]}, value, true};
  return value;
}

namespace {
SigmoidPolynomial rgbToSigmoidUncached(const Vec3& rgbIn) {
  const float rgb[3] = {std::clamp(sanitise(rgbIn.x), 0.0f, 1.0f), std::clamp(sanitise(rgbIn.y), 0.0f, 1.0f),
                        std::clamp(sanitise(rgbIn.z), 0.0f, 1.0f)};
  if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) return flat(rgb[0]);

  const RgbSigmoidTable& table = rgbSigmoidTable();
  const int res = table.resolution;
  const int largest = rgb[0] > rgb[1] ? (rgb[0] > rgb[2] ? 0 : 2) : (rgb[1] > rgb[2] ? 1 : 2);
  const float z = rgb[largest];  // > 0: not all equal
  const float x = rgb[(largest + 1) % 3] / z, y = rgb[(largest + 2) % 3] / z;
  // Cell and fraction along one axis: nodes[i] <= v < nodes[i + 1] (the last cell includes 1).
  const auto locate = [res](const float* nodes, float v, int& i, float& f) {
    i = int(std::upper_bound(nodes + 1, nodes + res - 1, v) - nodes) - 1;
    f = (v - nodes[i]) / (nodes[i + 1] - nodes[i]);
  };
  int xi, yi, zi;
  float dx, dy, dz;
  locate(table.xyNodes, x, xi, dx);
  locate(table.xyNodes, y, yi, dy);
  locate(table.zNodes, z, zi, dz);

  // Trilinear interpolation of the coefficients.
  float c[3] = {0, 0, 0};
  for (int corner = 0; corner < 8; ++corner) {
    const int ox = corner & 1, oy = (corner >> 1) & 1, oz = corner >> 2;
    const float w = (ox ? dx : 1.0f - dx) * (oy ? dy : 1.0f - dy) * (oz ? dz : 1.0f - dz);
    const float* cell = table.cell(largest, zi + oz, yi + oy, xi + ox);
    c[0] += w * cell[0], c[1] += w * cell[1], c[2] += w * cell[2];
  }
  return {c[0], c[1], c[2]};
}

}  // namespace

RgbUnbounded rgbToUnbounded(const Vec3& rgbIn) {
  // As pbrt-v4's RGBUnboundedSpectrum: the shape's largest component is 1/2, leaving the
  // fitted spectrum room above and below.
  const Vec3 rgb(std::max(sanitise(rgbIn.x), 0.0f), std::max(sanitise(rgbIn.y), 0.0f),
                 std::max(sanitise(rgbIn.z), 0.0f));
  const float m = std::max({rgb.x, rgb.y, rgb.z});
  if (!(m > 0.0f) || !std::isfinite(m)) return {};
  const float scale = 2.0f * m;
  return {rgbToSigmoid(rgb / scale), scale};
}

namespace {

// Four values of the sigmoid polynomial at once, with the scalar operator()'s operations in its
// order (SSE2's sqrt and division round like the scalar ones, and x86-64 has no FMA to
// contract into): the same bits.
__m128 sigmoidPolynomial4(const SigmoidPolynomial& s, __m128 lambdaNm) {
  const __m128 half = _mm_set1_ps(0.5f), one = _mm_set1_ps(1.0f);
  const __m128 x = _mm_add_ps(
      _mm_mul_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(s.c0), lambdaNm), _mm_set1_ps(s.c1)), lambdaNm), _mm_set1_ps(s.c2));
  const __m128 y = _mm_add_ps(half, _mm_div_ps(_mm_mul_ps(half, x), _mm_sqrt_ps(_mm_add_ps(one, _mm_mul_ps(x, x)))));
  // sigmoid()'s exact limits beyond |x| = 1e18 (NaN compares false there too, and stays NaN).
  const __m128 beyond = _mm_cmpgt_ps(_mm_andnot_ps(_mm_set1_ps(-0.0f), x), _mm_set1_ps(1e18f));
  const __m128 limit = _mm_and_ps(_mm_cmpgt_ps(x, _mm_setzero_ps()), one);
  return _mm_or_ps(_mm_and_ps(beyond, limit), _mm_andnot_ps(beyond, y));
}

// scale * shape(lambda), times d65Normalised(lambda) for an illuminant, at the group's
// wavelengths (lanes past the group's count zero; scale 1 multiplies exactly). Four lanes are
// one vector store: the callers' vector loads of four scalar stores stalled on store forwarding.
Spectrum sigmoidSpectrum(const SigmoidPolynomial& shape, float scale, bool illuminant, const Wavelengths& lambda) {
  Spectrum s;
  for (int i = 0; i < lambda.count; i += 4) {
    const float* l = &lambda.lambdaNm[size_t(i)];
    __m128 v = _mm_mul_ps(_mm_set1_ps(scale), sigmoidPolynomial4(shape, _mm_loadu_ps(l)));
    if (illuminant)
      v = _mm_mul_ps(v, _mm_setr_ps(d65Normalised(l[0]), d65Normalised(l[1]), d65Normalised(l[2]), d65Normalised(l[3])));
    _mm_store_ps(&s.v[i], v);
  }
  if (lambda.count % 4 != 0)
    for (int i = lambda.count; i < kLanes; ++i) s.v[i] = 0.0f;
  return s;
}

}  // namespace

Spectrum reflectanceSpectrum(const SigmoidPolynomial& shape, const Wavelengths& lambda) {
  return sigmoidSpectrum(shape, 1.0f, false, lambda);
}

Spectrum unboundedSpectrum(const RgbUnbounded& fitted, const Wavelengths& lambda) {
  return sigmoidSpectrum(fitted.shape, fitted.scale, false, lambda);
}

Spectrum illuminantSpectrum(const RgbUnbounded& fitted, const Wavelengths& lambda) {
  return sigmoidSpectrum(fitted.shape, fitted.scale, true, lambda);
}

Spectrum rgbReflectanceSpectrum(const Vec3& rgb, const Wavelengths& lambda) {
  return reflectanceSpectrum(rgbToSigmoid(rgb), lambda);
}

Spectrum rgbUnboundedSpectrum(const Vec3& rgb, const Wavelengths& lambda) {
  return unboundedSpectrum(rgbToUnbounded(rgb), lambda);
}

Spectrum rgbIlluminantSpectrum(const Vec3& rgb, const Wavelengths& lambda) {
  return illuminantSpectrum(rgbToUnbounded(rgb), lambda);
}

float rgbReflectanceAt(const Vec3& rgb, float lambdaNm) { return rgbToSigmoid(rgb)(lambdaNm); }

float rgbUnboundedAt(const Vec3& rgb, float lambdaNm) { return rgbToUnbounded(rgb)(lambdaNm); }

float rgbIlluminantAt(const Vec3& rgb, float lambdaNm) {
  return rgbToUnbounded(rgb)(lambdaNm) * d65Normalised(lambdaNm);
}

float d65Normalised(float lambdaNm) {
  // Y = integral(L ybar) / integral(ybar) = 1 with the 1 nm quadrature of color/spectral_to_rgb.
  static const float scale = [] {
    double y = 0;
    for (int i = 0; i < color::kCieSampleCount; ++i)
      y += double(color::kCie1931Y[i]) * color::d65RelativePower(float(color::kCieLambdaMinNm + i));
    return float(color::kCie1931YIntegralNm / y);
  }();
  return color::d65RelativePower(lambdaNm) * scale;
}

float blackbodyNormalised(float lambdaNm, float kelvin) {
  if (!(kelvin > 0.0f) || !(lambdaNm > 0.0f)) return 0.0f;
  // Planck's law; the constant 2 h c^2 cancels in the ratio to the peak (Wien's displacement
  // law: lambdaMax = b / T, b = 2.897771955e-3 m K, CODATA 2018).
  constexpr double kHcOverK = 1.438776877e-2;  // second radiation constant h c / k_B, m K
  constexpr double kWienB = 2.897771955e-3;
  const auto planckShape = [&](double lambdaM) {
    return 1.0 / (std::pow(lambdaM, 5.0) * std::expm1(kHcOverK / (lambdaM * kelvin)));
  };
  const double peak = planckShape(kWienB / kelvin);
  const double value = planckShape(double(lambdaNm) * 1e-9);
  return std::isfinite(value) ? float(value / peak) : 0.0f;
}

namespace {
void languageUpsampling(lang::RgbUse use, const float rgb[3], const float* lambdaNm, int count, float* out) {
  // The colour's coefficients once for all wavelengths (rgb*At would look them up per wavelength).
  const Vec3 c(rgb[0], rgb[1], rgb[2]);
  if (use == lang::RgbUse::Reflectance) {
    const SigmoidPolynomial s = rgbToSigmoid(c);
    for (int i = 0; i < count; ++i) out[i] = s(lambdaNm[i]);
    return;
  }
  const RgbUnbounded u = rgbToUnbounded(c);
  for (int i = 0; i < count; ++i)
    out[i] = use == lang::RgbUse::Illuminant ? u(lambdaNm[i]) * d65Normalised(lambdaNm[i]) : u(lambdaNm[i]);
}
const bool kInstalledAtStartUp = (lang::setRgbToSpectrum(&languageUpsampling), true);
}  // namespace

void installRgbUpsampling() {
  (void)kInstalledAtStartUp;
  lang::setRgbToSpectrum(&languageUpsampling);
}

}  // namespace tex::render
