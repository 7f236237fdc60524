// Quake 3 shader scripts (scripts/*.shader): the parsers that pick each shader's image and sky box.
#include "importers/bsp/q3_textures.h"

#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // Neither parser documents an exception: a script they cannot read yields fewer shaders.
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  (void)bt::bsp::parseShaderImages(text);
  (void)bt::bsp::parseShaderSkyBoxes(text);
  return 0;
}
