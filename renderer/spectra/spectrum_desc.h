// Evaluating the spectra scene files describe (SpectrumDesc in renderer/scene/) and the
// built-in library of named, measured spectra (library entries cite their sources in
// renderer/spectra/named_spectra.cpp).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "renderer/core/spectrum.h"
#include "renderer/scene/scene_description.h"
#include "renderer/spectra/rgb_spectrum.h"

namespace tex::render {

// How an RGB SpectrumDesc is upsampled (rgb_spectrum.h).
enum class SpectrumUse : uint8_t { Reflectance, Unbounded, Illuminant };

// A spectrum as a function of wavelength, ready to evaluate (copyable, immutable).
class SpectrumSource {
 public:
  SpectrumSource() = default;  // zero everywhere
  // Throws std::invalid_argument for an unknown name or a malformed table (sizes differ,
  // wavelengths not increasing).
  SpectrumSource(const SpectrumDesc& desc, SpectrumUse use);
  static SpectrumSource constant(float value);

  float at(float lambdaNm) const;
  Spectrum sample(const Wavelengths& lambda) const;
  // Luminance-like scalar: the Y of this spectrum as a radiance (illuminants) or, for
  // reflectances, under D65 (for choosing lights by power and lobes by albedo).
  float luminance() const;
  bool isConstant() const;  // the same value at every wavelength

 private:
  using Table = std::vector<std::pair<float, float>>;
  static constexpr float kDenseMinNm = 360.0f;
  static constexpr int kDenseCount = 471;  // 360..830 nm in 1 nm steps
  float atExact(float lambdaNm) const;

  SpectrumDesc desc_;
  SpectrumUse use_ = SpectrumUse::Reflectance;
  float luminance_ = 0;
  // Resolved at construction so that evaluation does no lookups: value = factor_ * shape(lambda).
  float factor_ = 0;
  SigmoidPolynomial sigmoid_;                 // Rgb
  const Table* table_ = nullptr;              // Named (library-owned) or Tabulated (ownedTable_)
  std::shared_ptr<const Table> ownedTable_;
  std::shared_ptr<const std::vector<float>> dense_;  // resampled shape x factor (see at())
};

// A named spectrum from the built-in library, or nullptr if unknown. Names: see
// namedSpectrumNames(); values are (lambdaNm, value) pairs, linearly interpolated.
const std::vector<std::pair<float, float>>* namedSpectrum(const std::string& name);
std::vector<std::string> namedSpectrumNames();

// Piecewise-linear interpolation of a (lambdaNm, value) table, 0 outside its range.
float interpolateTable(const std::vector<std::pair<float, float>>& table, float lambdaNm);

}  // namespace tex::render
