#include "renderer/color/color.h"

namespace tex::color {

Xyz linearSrgbToXyz(const Rgb& c) {
  return {0.4124564f * c.r + 0.3575761f * c.g + 0.1804375f * c.b,
          0.2126729f * c.r + 0.7151522f * c.g + 0.0721750f * c.b,
          0.0193339f * c.r + 0.1191920f * c.g + 0.9503041f * c.b};
}

}  // namespace tex::color
