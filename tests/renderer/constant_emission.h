// An emission of the same radiance at every point and wavelength, for light tests (in
// tex::test, beside chi_square.h's helpers).
#pragma once
#include "renderer/lights/light.h"

namespace tex::test {

class ConstantEmission final : public render::EmissionSource {
 public:
  explicit ConstantEmission(float L) : L_(L) {}
  render::Spectrum radiance(const render::EmitterPoint&, const render::Wavelengths& lambda) const override {
    render::Spectrum s;
    for (int i = 0; i < lambda.count; ++i) s[i] = L_;
    return s;
  }
  float averageRadiance() const override { return L_; }

 private:
  float L_;
};

}  // namespace tex::test
