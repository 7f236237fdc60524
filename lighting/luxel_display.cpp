#include "lighting/luxel_display.h"

#include <algorithm>
#include <cmath>

namespace bt {

std::array<float, BT_LUXEL_TABLE_SIZE> buildGoldSrcLuxelTable(float gamma, float lightgamma, float brightness) {
  // BuildGammaTable's lightgammatable, in its own mix of float and double.
  const float g1 = 1.0f / gamma;
  const float g3 = brightness <= 0.0f ? 0.125f : brightness <= 1.0f ? 0.125f - brightness * brightness * 0.075f : 0.05f;
  std::array<int, 1024> lightgamma10{};
  for (int i = 0; i < 1024; ++i) {
    float f = float(std::pow(i / 1023.0, double(lightgamma)));
    if (brightness > 1.0f) f *= brightness;
    f = f <= g3 ? (f / g3) * 0.125f : float(((f - g3) / (1.0 - g3)) * 0.875 + 0.125);
    lightgamma10[size_t(i)] = std::clamp(int(std::pow(double(f), double(g1)) * 1023.0), 0, 1023);
  }
  // R_BuildLightMap without overbright: the sum of styles scaled by 2^(1 / lightgamma), 10 bits.
  const int lightscale = int(std::pow(2.0f, 1.0f / lightgamma) * 256.0f + 0.5f);
  std::array<float, BT_LUXEL_TABLE_SIZE> out{};
  for (int b = 0; b < BT_LUXEL_TABLE_SIZE; ++b) {
    const int t = std::min(1023, (b * BT_GOLDSRC_STYLE_M * lightscale) >> 14);
    out[size_t(b)] = float(lightgamma10[size_t(t)] >> 2);
  }
  return out;
}

const std::array<float, BT_LUXEL_TABLE_SIZE>& goldSrcLuxelTable() {
  static const std::array<float, BT_LUXEL_TABLE_SIZE> table =
      buildGoldSrcLuxelTable(BT_GOLDSRC_GAMMA, BT_GOLDSRC_LIGHTGAMMA, BT_GOLDSRC_BRIGHTNESS); // a constant
  return table;
}

float shownLuxel(LuxelDisplay display, float stored) {
  if (display != BT_LUXEL_DISPLAY_GOLDSRC) return stored;
  const std::array<float, BT_LUXEL_TABLE_SIZE>& table = goldSrcLuxelTable();
  const float s = std::clamp(stored, 0.0f, float(BT_LUXEL_TABLE_SIZE - 1));
  const int i = std::min(int(s), BT_LUXEL_TABLE_SIZE - 2);
  const float w = s - float(i);
  return table[size_t(i)] * (1.0f - w) + table[size_t(i) + 1] * w;
}

glm::vec3 shownLuxel(LuxelDisplay display, const glm::vec3& stored) {
  return {shownLuxel(display, stored.x), shownLuxel(display, stored.y), shownLuxel(display, stored.z)};
}

} // namespace bt
