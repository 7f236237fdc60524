#include "viewer/view_modes.h"

#include "scene/color.h"

#include <algorithm>
#include <cmath>

namespace bt {

const char* toString(ViewMode mode) {
  switch (mode) {
  case ViewMode::Beauty: return "lit";
  case ViewMode::Fullbright: return "fullbright";
  case ViewMode::Normal: return "normals";
  case ViewMode::LightOnly: return "light only";
  case ViewMode::Flat: return "flat";
  }
  return "?";
}

namespace {

// Below one byte of texture there is no light left to tell.
constexpr float kDarkestTexel = 1.0f / 255.0f;

float over(float picture, float texture) {
  return texture < kDarkestTexel ? 0.0f : picture / texture;
}

} // namespace

std::vector<glm::vec3> lightAlone(const RenderImage& image, bool engineSpace) {
  std::vector<glm::vec3> light(image.beauty.size());
  for (size_t i = 0; i < light.size(); ++i) {
    if (image.face[i] == 0) {
      light[i] = image.beauty[i];
      continue;
    }
    const glm::vec3 picture = engineSpace ? linearToSrgb(glm::max(image.beauty[i], glm::vec3(0.0f))) : image.beauty[i];
    const glm::vec3 texture = engineSpace ? linearToSrgb(image.albedo[i]) : image.albedo[i];
    const glm::vec3 alone(over(picture.x, texture.x), over(picture.y, texture.y), over(picture.z, texture.z));
    light[i] = engineSpace ? srgbToLinear(alone) : alone;
  }
  return light;
}

} // namespace bt
