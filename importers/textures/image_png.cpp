// Loose images in bt_importers_portable, the importers without OpenImageIO: PNG only, through
// libpng's simplified API (LibreQuake's textures, the largest shared map's, are PNGs). Any other
// format is an ImportError naming the file, which the material loader reports and replaces with
// the placeholder like any unreadable image. libpng applies a file's gAMA chunk where
// OpenImageIO does not, so the two builds may differ on such files; LibreQuake's have none.
#include "importers/textures/textures.h"

#include <fmt/format.h>
#include <png.h>

#include <algorithm>
#include <cctype>

namespace bt {

namespace {

[[noreturn]] void fail(const std::string& file, const std::string& message) {
  throw ImportError(Diagnostic{Severity::Error, file, 0, 0, message});
}

constexpr png_uint_32 kMaxImageSide = 16384; // as image.cpp: past this it is not a texture

bool isPng(const std::string& name) {
  std::string ext = std::filesystem::path(name).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".png";
}

// Decodes an image whose header png_image_begin_read_* has read, as 8-bit RGBA.
Image finishRead(png_image& png, const std::string& file) {
  if (PNG_IMAGE_FAILED(png)) fail(file, fmt::format("cannot read image: {}", png.message));
  if (png.width == 0 || png.height == 0 || png.width > kMaxImageSide || png.height > kMaxImageSide) {
    png_image_free(&png);
    fail(file, fmt::format("unsupported image size {}x{}", png.width, png.height));
  }
  png.format = PNG_FORMAT_RGBA;
  Image image;
  image.width = static_cast<int>(png.width);
  image.height = static_cast<int>(png.height);
  image.rgba.resize(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, image.rgba.data(), 0, nullptr)) fail(file, fmt::format("cannot decode image: {}", png.message));
  return image;
}

[[noreturn]] void notPng(const std::string& file) {
  fail(file, "cannot read image: this build of brushtrace reads PNG images only (it has no OpenImageIO)");
}

} // namespace

Image loadImage(const std::filesystem::path& path) {
  const std::string file = path.string();
  if (!isPng(file)) notPng(file);
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png_image_begin_read_from_file(&png, file.c_str());
  return finishRead(png, file);
}

Image decodeImage(std::span<const uint8_t> bytes, const std::string& name) {
  if (!isPng(name)) notPng(name);
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png_image_begin_read_from_memory(&png, bytes.data(), bytes.size());
  return finishRead(png, name);
}

} // namespace bt
