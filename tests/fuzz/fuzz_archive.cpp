// Game archives: the .pak reader (directory, every entry) and, selector bit 0 set, the same bytes
// as a .pk3 through libzip, each entry read (libzip is the parser; what is fuzzed is our use of it:
// sizes, names, errors). Archives of pak files and zips are what a game install is made of.
#include "importers/bsp/pk3.h"
#include "importers/game/archive.h"
#include "scene/diagnostics.h"

#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t selector = data[0];
  std::vector<uint8_t> bytes(data + 1, data + size);
  try {
    if (selector & 1) {
      // libzip opens files by name: one file per process, rewritten each run.
      const std::string path = "/tmp/fuzz_archive_" + std::to_string(::getpid()) + ".pk3";
      std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
      const bt::bsp::Pk3Archive pk3(path);
      for (const std::string& name : pk3.names()) (void)pk3.read(name, uint64_t{64} << 20);
    } else {
      const bt::game::PakArchive pak("fuzz.pak", std::move(bytes));
      for (const std::string& name : pak.names()) (void)pak.read(name);
    }
  } catch (const bt::ImportError&) {
    // the documented way to refuse a file
  }
  return 0;
}
