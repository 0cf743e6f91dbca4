// The built-in library of named spectra. Every table cites its source; values are facts
// (measurements and standard formulas), written compactly.
#include <cmath>
#include <map>
#include <stdexcept>

#include "renderer/color/cie_tables.h"
#include "renderer/color/color.h"
#include "renderer/spectra/spectrum_desc.h"

namespace tex::render {

namespace {

using Table = std::vector<std::pair<float, float>>;

// Cornell Box Data, Cornell University Program of Computer Graphics,
// https://www.graphics.cornell.edu/online/box/data.html: diffuse reflectances of the walls,
// measured at 400..700 nm in 4 nm steps (76 samples; as also shipped by Mitsuba's and other
// renderers' "cbox" scenes). Outside 400..700 nm the page gives nothing, so the tables are 0.
constexpr float kCornellFirstNm = 400.0f, kCornellStepNm = 4.0f;
constexpr int kCornellCount = 76;
constexpr float kCornellWhite[kCornellCount] = {
    0.343f, 0.445f, 0.551f, 0.624f, 0.665f, 0.687f, 0.708f, 0.723f, 0.715f, 0.71f,
    0.745f, 0.758f, 0.739f, 0.767f, 0.777f, 0.765f, 0.751f, 0.745f, 0.748f, 0.729f,
    0.745f, 0.757f, 0.753f, 0.75f, 0.746f, 0.747f, 0.735f, 0.732f, 0.739f, 0.734f,
    0.725f, 0.721f, 0.733f, 0.725f, 0.732f, 0.743f, 0.744f, 0.748f, 0.728f, 0.716f,
    0.733f, 0.726f, 0.713f, 0.74f, 0.754f, 0.764f, 0.752f, 0.736f, 0.734f, 0.741f,
    0.74f, 0.732f, 0.745f, 0.755f, 0.751f, 0.744f, 0.731f, 0.733f, 0.744f, 0.731f,
    0.712f, 0.708f, 0.729f, 0.73f, 0.727f, 0.707f, 0.703f, 0.729f, 0.75f, 0.76f,
    0.751f, 0.739f, 0.724f, 0.73f, 0.74f, 0.737f,
};
constexpr float kCornellGreen[kCornellCount] = {
    0.092f, 0.096f, 0.098f, 0.097f, 0.098f, 0.095f, 0.095f, 0.097f, 0.095f, 0.094f,
    0.097f, 0.098f, 0.096f, 0.101f, 0.103f, 0.104f, 0.107f, 0.109f, 0.112f, 0.115f,
    0.125f, 0.14f, 0.16f, 0.187f, 0.229f, 0.285f, 0.343f, 0.39f, 0.435f, 0.464f,
    0.472f, 0.476f, 0.481f, 0.462f, 0.447f, 0.441f, 0.426f, 0.406f, 0.373f, 0.347f,
    0.337f, 0.314f, 0.285f, 0.277f, 0.266f, 0.25f, 0.23f, 0.207f, 0.186f, 0.171f,
    0.16f, 0.148f, 0.141f, 0.136f, 0.13f, 0.126f, 0.123f, 0.121f, 0.122f, 0.119f,
    0.114f, 0.115f, 0.117f, 0.117f, 0.118f, 0.12f, 0.122f, 0.128f, 0.132f, 0.139f,
    0.144f, 0.146f, 0.15f, 0.152f, 0.157f, 0.159f,
};
constexpr float kCornellRed[kCornellCount] = {
    0.04f, 0.046f, 0.048f, 0.053f, 0.049f, 0.05f, 0.053f, 0.055f, 0.057f, 0.056f,
    0.059f, 0.057f, 0.061f, 0.061f, 0.06f, 0.062f, 0.062f, 0.062f, 0.061f, 0.062f,
    0.06f, 0.059f, 0.057f, 0.058f, 0.058f, 0.058f, 0.056f, 0.055f, 0.056f, 0.059f,
    0.057f, 0.055f, 0.059f, 0.059f, 0.058f, 0.059f, 0.061f, 0.061f, 0.063f, 0.063f,
    0.067f, 0.068f, 0.072f, 0.08f, 0.09f, 0.099f, 0.124f, 0.154f, 0.192f, 0.255f,
    0.287f, 0.349f, 0.402f, 0.443f, 0.487f, 0.513f, 0.558f, 0.584f, 0.62f, 0.606f,
    0.609f, 0.651f, 0.612f, 0.61f, 0.65f, 0.638f, 0.627f, 0.62f, 0.63f, 0.628f,
    0.642f, 0.639f, 0.657f, 0.639f, 0.635f, 0.642f,
};
// The same page: the light's emission spectrum (relative), at 400, 500, 600, 700 nm.
constexpr float kCornellLight[][2] = {{400.0f, 0.0f}, {500.0f, 8.0f}, {600.0f, 15.6f}, {700.0f, 18.4f}};

// Complex refractive index (eta, k) of metals, from pbrt-v4 (src/pbrt/util/spectrum.cpp, named
// spectra "metal-Ag-eta" etc.; the tables are inherited from pbrt-v3, which does not name the
// original measurements). 56 samples from 298.8 to 885.6 nm shared by all eight tables.
constexpr int kMetalCount = 56;
constexpr float kMetalLambdaNm[kMetalCount] = {
    298.75705f, 302.400421f, 306.133759f, 309.960449f, 313.884003f, 317.908142f, 322.036835f, 326.274139f,
    330.624481f, 335.092377f, 339.682678f, 344.400482f, 349.251221f, 354.240509f, 359.37442f, 364.659332f,
    370.10202f, 375.709625f, 381.489777f, 387.450562f, 393.600555f, 399.948975f, 406.505493f, 413.280579f,
    420.285339f, 427.531647f, 435.032196f, 442.800629f, 450.851562f, 459.200653f, 467.864838f, 476.862213f,
    486.212463f, 495.936707f, 506.057861f, 516.600769f, 527.592224f, 539.061646f, 551.040771f, 563.564453f,
    576.670593f, 590.400818f, 604.800842f, 619.920898f, 635.816284f, 652.548279f, 670.184753f, 688.800964f,
    708.481018f, 729.318665f, 751.41925f, 774.901123f, 799.897949f, 826.561157f, 855.063293f, 885.601257f,
};
constexpr float kAgEta[kMetalCount] = {
    1.519f, 1.496f, 1.4325f, 1.323f, 1.142062f, 0.932f, 0.719062f, 0.526f, 0.388125f, 0.294f,
    0.253313f, 0.238f, 0.221438f, 0.209f, 0.194813f, 0.186f, 0.192063f, 0.2f, 0.198063f, 0.192f,
    0.182f, 0.173f, 0.172625f, 0.173f, 0.166688f, 0.16f, 0.1585f, 0.157f, 0.151063f, 0.144f,
    0.137313f, 0.132f, 0.13025f, 0.13f, 0.129938f, 0.13f, 0.130063f, 0.129f, 0.124375f, 0.12f,
    0.119313f, 0.121f, 0.1255f, 0.131f, 0.136125f, 0.14f, 0.140063f, 0.14f, 0.144313f, 0.148f,
    0.145875f, 0.143f, 0.142563f, 0.145f, 0.151938f, 0.163f,
};
constexpr float kAgK[kMetalCount] = {
    1.08f, 0.882f, 0.761063f, 0.647f, 0.550875f, 0.504f, 0.554375f, 0.663f, 0.818563f, 0.986f,
    1.120687f, 1.24f, 1.34525f, 1.44f, 1.53375f, 1.61f, 1.641875f, 1.67f, 1.735f, 1.81f,
    1.87875f, 1.95f, 2.029375f, 2.11f, 2.18625f, 2.26f, 2.329375f, 2.4f, 2.47875f, 2.56f,
    2.64f, 2.72f, 2.798125f, 2.88f, 2.97375f, 3.07f, 3.159375f, 3.25f, 3.348125f, 3.45f,
    3.55375f, 3.66f, 3.76625f, 3.88f, 4.010625f, 4.15f, 4.293125f, 4.44f, 4.58625f, 4.74f,
    4.908125f, 5.09f, 5.28875f, 5.5f, 5.720624f, 5.95f,
};
constexpr float kAlEta[kMetalCount] = {
    0.273375f, 0.28f, 0.286813f, 0.294f, 0.301875f, 0.31f, 0.317875f, 0.326f, 0.33475f, 0.344f,
    0.353813f, 0.364f, 0.374375f, 0.385f, 0.39575f, 0.407f, 0.419125f, 0.432f, 0.445688f, 0.46f,
    0.474688f, 0.49f, 0.506188f, 0.523f, 0.540063f, 0.558f, 0.577313f, 0.598f, 0.620313f, 0.644f,
    0.668625f, 0.695f, 0.72375f, 0.755f, 0.789f, 0.826f, 0.867f, 0.912f, 0.963f, 1.02f,
    1.08f, 1.15f, 1.22f, 1.3f, 1.39f, 1.49f, 1.6f, 1.74f, 1.91f, 2.14f,
    2.41f, 2.63f, 2.8f, 2.74f, 2.58f, 2.24f,
};
constexpr float kAlK[kMetalCount] = {
    3.59375f, 3.64f, 3.689375f, 3.74f, 3.789375f, 3.84f, 3.894375f, 3.95f, 4.005f, 4.06f,
    4.11375f, 4.17f, 4.23375f, 4.3f, 4.365f, 4.43f, 4.49375f, 4.56f, 4.63375f, 4.71f,
    4.784375f, 4.86f, 4.938125f, 5.02f, 5.10875f, 5.2f, 5.29f, 5.38f, 5.48f, 5.58f,
    5.69f, 5.8f, 5.915f, 6.03f, 6.15f, 6.28f, 6.42f, 6.55f, 6.7f, 6.85f,
    7.0f, 7.15f, 7.31f, 7.48f, 7.65f, 7.82f, 8.01f, 8.21f, 8.39f, 8.57f,
    8.62f, 8.6f, 8.45f, 8.31f, 8.21f, 8.21f,
};
constexpr float kAuEta[kMetalCount] = {
    1.795f, 1.812f, 1.822625f, 1.83f, 1.837125f, 1.84f, 1.83425f, 1.824f, 1.812f, 1.798f,
    1.782f, 1.766f, 1.7525f, 1.74f, 1.727625f, 1.716f, 1.705875f, 1.696f, 1.68475f, 1.674f,
    1.666f, 1.658f, 1.64725f, 1.636f, 1.628f, 1.616f, 1.59625f, 1.562f, 1.502125f, 1.426f,
    1.345875f, 1.242f, 1.08675f, 0.916f, 0.7545f, 0.608f, 0.49175f, 0.402f, 0.3455f, 0.306f,
    0.267625f, 0.236f, 0.212375f, 0.194f, 0.17775f, 0.166f, 0.161f, 0.16f, 0.160875f, 0.164f,
    0.1695f, 0.176f, 0.181375f, 0.188f, 0.198125f, 0.21f,
};
constexpr float kAuK[kMetalCount] = {
    1.920375f, 1.92f, 1.918875f, 1.916f, 1.911375f, 1.904f, 1.891375f, 1.878f, 1.86825f, 1.86f,
    1.85175f, 1.846f, 1.84525f, 1.848f, 1.852375f, 1.862f, 1.883f, 1.906f, 1.9225f, 1.936f,
    1.94775f, 1.956f, 1.959375f, 1.958f, 1.951375f, 1.94f, 1.9245f, 1.904f, 1.875875f, 1.846f,
    1.814625f, 1.796f, 1.797375f, 1.84f, 1.9565f, 2.12f, 2.32625f, 2.54f, 2.730625f, 2.88f,
    2.940625f, 2.97f, 3.015f, 3.06f, 3.07f, 3.15f, 3.445812f, 3.8f, 4.087687f, 4.357f,
    4.610188f, 4.86f, 5.125813f, 5.39f, 5.63125f, 5.88f,
};
constexpr float kCuEta[kMetalCount] = {
    1.400313f, 1.38f, 1.358438f, 1.34f, 1.329063f, 1.325f, 1.3325f, 1.34f, 1.334375f, 1.325f,
    1.317812f, 1.31f, 1.300313f, 1.29f, 1.281563f, 1.27f, 1.249062f, 1.225f, 1.2f, 1.18f,
    1.174375f, 1.175f, 1.1775f, 1.18f, 1.178125f, 1.175f, 1.172812f, 1.17f, 1.165312f, 1.16f,
    1.155312f, 1.15f, 1.142812f, 1.135f, 1.131562f, 1.12f, 1.092437f, 1.04f, 0.950375f, 0.826f,
    0.645875f, 0.468f, 0.35125f, 0.272f, 0.230813f, 0.214f, 0.20925f, 0.213f, 0.21625f, 0.223f,
    0.2365f, 0.25f, 0.254188f, 0.26f, 0.28f, 0.3f,
};
constexpr float kCuK[kMetalCount] = {
    1.662125f, 1.687f, 1.703313f, 1.72f, 1.744563f, 1.77f, 1.791625f, 1.81f, 1.822125f, 1.834f,
    1.85175f, 1.872f, 1.89425f, 1.916f, 1.931688f, 1.95f, 1.972438f, 2.015f, 2.121562f, 2.21f,
    2.177188f, 2.13f, 2.160063f, 2.21f, 2.249938f, 2.289f, 2.326f, 2.362f, 2.397625f, 2.433f,
    2.469187f, 2.504f, 2.535875f, 2.564f, 2.589625f, 2.605f, 2.595562f, 2.583f, 2.5765f, 2.599f,
    2.678062f, 2.809f, 3.01075f, 3.24f, 3.458187f, 3.67f, 3.863125f, 4.05f, 4.239563f, 4.43f,
    4.619563f, 4.817f, 5.034125f, 5.26f, 5.485625f, 5.717f,
};

Table sampled(const float* values, int count, float firstNm, float stepNm) {
  Table t;
  for (int i = 0; i < count; ++i) t.emplace_back(firstNm + stepNm * float(i), values[i]);
  return t;
}

Table metal(const float* values) {
  Table t;
  for (int i = 0; i < kMetalCount; ++i) t.emplace_back(kMetalLambdaNm[i], values[i]);
  return t;
}

// Y of a radiance table with the 1 nm quadrature of color/spectral_to_rgb.h.
double luminance(const Table& t) {
  double y = 0;
  for (int i = 0; i < color::kCieSampleCount; ++i) {
    const float lambda = float(color::kCieLambdaMinNm + i);
    y += double(color::kCie1931Y[i]) * interpolateTable(t, lambda);
  }
  return y / color::kCie1931YIntegralNm;
}

Table normalisedToUnitLuminance(Table t) {
  const double y = luminance(t);
  for (auto& entry : t) entry.second = float(entry.second / y);
  return t;
}

// CIE standard illuminant D65 (the 5 nm table of renderer/color/cie_tables.h), luminance 1.
Table d65() {
  Table t;
  for (int i = 0; i < color::kD65SampleCount; ++i)
    t.emplace_back(float(color::kD65LambdaMinNm + color::kD65LambdaStepNm * i), color::kD65[i]);
  return normalisedToUnitLuminance(std::move(t));
}

// CIE standard illuminant A by its defining formula (CIE 15:2004, section 3.1):
// S(lambda) = 100 (560 / lambda)^5 (e^(c2 / (2848 * 560e-9)) - 1) / (e^(c2 / (2848 lambda)) - 1),
// c2 = 1.435e-2 m K; sampled at 5 nm over 300..830 nm, then normalised to luminance 1.
Table illuminantA() {
  Table t;
  constexpr double c2 = 1.435e-2, kelvin = 2848.0;
  for (int lambda = 300; lambda <= 830; lambda += 5) {
    const double l = lambda * 1e-9;
    const double s = 100.0 * std::pow(560e-9 / l, 5.0) * std::expm1(c2 / (kelvin * 560e-9)) /
                     std::expm1(c2 / (kelvin * l));
    t.emplace_back(float(lambda), float(s));
  }
  return normalisedToUnitLuminance(std::move(t));
}

// Sellmeier dispersion n^2 = 1 + sum B_i l^2 / (l^2 - C_i), l in micrometres, sampled at 5 nm
// over 300..900 nm (linear interpolation between samples is within 1e-6 of the formula).
Table sellmeier(const double (&b)[3], const double (&c)[3]) {
  Table t;
  for (int lambda = 300; lambda <= 900; lambda += 5) {
    const double l2 = (lambda * 1e-3) * (lambda * 1e-3);
    double n2 = 1.0;
    for (int i = 0; i < 3; ++i) n2 += b[i] * l2 / (l2 - c[i]);
    t.emplace_back(float(lambda), float(std::sqrt(n2)));
  }
  return t;
}

std::map<std::string, Table> buildLibrary() {
  std::map<std::string, Table> lib;
  lib["cornell-white"] = sampled(kCornellWhite, kCornellCount, kCornellFirstNm, kCornellStepNm);
  lib["cornell-green"] = sampled(kCornellGreen, kCornellCount, kCornellFirstNm, kCornellStepNm);
  lib["cornell-red"] = sampled(kCornellRed, kCornellCount, kCornellFirstNm, kCornellStepNm);
  for (const auto& [lambda, value] : kCornellLight) lib["cornell-light"].emplace_back(lambda, value);
  lib["Ag-eta"] = metal(kAgEta), lib["Ag-k"] = metal(kAgK);
  lib["Al-eta"] = metal(kAlEta), lib["Al-k"] = metal(kAlK);
  lib["Au-eta"] = metal(kAuEta), lib["Au-k"] = metal(kAuK);
  lib["Cu-eta"] = metal(kCuEta), lib["Cu-k"] = metal(kCuK);
  lib["D65"] = d65();
  lib["illuminant-A"] = illuminantA();
  // SCHOTT N-BK7 data sheet (SCHOTT optical glass catalogue): B1..3, C1..3 in um^2.
  lib["BK7-ior"] = sellmeier({1.03961212, 0.231792344, 1.01046945}, {0.00600069867, 0.0200179144, 103.560653});
  // Fused silica: I. H. Malitson, "Interspecimen comparison of the refractive index of fused
  // silica", JOSA 55(10), 1965: B = 0.6961663, 0.4079426, 0.8974794; C = (0.0684043,
  // 0.1162414, 9.896161 um)^2.
  lib["fused-silica-ior"] = sellmeier({0.6961663, 0.4079426, 0.8974794},
                                      {0.0684043 * 0.0684043, 0.1162414 * 0.1162414, 9.896161 * 9.896161});
  return lib;
}

const std::map<std::string, Table>& library() {
  static const std::map<std::string, Table> lib = buildLibrary();
  return lib;
}

}  // namespace

const std::vector<std::pair<float, float>>* namedSpectrum(const std::string& name) {
  const auto& lib = library();
  const auto it = lib.find(name);
  return it == lib.end() ? nullptr : &it->second;
}

std::vector<std::string> namedSpectrumNames() {
  std::vector<std::string> names;
  for (const auto& entry : library()) names.push_back(entry.first);
  return names;
}

}  // namespace tex::render
