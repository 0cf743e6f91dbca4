// Wavelength sampling over the visible range: the importance density of Radziszewski et al.
// (as reported in pbrt-v4, "SampleVisibleWavelengths"):
//   pdf(lambda) = a / ((A + B) cosh^2(a (lambda - 538))),  a = 0.0072 / nm,  on 360..830 nm,
// A = tanh(a (538 - 360)), B = tanh(a (830 - 538)); a / (A + B) = 0.0039398 / nm, and the
// inverse CDF is lambda = 538 - atanh(A - (A + B) u) / a = 538 - 138.889 atanh(0.85691 - 1.82750 u).
// Hero-style groups rotate u evenly: u_j = frac(u + j / n), so each wavelength of a group has
// the marginal density pdf(lambda) and the group is stratified over the range. Renderers use
// sampleWavelengthGroupStratified, whose groups are stratified at n times the sample count.
#pragma once
#include <array>

namespace tex::color {

inline constexpr int kMaxWavelengths = 8;
inline constexpr float kVisibleLambdaMinNm = 360.0f;
inline constexpr float kVisibleLambdaMaxNm = 830.0f;

// Density per nm of one visible wavelength; zero outside 360..830 nm.
float visibleWavelengthPdf(float lambdaNm);

// Inverse CDF: u in [0,1) to a wavelength in [360, 830) nm.
float sampleVisibleWavelength(float u);

// CDF (inverse of sampleVisibleWavelength), for tests and stratification.
float visibleWavelengthCdf(float lambdaNm);

// A group of wavelengths carried by one path, with each one's marginal density per nm.
struct WavelengthGroup {
  int count = 0;
  std::array<float, kMaxWavelengths> lambdaNm{};
  std::array<float, kMaxWavelengths> pdfLambda{};
};

// Hero-style group of `count` (1..8) wavelengths from one uniform number u in [0,1).
WavelengthGroup sampleWavelengthGroup(float u, int count);

// The same group with its lanes' CDF values at (uSet + j) / count, j = 0..count-1, and the
// hero (lane 0) the one at j = floor(uHero * count), the rest following it cyclically. The
// group as a set is that of sampleWavelengthGroup((uSet + k) / count) for any k, so it depends
// on uSet alone: samples whose uSet are stratified give groups stratified at count times their
// number (with u_j = frac(u + j / count), stratifying u only stratifies the groups at the
// coarse scale their rotation already covers). The hero's CDF value (uSet + k) / count is
// uniform on [0,1) when uSet and uHero are independent, as the hero's own density requires.
WavelengthGroup sampleWavelengthGroupStratified(float uSet, float uHero, int count);

}  // namespace tex::color
