#include "importers/bsp/q3_shader_light.h"

#include "importers/bsp/shader_lexer.h"
#include "importers/textures/textures.h"
#include "scene/names.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>

namespace bt::bsp {

namespace {

std::string withoutExtension(std::string_view name) {
  const size_t dot = name.find_last_of('.');
  const size_t slash = name.find_last_of('/');
  if (dot != std::string_view::npos && (slash == std::string_view::npos || dot > slash)) name = name.substr(0, dot);
  return std::string(name);
}

// q3map2's ImageLoad: the image under any of the extensions it reads.
std::optional<Image> loadImage(const GameFiles& files, std::string_view name, Diagnostics& diagnostics,
                               std::vector<std::string>* filesRead) {
  const std::string stem = withoutExtension(name);
  for (const char* ext : {".tga", ".jpg", ".png"}) {
    const std::string file = stem + ext;
    const auto bytes = files.read(file);
    if (!bytes) continue;
    if (filesRead)
      if (const auto holder = files.fileHolding(file)) filesRead->push_back(holder->string());
    try {
      return decodeImage(*bytes, file);
    } catch (const ImportError& e) {
      diagnostics.push_back(
          {Severity::Warning, files.describe(file).value_or(file), 0, 0, "cannot decode the light image: " + e.diagnostic().message});
    }
  }
  return std::nullopt;
}

} // namespace

void setColorFromImage(Q3ShaderLight& light, const Image& image) {
  double sum[3] = {0.0, 0.0, 0.0};
  for (size_t i = 0; i + 3 < image.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) sum[c] += image.rgba[i + c];
  const double peak = std::max({sum[0], sum[1], sum[2]});
  for (int c = 0; c < 3; ++c) light.color[c] = peak == 0.0 ? 1.0f : float(sum[c] / peak);
}

void readQuake3ShaderLight(std::vector<Material>& materials, const Quake3Shaders& shaders, const GameFiles& files, Diagnostics& diagnostics,
                           std::vector<std::string>* filesRead) {
  for (Material& m : materials) {
    // A .bsp names the shader; a .map leaves out the "textures/" that q3map2 puts before it.
    auto it = shaders.find(lowercase(withoutExtension(m.name)));
    if (it == shaders.end()) it = shaders.find("textures/" + lowercase(withoutExtension(m.name)));
    if (it == shaders.end()) continue;
    m.q3 = it->second.light.light;
    m.blend = it->second.blend;
    // si->color lights surface lights and sky lights only; the images are read for those alone.
    if (m.q3.hasLightRGB || (m.q3.surfaceLight <= 0.0f && m.q3.skyLightValue <= 0.0f)) continue;
    for (const std::string& image : {m.q3.lightImage, it->second.light.editorImage, it->first}) {
      if (image.empty()) continue;
      if (const auto loaded = loadImage(files, image, diagnostics, filesRead)) {
        setColorFromImage(m.q3, *loaded);
        break;
      }
    }
  }
}

} // namespace bt::bsp
