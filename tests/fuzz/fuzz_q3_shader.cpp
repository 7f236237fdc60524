// Quake 3 shader scripts (scripts/*.shader): the one reader of each shader's image, alphaFunc,
// sky box and the keys q3map2 lights with.
#include "importers/bsp/q3_shaders.h"

#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  // It documents no exception: a script it cannot read yields fewer shaders and warnings.
  bt::Diagnostics diagnostics;
  (void)bt::bsp::parseShaderScript(text, "fuzz.shader", diagnostics);
  return 0;
}
