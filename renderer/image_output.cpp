#include "renderer/image_output.h"

#include "scene/names.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <unistd.h>

namespace bt {

namespace {

// Linear beauty (exposure applied) as R, G, B, the default layer, then the AOVs and, after
// --denoise, the denoised beauty as denoised.R/G/B. The exposure goes into the header.
bool writeExr(OIIO::ImageOutput& out, const std::string& temp, const RenderImage& image, const OutputSettings& output) {
  const size_t n = size_t(image.width) * size_t(image.height);
  const bool denoised = !image.denoised.empty();
  const int channels = denoised ? 13 : 10;
  std::vector<float> pixels(n * size_t(channels));
  const float exposure = std::exp2(output.exposureEv);
  for (size_t i = 0; i < n; ++i) {
    float* p = &pixels[i * size_t(channels)];
    const glm::vec3 b = image.beauty[i] * exposure;
    p[0] = b.x, p[1] = b.y, p[2] = b.z;
    p[3] = image.albedo[i].x, p[4] = image.albedo[i].y, p[5] = image.albedo[i].z;
    p[6] = image.normal[i].x, p[7] = image.normal[i].y, p[8] = image.normal[i].z;
    p[9] = image.depth[i];
    if (denoised) {
      const glm::vec3 d = image.denoised[i] * exposure;
      p[10] = d.x, p[11] = d.y, p[12] = d.z;
    }
  }
  OIIO::ImageSpec spec(image.width, image.height, channels, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"R", "G", "B", "albedo.R", "albedo.G", "albedo.B", "normal.X", "normal.Y", "normal.Z", "depth.Z"};
  if (denoised) spec.channelnames.insert(spec.channelnames.end(), {"denoised.R", "denoised.G", "denoised.B"});
  spec.attribute("compression", "zip");
  spec.attribute("brushtrace:exposureEV", output.exposureEv);
  spec.attribute("brushtrace:exposure", output.exposureAuto ? "auto" : "given");
  return out.open(temp, spec) && out.write_image(OIIO::TypeDesc::FLOAT, pixels.data());
}

} // namespace

void writeImage(const std::string& path, const RenderImage& image, const OutputSettings& output) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const std::string ext = lowercase(target.extension().string());
  if (ext != ".png" && ext != ".exr") throw std::runtime_error(fmt::format("{}: output must be .png or .exr", path));
  // Same extension so that OpenImageIO picks the same format; renamed over the target at the end.
  const fs::path temp = target.parent_path() / fmt::format(".{}.tmp{}{}", target.stem().string(), getpid(), ext);

  auto out = OIIO::ImageOutput::create(temp.string());
  if (!out) throw std::runtime_error(fmt::format("{}: {}", path, OIIO::geterror()));
  bool ok = false;
  if (ext == ".png") {
    const std::vector<uint8_t> pixels = displayPixels(image, output);
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
    ok = out->open(temp.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, pixels.data());
  } else {
    ok = writeExr(*out, temp.string(), image, output);
  }
  const std::string error = out->geterror();
  ok = out->close() && ok;
  if (!ok) {
    std::error_code ec;
    fs::remove(temp, ec);
    throw std::runtime_error(fmt::format("{}: cannot write image: {}", path, error.empty() ? "unknown error" : error));
  }
  std::error_code ec;
  fs::rename(temp, target, ec);
  if (ec) {
    fs::remove(temp, ec);
    throw std::runtime_error(fmt::format("{}: cannot rename the finished image into place: {}", path, ec.message()));
  }
}

} // namespace bt
