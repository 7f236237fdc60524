#include "importers/bsp/q3_textures.h"
#include "importers/textures/textures.h"
#include "scene/names.h"

#include <fmt/format.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <optional>

namespace bt::bsp {

namespace {

bool isImage(std::string_view path) {
  return !path.empty() && path[0] != '$' && path[0] != '*';
}

std::string stripExtension(const std::string& name) {
  const size_t dot = name.find_last_of('.');
  const size_t slash = name.find_last_of('/');
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) return name.substr(0, dot);
  return name;
}

} // namespace

void resolveQuake3Materials(std::vector<Material>& materials, const Quake3Shaders& shaders, const GameFiles& files,
                            Diagnostics& diagnostics, std::vector<std::string>* filesRead) {
  auto noteRead = [&](std::string_view name) {
    if (!filesRead) return;
    if (const auto file = files.fileHolding(name)) filesRead->push_back(file->string());
  };
  for (Material& m : materials) {
    // Quake 3 draws an image's alpha only where the shader says how.
    const auto shader = shaders.find(lowercase(m.name));
    m.alphaTest = shader != shaders.end() ? shader->second.alphaTest : AlphaTest::None;
    m.blend = shader != shaders.end() ? shader->second.blend : ShaderBlend::Opaque;
    std::vector<std::string> candidates;
    if (shader != shaders.end() && !shader->second.image.empty()) candidates.push_back(stripExtension(shader->second.image));
    candidates.push_back(stripExtension(m.name));
    for (const std::string& base : candidates) {
      for (const char* ext : {".tga", ".jpg", ".png"}) {
        const std::string file = base + ext;
        const auto bytes = files.read(file);
        if (!bytes) continue;
        noteRead(file);
        Image image;
        try {
          image = decodeImage(*bytes, file);
        } catch (const ImportError& e) {
          diagnostics.push_back(
              {Severity::Warning, file, 0, 0, "cannot decode image for shader " + m.name + ": " + e.diagnostic().message});
          continue;
        }
        m.width = image.width;
        m.height = image.height;
        m.baseColor = std::move(image);
        m.source = TextureSource::LooseImage;
        m.sourcePath = file;
        break;
      }
      if (!m.missing()) break;
    }
  }
}

void resolveQuake3Materials(std::vector<Material>& materials, const GameFiles& files, Diagnostics& diagnostics,
                            std::vector<std::string>* filesRead) {
  resolveQuake3Materials(materials, readQuake3Shaders(files, diagnostics, filesRead), files, diagnostics, filesRead);
}

namespace {

// ParseSkyParms' `suf`: the order Sky keeps the box's materials in.
constexpr const char* kSkySuffixes[6] = {"rt", "bk", "lf", "ft", "up", "dn"};

// The six sides of a far box; fewer where an image is missing or unreadable (named in `missing`).
std::vector<Material> readFarBox(const std::string& farbox, const GameFiles& files, std::vector<std::string>& missing,
                                 std::vector<std::string>* filesRead) {
  std::vector<Material> sides;
  for (const char* suffix : kSkySuffixes) {
    const size_t before = sides.size();
    std::vector<std::string> tried;
    for (const char* ext : {".tga", ".jpg", ".png"}) {
      const std::string file = fmt::format("{}_{}{}", farbox, suffix, ext);
      const auto bytes = files.read(file);
      if (!bytes) {
        tried.push_back(file);
        continue;
      }
      if (filesRead)
        if (const auto holder = files.fileHolding(file)) filesRead->push_back(holder->string());
      Material side;
      try {
        side.baseColor = decodeImage(*bytes, file);
      } catch (const ImportError& e) {
        tried.push_back(fmt::format("{} ({})", file, e.diagnostic().message));
        continue;
      }
      side.name = side.sourcePath = file;
      side.width = side.baseColor.width, side.height = side.baseColor.height;
      side.source = TextureSource::LooseImage;
      side.alphaTest = AlphaTest::None;
      sides.push_back(std::move(side));
      break;
    }
    if (sides.size() == before) missing.insert(missing.end(), tried.begin(), tried.end());
  }
  return sides;
}

// One colour in every direction: six 1x1 sides of the image's mean colour (sRGB bytes averaged).
std::vector<Material> flatSky(const Material& shader) {
  glm::dvec3 sum(0.0);
  const size_t texels = shader.baseColor.rgba.size() / 4;
  for (size_t i = 0; i < texels; ++i)
    sum += glm::dvec3(shader.baseColor.rgba[i * 4], shader.baseColor.rgba[i * 4 + 1], shader.baseColor.rgba[i * 4 + 2]);
  const glm::dvec3 mean = sum / double(std::max<size_t>(texels, 1));
  Material side;
  side.name = shader.name + " (mean colour)";
  side.sourcePath = shader.sourcePath;
  side.width = side.height = 1;
  side.source = shader.source;
  side.alphaTest = AlphaTest::None;
  side.baseColor.width = side.baseColor.height = 1;
  side.baseColor.rgba = {uint8_t(std::lround(mean.x)), uint8_t(std::lround(mean.y)), uint8_t(std::lround(mean.z)), 255};
  return std::vector<Material>(6, side);
}

} // namespace

void loadQuake3Sky(Scene& scene, const GameFiles& files, const Quake3Shaders& shaders, std::vector<std::string>* filesRead) {
  // A level has one sky shader in practice; ioquake3 would draw each one's box on its own faces.
  std::optional<uint32_t> shader;
  std::string farbox;
  for (const Face& face : scene.faces) {
    if (face.material >= scene.materials.size()) continue;
    const auto it = shaders.find(lowercase(scene.materials[face.material].name));
    if (it == shaders.end() || !it->second.skyBox) continue;
    shader = face.material, farbox = *it->second.skyBox;
    break;
  }
  if (!shader) return;
  const std::string name = scene.materials[*shader].name;
  std::vector<std::string> missing;
  std::vector<Material> sides;
  if (!farbox.empty()) {
    sides = readFarBox(farbox, files, missing, filesRead);
    if (!missing.empty()) {
      std::string list;
      for (const std::string& file : missing) list += (list.empty() ? "" : ", ") + file;
      scene.diagnostics.push_back(Diagnostic{Severity::Warning, scene.sourcePath, 0, 0,
                                             fmt::format("sky box '{}' of shader '{}' not drawn: no image for {}; the sky shows the "
                                                         "mean colour of the shader's image instead",
                                                         farbox, name, list)});
      sides.clear();
    }
  }
  if (sides.empty() && !scene.materials[*shader].missing()) sides = flatSky(scene.materials[*shader]);
  if (sides.empty()) return;
  const bool box = !farbox.empty() && missing.empty();
  scene.sky = Sky{Sky::Kind::BoxClamped, box ? farbox : name, uint32_t(scene.materials.size())};
  for (Material& side : sides) scene.materials.push_back(std::move(side));
}

} // namespace bt::bsp
