#include "importers/textures/png_indices.h"

#include <png.h>

#include <cstdio>
#include <memory>

namespace bt {

namespace {

struct PngReader {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~PngReader() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

std::optional<std::vector<uint8_t>> readRows(PngReader& r, png_uint_32 width, png_uint_32 height) {
  std::vector<uint8_t> indices(size_t(width) * height);
  std::vector<png_bytep> rows(height);
  for (png_uint_32 y = 0; y < height; ++y) rows[y] = &indices[size_t(y) * width];
  if (setjmp(png_jmpbuf(r.png))) return std::nullopt;
  png_read_image(r.png, rows.data());
  return indices;
}

} // namespace

// libpng's simplified API would hand back indices into a colour map of its own making, not the
// file's palette order; the low-level API reads the file's indices as they are.
std::optional<std::vector<uint8_t>> readPngPaletteIndices(const std::filesystem::path& file) {
  std::unique_ptr<std::FILE, FileCloser> f(std::fopen(file.string().c_str(), "rb"));
  if (!f) return std::nullopt;
  png_byte signature[8];
  if (std::fread(signature, 1, 8, f.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0) return std::nullopt;
  PngReader r;
  // Silent: the image has been decoded already, and its problems reported there.
  r.png = png_create_read_struct(
      PNG_LIBPNG_VER_STRING, nullptr, [](png_structp p, png_const_charp) { png_longjmp(p, 1); }, [](png_structp, png_const_charp) {});
  if (!r.png) return std::nullopt;
  r.info = png_create_info_struct(r.png);
  if (!r.info) return std::nullopt;
  // libpng reports errors by longjmp: locals touched between a setjmp and the jump are
  // indeterminate after it, so each setjmp comes after the vectors are last resized.
  if (setjmp(png_jmpbuf(r.png))) return std::nullopt;
  png_init_io(r.png, f.get());
  png_set_sig_bytes(r.png, 8);
  png_read_info(r.png, r.info);
  const png_uint_32 width = png_get_image_width(r.png, r.info), height = png_get_image_height(r.png, r.info);
  if (png_get_color_type(r.png, r.info) != PNG_COLOR_TYPE_PALETTE || png_get_bit_depth(r.png, r.info) != 8 ||
      png_get_interlace_type(r.png, r.info) != PNG_INTERLACE_NONE || width == 0 || height == 0 || width > 16384 || height > 16384)
    return std::nullopt;
  return readRows(r, width, height);
}

} // namespace bt
