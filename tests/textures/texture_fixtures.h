// Helpers for the textures tests: temporary folders, tiny WAD/miptex/.wal files built in memory,
// and images written with OpenImageIO.
#pragma once

#include "importers/textures/textures.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace bt::test {

// A fresh folder under the system temp dir, removed with everything in it when destroyed.
class TempDir {
public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& relative) const { return path_ / relative; }

private:
  std::filesystem::path path_;
};

// A miptex lump: header, the four mips (mip 0 = `indices`, smaller ones filled with 0), and for
// Half-Life the uint16 colour count and `ownPalette` after them.
std::vector<uint8_t> makeMiptex(const std::string& name, int width, int height, const std::vector<uint8_t>& indices,
                                const std::vector<uint8_t>* ownPalette = nullptr);

struct WadLump {
  std::string name;
  uint8_t type;
  std::vector<uint8_t> data;
};
// "WAD2" or "WAD3" with the given lumps, directory at the end.
std::vector<uint8_t> makeWad(const std::string& magic, const std::vector<WadLump>& lumps);

// A Quake 2 .wal with mip 0 = indices.
std::vector<uint8_t> makeWal(const std::string& name, int width, int height, const std::vector<uint8_t>& indices);

void writeFile(const std::filesystem::path& path, const std::vector<uint8_t>& bytes);
std::vector<uint8_t> readFile(const std::filesystem::path& path);

// The texels OpenImageIO 2.4 read from an image file in memory (colour as stored, not multiplied
// by alpha), as 8-bit RGBA: what brushtrace's loose images were before it dropped OpenImageIO
// (issue 21), the reference its own readers are held to. Throws std::runtime_error when
// OpenImageIO cannot read it.
Image readWithOpenImageIo(std::span<const uint8_t> bytes, const std::string& name);

// Writes an 8-bit image (1, 3 or 4 channels) with OpenImageIO, creating folders as needed.
void writeImage(const std::filesystem::path& path, int width, int height, int channels, const std::vector<uint8_t>& pixels);

// A Scene with a worldspawn carrying `keys` and one material per name, all still missing.
Scene makeScene(const std::filesystem::path& sourcePath, const std::vector<std::pair<std::string, std::string>>& keys,
                const std::vector<std::string>& materialNames);

int countWarnings(const Scene& scene);
// Text of all diagnostics, one per line, for failure messages.
std::string describe(const Diagnostics& diagnostics);

} // namespace bt::test
