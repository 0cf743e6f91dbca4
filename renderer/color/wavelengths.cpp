#include "renderer/color/wavelengths.h"

#include <emmintrin.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace tex::color {

namespace {
constexpr double kA = 0.0072;     // per nm
constexpr double kCentreNm = 538.0;
const double kTanhLow = std::tanh(kA * (kCentreNm - kVisibleLambdaMinNm));   // 0.85691
const double kTanhHigh = std::tanh(kA * (kVisibleLambdaMaxNm - kCentreNm));  // 0.97059
const double kTanhSpan = kTanhLow + kTanhHigh;                               // 1.82750
constexpr double kNmPerLog = 0.5 / kA;  // lambda = 538 - log((1 + t) / (1 - t)) / (2 a)

// j / n for a group of n wavelengths, lane j (u_j = frac(u + j / n)): constant-folded, so the
// same floats as the division, which began every group's chain of dependent operations.
constexpr auto kLaneOffsets = [] {
  std::array<std::array<float, kMaxWavelengths>, kMaxWavelengths + 1> offsets{};
  for (int n = 1; n <= kMaxWavelengths; ++n)
    for (int j = 0; j < kMaxWavelengths; ++j) offsets[size_t(n)][size_t(j)] = float(j) / float(n);
  return offsets;
}();

// Natural logs of four positive normal floats, all at once (a path's four wavelengths took
// four calls of glibc's double log): Cephes' logf, x = m 2^e with m in [sqrt(1/2), sqrt(2)),
// log m by a polynomial in m - 1, ln 2 in two parts. On the ratios (1 + t) / (1 - t) of
// every float u in [0, 1) its error, with the ratio's rounding to float, is < 3e-7, and the
// wavelength differs from the double formula's by at most one float ulp (3 % of u's differ).
__m128 log4(__m128 x) {
  const __m128 one = _mm_set1_ps(1.0f);
  const __m128i bits = _mm_castps_si128(x);
  __m128i e = _mm_sub_epi32(_mm_srli_epi32(bits, 23), _mm_set1_epi32(126));  // x = m 2^e, m in [1/2, 1)
  const __m128 m =
      _mm_castsi128_ps(_mm_or_si128(_mm_and_si128(bits, _mm_set1_epi32(0x007FFFFF)), _mm_set1_epi32(0x3F000000)));
  const __m128 low = _mm_cmplt_ps(m, _mm_set1_ps(0.707106781186547524f));  // there m -> 2 m, e -> e - 1
  e = _mm_add_epi32(e, _mm_castps_si128(low));
  const __m128 f = _mm_sub_ps(_mm_add_ps(m, _mm_and_ps(low, m)), one);
  const __m128 ef = _mm_cvtepi32_ps(e);
  const __m128 f2 = _mm_mul_ps(f, f);
  __m128 p = _mm_set1_ps(7.0376836292e-2f);
  for (float c : {-1.1514610310e-1f, 1.1676998740e-1f, -1.2420140846e-1f, 1.4249322787e-1f, -1.6668057665e-1f,
                  2.0000714765e-1f, -2.4999993993e-1f, 3.3333331174e-1f})
    p = _mm_add_ps(_mm_mul_ps(p, f), _mm_set1_ps(c));
  __m128 y = _mm_mul_ps(_mm_mul_ps(p, f), f2);
  y = _mm_add_ps(y, _mm_mul_ps(_mm_set1_ps(-2.12194440e-4f), ef));
  y = _mm_sub_ps(y, _mm_mul_ps(_mm_set1_ps(0.5f), f2));
  return _mm_add_ps(_mm_add_ps(f, y), _mm_mul_ps(_mm_set1_ps(0.693359375f), ef));
}
}  // namespace

float visibleWavelengthPdf(float lambdaNm) {
  if (!(lambdaNm >= kVisibleLambdaMinNm && lambdaNm <= kVisibleLambdaMaxNm)) return 0.0f;
  const double c = std::cosh(kA * (double(lambdaNm) - kCentreNm));
  return float(kA / (kTanhSpan * c * c));
}

float sampleVisibleWavelength(float u) {
  const double lambda = kCentreNm - std::atanh(kTanhLow - kTanhSpan * double(u)) / kA;
  // Rounding near u = 1 must not leave the range the pdf is defined on.
  return std::clamp(float(lambda), kVisibleLambdaMinNm, std::nextafter(kVisibleLambdaMaxNm, 0.0f));
}

float visibleWavelengthCdf(float lambdaNm) {
  if (lambdaNm <= kVisibleLambdaMinNm) return 0.0f;
  if (lambdaNm >= kVisibleLambdaMaxNm) return 1.0f;
  return float((kTanhLow + std::tanh(kA * (double(lambdaNm) - kCentreNm))) / kTanhSpan);
}

WavelengthGroup sampleWavelengthGroupStratified(float uSet, float uHero, int count) {
  const int n = std::clamp(count, 1, kMaxWavelengths);
  const float k = std::min(std::floor(uHero * float(n)), float(n - 1));
  // (uSet + k) / n < 1 in float for uSet <= 1 - 2^-24 and n <= 8.
  return sampleWavelengthGroup((uSet + k) / float(n), n);
}

WavelengthGroup sampleWavelengthGroup(float u, int count) {
  WavelengthGroup group;
  group.count = std::clamp(count, 1, kMaxWavelengths);
  // With t = tanh(a (538 - lambda)) = A - (A + B) u, lambda = 538 - log((1 + t) / (1 - t)) / (2 a)
  // and the density a / ((A + B) cosh^2) is a (1 - t^2) / (A + B): no cosh needed (this runs
  // for every path). The ratio is formed in double (1 - t >= 0.029: no cancellation).
  // Four wavelengths at a time in SSE2 registers, float and double, with the scalar formula's
  // operations in its order (SSE2 arithmetic and conversions round as the scalar ones do): the
  // ratios stored lane by lane and reloaded as one vector for log4 stalled on store forwarding.
  const __m128 one = _mm_set1_ps(1.0f);
  const __m128 uu = _mm_set1_ps(u);
  const __m128d tanhLow = _mm_set1_pd(kTanhLow);
  const __m128d tanhSpan = _mm_set1_pd(kTanhSpan);
  const __m128d oneD = _mm_set1_pd(1.0);
  const __m128d centre = _mm_set1_pd(kCentreNm);
  const __m128d nmPerLog = _mm_set1_pd(kNmPerLog);
  const __m128d pdfScale = _mm_set1_pd(kA / kTanhSpan);
  const __m128 lo = _mm_set1_ps(kVisibleLambdaMinNm);
  const __m128 hi = _mm_set1_ps(std::nextafter(kVisibleLambdaMaxNm, 0.0f));
  for (int j0 = 0; j0 < group.count; j0 += 4) {
    const __m128i lane = _mm_add_epi32(_mm_set1_epi32(j0), _mm_setr_epi32(0, 1, 2, 3));
    const __m128 used = _mm_castsi128_ps(_mm_cmplt_epi32(lane, _mm_set1_epi32(group.count)));
    __m128 uj = _mm_add_ps(uu, _mm_loadu_ps(&kLaneOffsets[size_t(group.count)][size_t(j0)]));
    uj = _mm_sub_ps(uj, _mm_and_ps(_mm_cmpge_ps(uj, one), one));
    const __m128d tLow = _mm_sub_pd(tanhLow, _mm_mul_pd(tanhSpan, _mm_cvtps_pd(uj)));
    const __m128d tHigh = _mm_sub_pd(tanhLow, _mm_mul_pd(tanhSpan, _mm_cvtps_pd(_mm_movehl_ps(uj, uj))));
    const __m128 ratio = _mm_movelh_ps(_mm_cvtpd_ps(_mm_div_pd(_mm_add_pd(oneD, tLow), _mm_sub_pd(oneD, tLow))),
                                       _mm_cvtpd_ps(_mm_div_pd(_mm_add_pd(oneD, tHigh), _mm_sub_pd(oneD, tHigh))));
    // Unused lanes take log 1.
    const __m128 logRatio = log4(_mm_or_ps(_mm_and_ps(used, ratio), _mm_andnot_ps(used, one)));
    const __m128d lambdaLow = _mm_sub_pd(centre, _mm_mul_pd(nmPerLog, _mm_cvtps_pd(logRatio)));
    const __m128d lambdaHigh =
        _mm_sub_pd(centre, _mm_mul_pd(nmPerLog, _mm_cvtps_pd(_mm_movehl_ps(logRatio, logRatio))));
    const __m128 lambda = _mm_movelh_ps(_mm_cvtpd_ps(lambdaLow), _mm_cvtpd_ps(lambdaHigh));
    // std::clamp(v, lo, hi) is v < lo ? lo : (hi < v ? hi : v): maxps(lo, v) then minps(hi, v).
    const __m128 clamped = _mm_min_ps(hi, _mm_max_ps(lo, lambda));
    const __m128 pdf = _mm_movelh_ps(
        _mm_cvtpd_ps(_mm_mul_pd(pdfScale, _mm_sub_pd(oneD, _mm_mul_pd(tLow, tLow)))),
        _mm_cvtpd_ps(_mm_mul_pd(pdfScale, _mm_sub_pd(oneD, _mm_mul_pd(tHigh, tHigh)))));
    // Unused lanes stay 0, as the value-initialised arrays had them.
    _mm_storeu_ps(&group.lambdaNm[j0], _mm_and_ps(used, clamped));
    _mm_storeu_ps(&group.pdfLambda[j0], _mm_and_ps(used, pdf));
    const int moved = _mm_movemask_ps(_mm_andnot_ps(_mm_cmpeq_ps(clamped, lambda), used));
    if (moved != 0) {
      for (int k = 0; k < 4; ++k)
        if (moved & (1 << k)) group.pdfLambda[j0 + k] = visibleWavelengthPdf(group.lambdaNm[j0 + k]);
    }
  }
  return group;
}

}  // namespace tex::color
