// Loose images (PNG, TGA, JPG, ...) through OpenImageIO, converted to 8-bit RGBA.
#include "importers/textures/textures.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <memory>
#include <mutex>

namespace bt {

namespace {
[[noreturn]] void fail(const std::string& file, const std::string& message) {
  throw ImportError(Diagnostic{Severity::Error, file, 0, 0, message});
}

// Texture replacements of 8k are common; anything past this is not a texture.
constexpr int kMaxImageSide = 16384;

// OpenImageIO 2.4 (Debian bookworm's) reads a file's ICC profile and Exif block while opening
// it, through tables that are not safe to build from two threads at once (OpenImageIO issue
// 3756): concurrent opens of LibreQuake's PNGs hung or corrupted the heap. Opening only reads
// headers, so it is serialised; decoding the pixels, the costly part, still runs in parallel.
// The texels are kept as the file stores them: OpenImageIO's PNG reader would otherwise multiply
// the colour by the alpha, which the engines never do (Quake 3's blendFunc blend weighs the
// stored colour by the stored alpha).
std::unique_ptr<OIIO::ImageInput> openImage(const std::string& name, OIIO::Filesystem::IOProxy* proxy) {
  static std::mutex openMutex;
  const std::lock_guard lock(openMutex);
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  if (proxy) config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy); // with a config, 2.4 reads the proxy from it
  return OIIO::ImageInput::open(name, &config, proxy);
}

// Reads the whole first subimage of an opened file as 8-bit RGBA: grey, grey+alpha, RGB or RGBA
// (extra channels ignored).
Image readRgba(OIIO::ImageInput& input, const std::string& file) {
  const OIIO::ImageSpec& spec = input.spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.width > kMaxImageSide || spec.height > kMaxImageSide || spec.nchannels <= 0 ||
      spec.depth != 1)
    fail(file, fmt::format("unsupported image size {}x{}x{} with {} channels", spec.width, spec.height, spec.depth, spec.nchannels));

  const int channels = spec.nchannels;
  std::vector<uint8_t> pixels(static_cast<size_t>(spec.width) * spec.height * channels);
  if (!input.read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, pixels.data()))
    fail(file, fmt::format("cannot decode image: {}", input.geterror()));
  input.close();

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
} // namespace

Image loadImage(const std::filesystem::path& path) {
  auto input = openImage(path.string(), nullptr);
  if (!input) fail(path.string(), fmt::format("cannot read image: {}", OIIO::geterror()));
  return readRgba(*input, path.string());
}

Image decodeImage(std::span<const uint8_t> bytes, const std::string& name) {
  // IOMemReader only reads, but 2.4 takes a non-const pointer.
  OIIO::Filesystem::IOMemReader proxy(const_cast<uint8_t*>(bytes.data()), bytes.size());
  auto input = openImage(name, &proxy);
  if (!input) fail(name, fmt::format("cannot read image: {}", OIIO::geterror()));
  return readRgba(*input, name);
}

} // namespace bt
