// Quake 3 shader scripts (scripts/*.shader): the parsers that pick each shader's image and sky
// box, and read the keys q3map2 lights with.
#include "importers/bsp/q3_shader_light.h"
#include "importers/bsp/q3_textures.h"

#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  // None documents an exception: a script they cannot read yields fewer shaders (and, for the
  // light keys, warnings).
  (void)bt::bsp::parseShaderImages(text);
  (void)bt::bsp::parseShaderSkyBoxes(text);
  bt::Diagnostics diagnostics;
  (void)bt::bsp::parseShaderLights(text, "fuzz.shader", diagnostics);
  return 0;
}
