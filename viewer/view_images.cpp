#include "viewer/view_images.h"

#include "renderer/image_output.h"
#include "scene/color.h"
#include "viewer/viewer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace bt {

namespace fs = std::filesystem;

namespace {
uint8_t toByte(float v) {
  return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}
} // namespace

RenderImage aovImage(const gl::AovImages& aovs) {
  RenderImage image;
  image.width = aovs.width;
  image.height = aovs.height;
  image.albedo.resize(aovs.albedo.size());
  for (size_t i = 0; i < aovs.albedo.size(); ++i) image.albedo[i] = glm::vec3(aovs.albedo[i]);
  image.normal = aovs.normal;
  image.depth = aovs.depth;
  image.face = aovs.face;
  return image;
}

std::vector<uint8_t> aovRgba(const RenderImage& image, ViewMode mode) {
  if (mode == ViewMode::Flat) {
    OutputSettings face;
    face.aov = Aov::Face;
    return rgbToRgba(displayPixels(image, face));
  }
  std::vector<uint8_t> rgba(image.albedo.size() * 4);
  for (size_t i = 0; i < image.albedo.size(); ++i) {
    glm::vec3 c = mode == ViewMode::Fullbright ? linearToSrgb(image.albedo[i]) : image.normal[i] * 0.5f + 0.5f;
    if (mode == ViewMode::Normal && image.face[i] == 0) c = glm::vec3(0.0f);
    rgba[i * 4 + 0] = toByte(c.r);
    rgba[i * 4 + 1] = toByte(c.g);
    rgba[i * 4 + 2] = toByte(c.b);
    rgba[i * 4 + 3] = 255;
  }
  return rgba;
}

std::vector<uint8_t> rgbToRgba(const std::vector<uint8_t>& rgb) {
  std::vector<uint8_t> rgba(rgb.size() / 3 * 4, 255);
  for (size_t i = 0; i < rgb.size() / 3; ++i) std::copy_n(&rgb[i * 3], 3, &rgba[i * 4]);
  return rgba;
}

fs::path writeScreenshot(const fs::path& folder, const std::string& stem, const RenderImage& image, const OutputSettings& output) {
  fs::path png;
  for (int i = 0;; ++i) {
    png = folder / fmt::format("{}-{:03}.png", stem, i);
    if (!fs::exists(png)) break;
  }
  writeImage(png.string(), image, output);
  fs::path exr = png;
  exr.replace_extension(".exr");
  try {
    writeImage(exr.string(), image, output);
  } catch (...) {
    std::error_code ignored; // half a screenshot is none: the PNG goes too
    fs::remove(png, ignored);
    throw;
  }
  return png;
}

} // namespace bt
