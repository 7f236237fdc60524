// Loose images (PNG, JPEG, TGA, BMP, ...) as 8-bit RGBA, through the decoders OpenImageIO used
// underneath, without OpenImageIO: its libraries (gdal, opencv, ffmpeg, ... 260 shared objects)
// cost every brushtrace command half a second in the dynamic loader (issue 21).
//   - PNG through libpng, with the transforms OpenImageIO's PNG reader asked for (palette and
//     low bit depths expanded, tRNS made alpha, no gamma applied, 16 bits scaled as OpenImageIO
//     converts them);
//   - JPEG through libjpeg-turbo, with libjpeg's default decoding, as OpenImageIO read them;
//   - the rest (TGA, BMP, PSD, GIF, ...) through stb_image.
// The format is picked from the file's first bytes, so a texture whose extension lies still
// loads (OpenImageIO tried every reader when the one its extension named failed).
// The texels are kept as the file stores them: no premultiplication by alpha, which the engines
// never do (Quake 3's blendFunc blend weighs the stored colour by the stored alpha), and no
// colour management (a gAMA chunk or ICC profile is ignored, as the engines ignore it).
// Every decoder works on the caller's bytes with state of its own, so textures decode in
// parallel.
#include "importers/textures/textures.h"

#include <fmt/format.h>
#include <jpeglib.h>
#include <png.h>

#include <algorithm>
#include <cctype>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC // private to this file: nothing else may see or clash with its symbols
#define STBI_NO_STDIO    // files are read by readTextureFile, pk3 members by the archive
#define STBI_NO_LINEAR   // 8-bit only: no HDR
#define STBI_NO_HDR
#define STBI_NO_PNG // PNG and JPEG go to the libraries above; stb's own decoders differ from them
#define STBI_NO_JPEG
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#endif
#include <stb/stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace bt {

namespace {

[[noreturn]] void fail(const std::string& file, const std::string& message) {
  throw ImportError(Diagnostic{Severity::Error, file, 0, 0, message});
}

// Texture replacements of 8k are common; anything past this is not a texture.
constexpr int kMaxImageSide = 16384;

void checkSize(int width, int height, int channels, const std::string& file) {
  if (width <= 0 || height <= 0 || width > kMaxImageSide || height > kMaxImageSide)
    fail(file, fmt::format("unsupported image size {}x{} with {} channels", width, height, channels));
}

// 8-bit pixels of 1 (grey), 2 (grey, alpha), 3 (RGB) or 4 (RGBA) channels as RGBA.
Image toRgba(int width, int height, int channels, const uint8_t* pixels) {
  Image image;
  image.width = width;
  image.height = height;
  const size_t n = size_t(width) * size_t(height);
  image.rgba.resize(n * 4);
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* src = &pixels[i * size_t(channels)];
    uint8_t* dst = &image.rgba[i * 4];
    dst[0] = src[0];
    dst[1] = src[channels < 3 ? 0 : 1];
    dst[2] = src[channels < 3 ? 0 : 2];
    dst[3] = channels == 2 ? src[1] : channels == 4 ? src[3] : 255;
  }
  return image;
}

// ---- PNG (libpng) ----

// libpng reports errors by longjmp to the jump buffer set around the calls below, which keep
// only plain data on their frames for that reason; the message is kept for the ImportError.
struct PngRead {
  std::span<const uint8_t> bytes;
  size_t offset = 0;
  char message[200] = "";
};

void pngError(png_structp png, png_const_charp message) {
  auto* read = static_cast<PngRead*>(png_get_error_ptr(png));
  std::snprintf(read->message, sizeof(read->message), "%s", message);
  png_longjmp(png, 1);
}

void pngWarning(png_structp, png_const_charp) {} // e.g. a bad iCCP chunk: the texels are still good

void pngReadBytes(png_structp png, png_bytep out, size_t size) {
  auto* read = static_cast<PngRead*>(png_get_io_ptr(png));
  if (size > read->bytes.size() - read->offset) png_error(png, "file truncated");
  std::memcpy(out, read->bytes.data() + read->offset, size);
  read->offset += size;
}

// OpenImageIO read 16-bit PNGs as 16 bits and converted them to 8 with rounding.
uint8_t sixteenToEight(uint16_t v) {
  return uint8_t((uint32_t(v) * 255u + 32767u) / 65535u);
}

Image decodePng(std::span<const uint8_t> bytes, const std::string& file) {
  PngRead read{bytes};
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &read, pngError, pngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    fail(file, "cannot read image: out of memory");
  }
  std::vector<uint8_t> pixels; // before setjmp: its destructor must not be skipped by longjmp
  std::vector<png_bytep> rows;
  int width = 0, height = 0, channels = 0, depth = 0;
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    fail(file, fmt::format("cannot decode image: {}", read.message));
  }
  png_set_read_fn(png, &read, pngReadBytes);
  png_set_user_limits(png, kMaxImageSide, kMaxImageSide);
  png_read_info(png, info);
  png_set_expand(png); // palette -> RGB, grey of 1, 2, 4 bits -> 8, tRNS -> alpha
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  width = int(png_get_image_width(png, info));
  height = int(png_get_image_height(png, info));
  channels = png_get_channels(png, info);
  depth = png_get_bit_depth(png, info);
  const size_t rowBytes = png_get_rowbytes(png, info);
  pixels.resize(rowBytes * size_t(height));
  rows.resize(size_t(height));
  for (int y = 0; y < height; ++y) rows[size_t(y)] = pixels.data() + rowBytes * size_t(y);
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);

  checkSize(width, height, channels, file);
  if (depth == 16) { // big-endian samples
    for (size_t i = 0, n = pixels.size() / 2; i < n; ++i) pixels[i] = sixteenToEight(uint16_t(pixels[2 * i] << 8 | pixels[2 * i + 1]));
  }
  return toRgba(width, height, channels, pixels.data());
}

// ---- JPEG (libjpeg-turbo) ----

struct JpegError {
  jpeg_error_mgr manager; // first: libjpeg's callbacks get a pointer to it
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = "";
};

void jpegError(j_common_ptr info) {
  auto* error = reinterpret_cast<JpegError*>(info->err);
  error->manager.format_message(info, error->message);
  std::longjmp(error->jump, 1);
}

void jpegMessage(j_common_ptr, int) {} // warnings (corrupt data past the end, ...) as OpenImageIO: ignored

// CMYK (Adobe's, stored inverted) as OpenImageIO converted it: R = C*K, G = M*K, B = Y*K.
void cmykToRgb(std::vector<uint8_t>& pixels) {
  for (size_t i = 0, n = pixels.size() / 4; i < n; ++i) {
    const float k = pixels[i * 4 + 3] / 255.0f;
    for (int c = 0; c < 3; ++c) pixels[i * 3 + size_t(c)] = uint8_t(pixels[i * 4 + size_t(c)] / 255.0f * k * 255.0f + 0.5f);
  }
  pixels.resize(pixels.size() / 4 * 3);
}

Image decodeJpeg(std::span<const uint8_t> bytes, const std::string& file) {
  jpeg_decompress_struct info{};
  JpegError error{};
  info.err = jpeg_std_error(&error.manager);
  error.manager.error_exit = jpegError;
  error.manager.emit_message = jpegMessage;
  std::vector<uint8_t> pixels; // before setjmp, as in decodePng
  int width = 0, height = 0, channels = 0;
  bool cmyk = false;
  if (setjmp(error.jump)) {
    jpeg_destroy_decompress(&info);
    fail(file, fmt::format("cannot decode image: {}", error.message));
  }
  jpeg_create_decompress(&info);
  jpeg_mem_src(&info, bytes.data(), static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&info, TRUE);
  cmyk = info.jpeg_color_space == JCS_CMYK || info.jpeg_color_space == JCS_YCCK;
  info.out_color_space = cmyk ? JCS_CMYK : info.num_components == 1 ? JCS_GRAYSCALE : JCS_RGB;
  width = int(info.image_width);
  height = int(info.image_height);
  if (width <= 0 || height <= 0 || width > kMaxImageSide || height > kMaxImageSide) {
    jpeg_destroy_decompress(&info);
    checkSize(width, height, info.num_components, file);
  }
  jpeg_start_decompress(&info);
  channels = info.output_components;
  const size_t rowBytes = size_t(width) * size_t(channels);
  pixels.resize(rowBytes * size_t(height));
  while (info.output_scanline < info.output_height) {
    JSAMPROW row = pixels.data() + rowBytes * info.output_scanline;
    jpeg_read_scanlines(&info, &row, 1);
  }
  jpeg_finish_decompress(&info);
  jpeg_destroy_decompress(&info);

  if (cmyk) {
    cmykToRgb(pixels);
    channels = 3;
  }
  return toRgba(width, height, channels, pixels.data());
}

// ---- everything else (stb_image) ----

// Where stb_image reads a TGA unlike OpenImageIO did, from the 18-byte header, the pixels are
// made OpenImageIO's: a right-to-left file is mirrored (stb_image ignores that bit); 5-bit
// colour (15/16-bit pixels or palette entries) is widened as (v << 3) | (v >> 2), not
// v * 255 / 31 (stb's, one below on some values, and invertible); OpenImageIO kept no alpha from
// a palette or from a 16-bit grey file whose descriptor names no alpha bits.
void matchOpenImageIoTga(std::span<const uint8_t> header, Image& image) {
  const uint8_t type = header[2], paletteBits = header[7], bits = header[16], descriptor = header[17];
  const bool paletted = type == 1 || type == 9, grey = type == 3 || type == 11;
  const size_t n = size_t(image.width) * size_t(image.height);
  if ((paletted && (paletteBits == 15 || paletteBits == 16)) || (!paletted && !grey && (bits == 15 || bits == 16))) {
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        uint8_t& v = image.rgba[i * 4 + size_t(c)];
        const int five = (v * 31 + 127) / 255;
        v = uint8_t(five << 3 | five >> 2);
      }
  }
  if (paletted || (grey && bits == 16 && !(descriptor & 0x08)))
    for (size_t i = 0; i < n; ++i) image.rgba[i * 4 + 3] = 255;
  if (descriptor & 0x10)
    for (int y = 0; y < image.height; ++y) {
      auto* row = reinterpret_cast<uint32_t*>(image.rgba.data()) + size_t(y) * size_t(image.width);
      std::reverse(row, row + image.width);
    }
}

// Whether a TGA's pixels end past the file's end: stb_image reads zeros there where OpenImageIO
// failed, and a cut-off texture is better reported than drawn half black.
bool tgaTruncated(std::span<const uint8_t> bytes) {
  if (bytes.size() < 18) return true;
  const uint8_t type = bytes[2], bits = bytes[16];
  const size_t paletteBytes = bytes[1] ? size_t(bytes[5] | bytes[6] << 8) * ((bytes[7] + 7u) / 8u) : 0;
  const size_t pixelBytes = (bits + 7u) / 8u, pixels = size_t(bytes[12] | bytes[13] << 8) * size_t(bytes[14] | bytes[15] << 8);
  size_t at = 18 + bytes[0] + paletteBytes;
  if (type < 8) return at + pixels * pixelBytes > bytes.size();
  for (size_t done = 0; done < pixels;) { // run-length packets: a count byte, then one pixel (a run) or count pixels
    if (at >= bytes.size()) return true;
    const size_t count = (bytes[at] & 0x7fu) + 1u;
    at += 1 + (bytes[at] & 0x80u ? 1u : count) * pixelBytes;
    done += count;
  }
  return at > bytes.size();
}

bool isTga(const std::string& file) {
  std::string ext = std::filesystem::path(file).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".tga";
}

Image decodeOther(std::span<const uint8_t> bytes, const std::string& file) {
  int width = 0, height = 0, channels = 0;
  if (bytes.size() > size_t(std::numeric_limits<int>::max())) fail(file, "cannot read image: file too large");
  if (!stbi_info_from_memory(bytes.data(), int(bytes.size()), &width, &height, &channels))
    fail(file, fmt::format("cannot read image: {}", stbi_failure_reason()));
  checkSize(width, height, channels, file);
  const bool tga = isTga(file);
  if (tga && tgaTruncated(bytes)) fail(file, "cannot decode image: file truncated");
  std::unique_ptr<uint8_t, void (*)(void*)> pixels(stbi_load_from_memory(bytes.data(), int(bytes.size()), &width, &height, &channels, 0),
                                                   stbi_image_free);
  if (!pixels) fail(file, fmt::format("cannot decode image: {}", stbi_failure_reason()));
  Image image = toRgba(width, height, channels, pixels.get());
  if (tga) matchOpenImageIoTga(bytes.first(18), image);
  return image;
}

Image decode(std::span<const uint8_t> bytes, const std::string& file) {
  static constexpr uint8_t kPng[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  static constexpr uint8_t kJpeg[] = {0xff, 0xd8, 0xff};
  if (bytes.size() >= sizeof(kPng) && std::memcmp(bytes.data(), kPng, sizeof(kPng)) == 0) return decodePng(bytes, file);
  if (bytes.size() >= sizeof(kJpeg) && std::memcmp(bytes.data(), kJpeg, sizeof(kJpeg)) == 0) return decodeJpeg(bytes, file);
  return decodeOther(bytes, file);
}

} // namespace

Image loadImage(const std::filesystem::path& path) {
  return decode(readTextureFile(path), path.string());
}

Image decodeImage(std::span<const uint8_t> bytes, const std::string& name) {
  return decode(bytes, name);
}

} // namespace bt
