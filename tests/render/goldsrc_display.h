// GoldSrc's display of a lightmap luxel, the tests' own copy (not the renderer's table,
// lighting/luxel_display.h): Xash3D FWGS engine/client/gamma.c BuildGammaTable and
// ref/gl/gl_rsurf.c R_BuildLightMap without overbright, at the engine's default cvars.
#pragma once

#include <algorithm>
#include <cmath>

namespace bt::test {

constexpr double kGoldSrcGamma = 2.5, kGoldSrcLightGamma = 2.5;
constexpr double kGoldSrcStyleM = 264.0; // light style 'm': ('m' - 'a') × 22

// The luxel GoldSrc uploads for a sum of stored values × style weights: scaled by
// round(2^(1 / lightgamma) × 256) = 338 to 10 bits, moved by brightness (at 0 it maps the value
// to itself), taken to the power lightgamma / gamma, back to 8 bits.
inline double goldSrcLuxel(double styleSum) {
  const int lightscale = int(std::pow(2.0, 1.0 / kGoldSrcLightGamma) * 256.0 + 0.5);
  const int t = std::min(1023, (int(styleSum) * lightscale) >> 14);
  const double f = std::pow(t / 1023.0, kGoldSrcLightGamma);
  return double(std::clamp(int(std::pow(f, 1.0 / kGoldSrcGamma) * 1023.0), 0, 1023) >> 2);
}

// A luxel stored in style 0 alone, as the engine shows it.
inline double goldSrcShownStored(double stored) {
  return goldSrcLuxel(stored * kGoldSrcStyleM);
}

} // namespace bt::test
