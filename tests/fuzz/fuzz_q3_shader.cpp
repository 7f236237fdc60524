// Quake 3 shader scripts (scripts/*.shader): the parser that picks each shader's image.
#include "importers/bsp/q3_textures.h"

#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // parseShaderImages documents no exception: a script it cannot read yields fewer shaders.
  (void)bt::bsp::parseShaderImages(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
