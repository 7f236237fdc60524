// .map text through what `brushtrace` does with it: parse (dialect detected, or forced as
// --dialect does), build brushes, planes, windings and frames into a Scene, prepare it for a
// render. Textures are not loaded (no files are read).
//
// Input: one selector byte, then the map text. Selector % 9: 0 = detect the dialect, 1..8 =
// force MapDialect(selector - 1).
#include "importers/map/map_parser.h"
#include "importers/map/map_scene.h"
#include "tests/fuzz/fuzz_support.h"

#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const unsigned selector = data[0] % 9;
  const std::optional<bt::MapDialect> forced = selector == 0 ? std::nullopt : std::optional(static_cast<bt::MapDialect>(selector - 1));
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    const bt::map::MapDocument doc = bt::map::parseMap(text, "fuzz.map", forced);
    const bt::Scene scene = bt::map::buildScene(doc);
    bt::fuzz::prepareForRender(scene);
  } catch (const bt::ImportError&) {
    // The documented way to refuse a file. Anything else escapes and libFuzzer reports it.
  }
  return 0;
}
