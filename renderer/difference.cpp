#include "renderer/difference.h"

#include "scene/color.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

namespace bt {

glm::vec3 differenceColour(int steps) {
  static constexpr std::array<glm::vec3, 5> kStops{glm::vec3(0, 0, 0), glm::vec3(0, 0, 1), glm::vec3(0, 1, 0), glm::vec3(1, 1, 0),
                                                   glm::vec3(1, 0, 0)};
  const float at = std::clamp(float(steps), 0.0f, float(kDifferenceFullScale)) / float(kDifferenceFullScale) * 4.0f;
  const int i = std::min(int(at), 3);
  return glm::mix(kStops[size_t(i)], kStops[size_t(i) + 1], at - float(i));
}

namespace {
int stepsAt(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, size_t pixel) {
  int steps = 0;
  for (size_t c = 0; c < 3; ++c) steps = std::max(steps, std::abs(int(a[pixel * 3 + c]) - int(b[pixel * 3 + c])));
  return steps;
}
} // namespace

std::vector<uint8_t> differencePixels(const std::vector<uint8_t>& compiled, const std::vector<uint8_t>& faithful) {
  std::vector<uint8_t> out(std::min(compiled.size(), faithful.size()));
  for (size_t i = 0; i < out.size() / 3; ++i) {
    const glm::vec3 c = differenceColour(stepsAt(compiled, faithful, i));
    for (int k = 0; k < 3; ++k) out[i * 3 + size_t(k)] = uint8_t(std::lround(c[k] * 255.0f));
  }
  return out;
}

RenderImage differenceImage(const RenderImage& compiled, const RenderImage& faithful, const OutputSettings& output) {
  OutputSettings shown = output;
  shown.aov = Aov::Beauty;
  const std::vector<uint8_t> a = displayPixels(compiled, shown), b = displayPixels(faithful, shown);
  RenderImage out = compiled;
  for (size_t i = 0; i < out.beauty.size(); ++i) out.beauty[i] = srgbToLinear(differenceColour(stepsAt(a, b, i)));
  return out;
}

} // namespace bt
