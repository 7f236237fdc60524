// Game archives built in the tests: .pak files (bytes written here) and .pk3 files (libzip).
// Never game data: every entry is made by the test that needs it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace bt::test {

struct ArchiveEntry {
  std::string name;
  std::vector<uint8_t> data;
};

// A Quake .pak: "PACK", the entries' data, then the directory of 64-byte entries.
std::vector<uint8_t> makePak(const std::vector<ArchiveEntry>& entries);
void writePak(const std::filesystem::path& path, const std::vector<ArchiveEntry>& entries);
// A .pk3 (zip) with the entries, deflated.
void writePk3(const std::filesystem::path& path, const std::vector<ArchiveEntry>& entries);

std::vector<uint8_t> bytesOf(const std::string& text);
// A 768-byte palette with colour i = (i, 255 - i, 77): unlike any game's, so a texture drawn with
// it shows that it was this palette that was read.
std::vector<uint8_t> testPalette();
// The same palette at the end of a minimal 256-colour PCX (Quake 2's pics/colormap.pcx layout).
std::vector<uint8_t> testPalettePcx();

} // namespace bt::test
