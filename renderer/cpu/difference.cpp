#include "renderer/cpu/difference.h"

#include "renderer/cpu/color.h"

#include <algorithm>
#include <array>
#include <cstdlib>

namespace bt {

glm::vec3 differenceColour(int steps) {
  static constexpr std::array<glm::vec3, 5> kStops{glm::vec3(0, 0, 0), glm::vec3(0, 0, 1), glm::vec3(0, 1, 0),
                                                   glm::vec3(1, 1, 0), glm::vec3(1, 0, 0)};
  const float at = std::clamp(float(steps), 0.0f, float(kDifferenceFullScale)) / float(kDifferenceFullScale) * 4.0f;
  const int i = std::min(int(at), 3);
  return glm::mix(kStops[size_t(i)], kStops[size_t(i) + 1], at - float(i));
}

RenderImage differenceImage(const RenderImage& compiled, const RenderImage& faithful, const OutputSettings& output) {
  OutputSettings shown = output;
  shown.aov = Aov::Beauty;
  const std::vector<uint8_t> a = displayPixels(compiled, shown), b = displayPixels(faithful, shown);
  RenderImage out = compiled;
  for (size_t i = 0; i < out.beauty.size(); ++i) {
    int steps = 0;
    for (size_t c = 0; c < 3; ++c) steps = std::max(steps, std::abs(int(a[i * 3 + c]) - int(b[i * 3 + c])));
    out.beauty[i] = srgbToLinear(differenceColour(steps));
  }
  return out;
}

} // namespace bt
