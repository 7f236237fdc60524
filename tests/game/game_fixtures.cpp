#include "tests/game/game_fixtures.h"

#include <zip.h>

#include <algorithm>

#include <fstream>
#include <stdexcept>

namespace bt::test {

namespace {
void putU32(std::vector<uint8_t>& out, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) out[at + i] = static_cast<uint8_t>(v >> (8 * i));
}
} // namespace

std::vector<uint8_t> makePak(const std::vector<ArchiveEntry>& entries) {
  std::vector<uint8_t> out(12, 0);
  std::vector<uint8_t> directory;
  for (const ArchiveEntry& e : entries) {
    std::vector<uint8_t> record(64, 0);
    std::copy(e.name.begin(), e.name.begin() + static_cast<ptrdiff_t>(std::min<size_t>(e.name.size(), 55)), record.begin());
    putU32(record, 56, static_cast<uint32_t>(out.size()));
    putU32(record, 60, static_cast<uint32_t>(e.data.size()));
    out.insert(out.end(), e.data.begin(), e.data.end());
    directory.insert(directory.end(), record.begin(), record.end());
  }
  std::copy_n("PACK", 4, out.begin());
  putU32(out, 4, static_cast<uint32_t>(out.size()));
  putU32(out, 8, static_cast<uint32_t>(directory.size()));
  out.insert(out.end(), directory.begin(), directory.end());
  return out;
}

void writePak(const std::filesystem::path& path, const std::vector<ArchiveEntry>& entries) {
  std::filesystem::create_directories(path.parent_path());
  const std::vector<uint8_t> bytes = makePak(entries);
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

void writePk3(const std::filesystem::path& path, const std::vector<ArchiveEntry>& entries) {
  std::filesystem::create_directories(path.parent_path());
  int error = 0;
  zip_t* zip = zip_open(path.string().c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
  if (!zip) throw std::runtime_error("cannot create " + path.string());
  for (const ArchiveEntry& e : entries) {
    zip_source_t* source = zip_source_buffer(zip, e.data.data(), e.data.size(), 0);
    if (!source || zip_file_add(zip, e.name.c_str(), source, ZIP_FL_OVERWRITE) < 0)
      throw std::runtime_error("cannot add " + e.name + " to " + path.string());
  }
  if (zip_close(zip) != 0) throw std::runtime_error("cannot write " + path.string());
}

std::vector<uint8_t> bytesOf(const std::string& text) {
  return {text.begin(), text.end()};
}

std::vector<uint8_t> testPalette() {
  std::vector<uint8_t> palette(768);
  for (int i = 0; i < 256; ++i) {
    palette[i * 3] = static_cast<uint8_t>(i);
    palette[i * 3 + 1] = static_cast<uint8_t>(255 - i);
    palette[i * 3 + 2] = 77;
  }
  return palette;
}

std::vector<uint8_t> testPalettePcx() {
  std::vector<uint8_t> pcx(128, 0);
  pcx[0] = 0x0A;       // PCX signature
  pcx.push_back(0);    // a token of image data
  pcx.push_back(0x0C); // the 256-colour palette follows
  const std::vector<uint8_t> palette = testPalette();
  pcx.insert(pcx.end(), palette.begin(), palette.end());
  return pcx;
}

} // namespace bt::test
