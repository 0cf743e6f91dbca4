// Spectral values carried by a path: one float per wavelength of the path's group (4 or 8,
// color::WavelengthGroup). Always 8 lanes wide so that arithmetic is one AVX register and the
// code is the same for both group sizes; lanes beyond the group's count are zero.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "renderer/color/wavelengths.h"

namespace tex::render {

using Wavelengths = color::WavelengthGroup;
inline constexpr int kLanes = color::kMaxWavelengths;

struct Spectrum {
  alignas(32) float v[kLanes];

  Spectrum() : v{} {}
  explicit Spectrum(float c) {
    for (float& x : v) x = c;
  }
  float& operator[](int i) { return v[i]; }
  float operator[](int i) const { return v[i]; }

#define TEX_SPECTRUM_OP(op)                                           \
  Spectrum& operator op##=(const Spectrum& o) {                       \
    for (int i = 0; i < kLanes; ++i) v[i] op## = o.v[i];              \
    return *this;                                                     \
  }                                                                   \
  Spectrum& operator op##=(float s) {                                 \
    for (int i = 0; i < kLanes; ++i) v[i] op## = s;                   \
    return *this;                                                     \
  }                                                                   \
  friend Spectrum operator op(Spectrum a, const Spectrum& b) { return a op## = b; } \
  friend Spectrum operator op(Spectrum a, float s) { return a op## = s; }
  TEX_SPECTRUM_OP(+)
  TEX_SPECTRUM_OP(-)
  TEX_SPECTRUM_OP(*)
#undef TEX_SPECTRUM_OP
  friend Spectrum operator*(float s, Spectrum a) { return a *= s; }
  // Division with 0/0 = 0 lane by lane (unused lanes stay zero; a zero pdf means "no sample").
  friend Spectrum safeDiv(const Spectrum& a, const Spectrum& b) {
    Spectrum r;
    for (int i = 0; i < kLanes; ++i) r.v[i] = b.v[i] != 0.0f ? a.v[i] / b.v[i] : 0.0f;
    return r;
  }
  Spectrum operator/(float s) const {
    Spectrum r = *this;
    const float inv = s != 0.0f ? 1.0f / s : 0.0f;
    return r *= inv;
  }

  // Both tests compare all lanes packed (SSE2: two compares and a movemask) instead of a
  // branch per lane: they are asked several times per path vertex.
  bool isBlack() const {
#if defined(__SSE2__)
    const __m128 zero = _mm_setzero_ps();  // cmpneq is true for NaN too, as x != 0 is
    const __m128 nonZero = _mm_or_ps(_mm_cmpneq_ps(_mm_load_ps(v), zero), _mm_cmpneq_ps(_mm_load_ps(v + 4), zero));
    return _mm_movemask_ps(nonZero) == 0;
#else
    for (float x : v)
      if (x != 0.0f) return false;
    return true;
#endif
  }
  // Lanes 4-7 all zero (a NaN lane is not): a group of 4 wavelengths, whose per-lane loops may
  // stop at lane 4.
  bool upperLanesZero() const {
#if defined(__SSE2__)
    return _mm_movemask_ps(_mm_cmpneq_ps(_mm_load_ps(v + 4), _mm_setzero_ps())) == 0;
#else
    return v[4] == 0.0f && v[5] == 0.0f && v[6] == 0.0f && v[7] == 0.0f;
#endif
  }
  float maxValue() const {
    float m = v[0];
    for (float x : v) m = std::max(m, x);
    return m;
  }
  // Mean over the first `count` lanes.
  float average(int count) const {
    float s = 0.0f;
    for (int i = 0; i < count; ++i) s += v[i];
    return count > 0 ? s / float(count) : 0.0f;
  }
  bool hasNaNOrInf() const {
#if defined(__SSE2__)
    // |x| <= FLT_MAX is false exactly for NaN and infinities.
    const __m128 signMask = _mm_set1_ps(-0.0f), maxFinite = _mm_set1_ps(std::numeric_limits<float>::max());
    const __m128 finiteLo = _mm_cmple_ps(_mm_andnot_ps(signMask, _mm_load_ps(v)), maxFinite);
    const __m128 finiteHi = _mm_cmple_ps(_mm_andnot_ps(signMask, _mm_load_ps(v + 4)), maxFinite);
    return _mm_movemask_ps(_mm_and_ps(finiteLo, finiteHi)) != 0xF;
#else
    for (float x : v)
      if (!std::isfinite(x)) return true;
    return false;
#endif
  }
};

inline Spectrum exp(const Spectrum& a) {
  Spectrum r;
  for (int i = 0; i < kLanes; ++i) r.v[i] = std::exp(a.v[i]);
  return r;
}
inline Spectrum clampZero(const Spectrum& a) {
  Spectrum r;
  for (int i = 0; i < kLanes; ++i) r.v[i] = std::max(a.v[i], 0.0f);
  return r;
}

// Evaluates f(lambdaNm) at each wavelength of the group (lanes past count stay zero).
template <class F>
Spectrum sampleSpectrum(const Wavelengths& lambda, F&& f) {
  Spectrum s;
  for (int i = 0; i < lambda.count; ++i) s.v[i] = f(lambda.lambdaNm[i]);
  return s;
}

}  // namespace tex::render
