// Loose images (PNG, TGA, JPG, ...) through OpenImageIO, converted to 8-bit RGBA.
#include "importers/textures/textures.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

namespace bt {

namespace {
[[noreturn]] void fail(const std::filesystem::path& path, const std::string& message) {
  throw ImportError(Diagnostic{Severity::Error, path.string(), 0, 0, message});
}

// Texture replacements of 8k are common; anything past this is not a texture.
constexpr int kMaxImageSide = 16384;
} // namespace

Image loadImage(const std::filesystem::path& path) {
  auto input = OIIO::ImageInput::open(path.string());
  if (!input) fail(path, fmt::format("cannot read image: {}", OIIO::geterror()));
  const OIIO::ImageSpec& spec = input->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.width > kMaxImageSide || spec.height > kMaxImageSide ||
      spec.nchannels <= 0 || spec.depth != 1)
    fail(path, fmt::format("unsupported image size {}x{}x{} with {} channels", spec.width, spec.height, spec.depth,
                           spec.nchannels));

  const int channels = spec.nchannels;
  std::vector<uint8_t> pixels(static_cast<size_t>(spec.width) * spec.height * channels);
  if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, pixels.data()))
    fail(path, fmt::format("cannot decode image: {}", input->geterror()));
  input->close();

  // Grey, grey+alpha, RGB or RGBA (extra channels ignored) to RGBA.
  Image image;
  image.width = spec.width;
  image.height = spec.height;
  image.rgba.resize(static_cast<size_t>(image.width) * image.height * 4);
  const int alphaChannel = spec.alpha_channel >= 0 ? spec.alpha_channel : (channels == 2 ? 1 : channels >= 4 ? 3 : -1);
  for (size_t i = 0, n = static_cast<size_t>(image.width) * image.height; i < n; ++i) {
    const uint8_t* src = &pixels[i * channels];
    uint8_t* dst = &image.rgba[i * 4];
    if (channels < 3) {
      dst[0] = dst[1] = dst[2] = src[0];
    } else {
      dst[0] = src[0];
      dst[1] = src[1];
      dst[2] = src[2];
    }
    dst[3] = alphaChannel >= 0 && alphaChannel < channels ? src[alphaChannel] : 255;
  }
  return image;
}

} // namespace bt
