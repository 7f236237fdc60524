#include "renderer/render.h"

#include "lighting/sampling.h" // pcgHash
#include "scene/color.h"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>

namespace bt {

namespace {

glm::vec3 faceColor(uint32_t face) {
  if (face == 0) return glm::vec3(0.0f);
  const uint32_t h = pcgHash(face);
  return glm::vec3(float(h & 0xff), float((h >> 8) & 0xff), float((h >> 16) & 0xff)) / 255.0f;
}

uint8_t toByte(float v) {
  return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

} // namespace

std::vector<uint8_t> displayPixels(const RenderImage& image, const OutputSettings& output) {
  const size_t n = size_t(image.width) * size_t(image.height);
  std::vector<uint8_t> pixels(n * 3);
  float maxDepth = 0.0f;
  for (float d : image.depth)
    if (std::isfinite(d)) maxDepth = std::max(maxDepth, d);
  const float exposure = std::exp2(output.exposureEv);
  const std::vector<glm::vec3>& beauty = image.denoised.empty() ? image.beauty : image.denoised;
  for (size_t i = 0; i < n; ++i) {
    glm::vec3 c;
    switch (output.aov) {
    case Aov::Beauty: c = linearToSrgb(applyTonemap(output.tonemap, beauty[i] * exposure)); break;
    case Aov::Albedo: c = linearToSrgb(glm::clamp(image.albedo[i], 0.0f, 1.0f)); break;
    case Aov::Normal: c = image.face[i] ? image.normal[i] * 0.5f + 0.5f : glm::vec3(0.0f); break;
    case Aov::Depth:
      // Near is bright; nothing hit is black.
      c = glm::vec3(std::isfinite(image.depth[i]) && maxDepth > 0.0f ? 1.0f - image.depth[i] / maxDepth : 0.0f);
      break;
    case Aov::Face: c = faceColor(image.face[i]); break;
    }
    pixels[i * 3 + 0] = toByte(c.x);
    pixels[i * 3 + 1] = toByte(c.y);
    pixels[i * 3 + 2] = toByte(c.z);
  }
  return pixels;
}

} // namespace bt
