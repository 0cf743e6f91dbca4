#include "renderer/spectra/spectrum_desc.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "renderer/color/spectral_to_rgb.h"

namespace tex::render {

SpectrumSource::SpectrumSource(const SpectrumDesc& desc, SpectrumUse use) : desc_(desc), use_(use) {
  factor_ = desc.scale;
  switch (desc.kind) {
    case SpectrumDesc::Kind::Constant:
      factor_ *= desc.value;
      break;
    case SpectrumDesc::Kind::Rgb:
      if (use == SpectrumUse::Reflectance) {
        sigmoid_ = rgbToSigmoid(desc.rgb);
      } else {
        const RgbUnbounded u = rgbToUnbounded(desc.rgb);
        sigmoid_ = u.shape;
        factor_ *= u.scale;
      }
      break;
    case SpectrumDesc::Kind::Blackbody:
      break;
    case SpectrumDesc::Kind::Named:
      table_ = namedSpectrum(desc.name);
      if (!table_) throw std::invalid_argument("unknown spectrum name '" + desc.name + "'");
      break;
    case SpectrumDesc::Kind::Tabulated: {
      if (desc.lambdaNm.size() != desc.values.size() || desc.lambdaNm.empty())
        throw std::invalid_argument("tabulated spectrum: wavelengths and values differ in count or are empty");
      auto table = std::make_shared<Table>();
      for (size_t i = 0; i < desc.lambdaNm.size(); ++i) {
        if (i > 0 && !(desc.lambdaNm[i] > desc.lambdaNm[i - 1]))
          throw std::invalid_argument("tabulated spectrum: wavelengths must increase");
        table->emplace_back(desc.lambdaNm[i], desc.values[i]);
      }
      ownedTable_ = std::move(table);
      table_ = ownedTable_.get();
      break;
    }
  }
  // Tables and Planck's law are resampled once at whole nanometres over the visible range, so
  // that evaluation at a path's wavelengths is an index and a lerp. That is exact for tables
  // whose knots are whole nanometres (every built-in one); others are evaluated exactly (a
  // spike between whole nanometres had been lost, or widened to twice its energy).
  bool wholeNanometres = true;
  if (table_)
    for (const auto& [lambdaNm, value] : *table_) wholeNanometres = wholeNanometres && lambdaNm == std::floor(lambdaNm);
  if (((desc.kind == SpectrumDesc::Kind::Named || desc.kind == SpectrumDesc::Kind::Tabulated) && wholeNanometres) ||
      desc.kind == SpectrumDesc::Kind::Blackbody) {
    auto dense = std::make_shared<std::vector<float>>(kDenseCount);
    for (int i = 0; i < kDenseCount; ++i) (*dense)[size_t(i)] = atExact(kDenseMinNm + float(i));
    dense_ = std::move(dense);
  }
  if (isConstant()) {
    luminance_ = at(560.0f);  // Y of a flat spectrum is its value in both conventions
  } else if (table_ && !wholeNanometres) {
    // Knots between whole nanometres: the 1 nm sums below could miss a narrow line entirely
    // (a laser-like light of luminance 0 is never chosen). Summed at 0.05 nm instead.
    double y = 0, norm = 0;
    for (int i = 0; i <= 20 * (kDenseCount - 1); ++i) {
      const float lambdaNm = kDenseMinNm + 0.05f * float(i);
      const double bar = color::cieXyzBar(lambdaNm).y;
      const double weight = use == SpectrumUse::Illuminant ? 1.0 : double(color::d65RelativePower(lambdaNm));
      y += bar * weight * double(atExact(lambdaNm));
      norm += bar * weight;
    }
    luminance_ = float(use == SpectrumUse::Illuminant ? y * 0.05 / color::kCie1931YIntegralNm : y / norm);
  } else {
    const auto f = [this](float l) { return at(l); };
    luminance_ = use == SpectrumUse::Illuminant ? color::radianceSpectrumToXyz(f).y
                                                : color::reflectanceSpectrumToXyz(f).y;
  }
}

SpectrumSource SpectrumSource::constant(float value) {
  SpectrumDesc desc;
  desc.kind = SpectrumDesc::Kind::Constant;
  desc.value = value;
  return SpectrumSource(desc, SpectrumUse::Reflectance);
}

float SpectrumSource::at(float lambdaNm) const {
  if (dense_) {
    const float x = lambdaNm - kDenseMinNm;
    if (x >= 0.0f && x < float(kDenseCount - 1)) {
      const int i = int(x);
      const float t = x - float(i);
      const float* d = dense_->data();
      return d[i] + t * (d[i + 1] - d[i]);
    }
  }
  return atExact(lambdaNm);
}

float SpectrumSource::atExact(float lambdaNm) const {
  switch (desc_.kind) {
    case SpectrumDesc::Kind::Constant:
      return factor_;
    case SpectrumDesc::Kind::Rgb: {
      const float shape = sigmoid_(lambdaNm);
      return use_ == SpectrumUse::Illuminant ? factor_ * shape * d65Normalised(lambdaNm) : factor_ * shape;
    }
    case SpectrumDesc::Kind::Blackbody:
      return factor_ * blackbodyNormalised(lambdaNm, desc_.kelvin);
    case SpectrumDesc::Kind::Named:
    case SpectrumDesc::Kind::Tabulated:
      return factor_ * interpolateTable(*table_, lambdaNm);
  }
  return 0.0f;
}

Spectrum SpectrumSource::sample(const Wavelengths& lambda) const {
  if (desc_.kind == SpectrumDesc::Kind::Constant) {
    return sampleSpectrum(lambda, [&](float) { return factor_; });
  }
  return sampleSpectrum(lambda, [&](float l) { return at(l); });
}

float SpectrumSource::luminance() const { return luminance_; }

bool SpectrumSource::isConstant() const {
  switch (desc_.kind) {
    case SpectrumDesc::Kind::Constant:
      return true;
    case SpectrumDesc::Kind::Rgb:
      // Grey reflectances and unbounded greys are flat; illuminants carry D65's shape.
      return factor_ == 0.0f || (use_ != SpectrumUse::Illuminant && desc_.rgb.x == desc_.rgb.y &&
                                 desc_.rgb.y == desc_.rgb.z);
    default:
      return factor_ == 0.0f;
  }
}

float interpolateTable(const std::vector<std::pair<float, float>>& table, float lambdaNm) {
  if (table.empty() || !(lambdaNm >= table.front().first) || lambdaNm > table.back().first) return 0.0f;
  if (table.size() == 1) return table.front().second;
  // First entry beyond lambda (the last one for lambda at the end), interpolate from its left.
  auto hi = std::upper_bound(table.begin() + 1, table.end() - 1, lambdaNm,
                             [](float l, const std::pair<float, float>& e) { return l < e.first; });
  auto lo = hi - 1;
  const float t = (lambdaNm - lo->first) / (hi->first - lo->first);
  return lo->second + t * (hi->second - lo->second);
}

}  // namespace tex::render
