// The games' model files (quake/alias_models.h): Quake .mdl, Quake 2 .md2, Quake 3 .md3, told
// apart by their magic as the importer tells them. Input: one selector byte (the .mdl skin
// asked for, % 4), then the file.
#include "quake/alias_models.h"
#include "scene/diagnostics.h"

#include <cstdint>
#include <span>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  try {
    const bt::quake::AliasModel model = bt::quake::readAliasModel(std::span(data + 1, size - 1), "fuzz.mdl", data[0] % 4);
    size_t corners = 0;
    for (const bt::quake::AliasSurface& s : model.surfaces) corners += s.corners.size();
    (void)corners;
  } catch (const bt::ImportError&) {
    // the documented way to refuse a file
  }
  return 0;
}
