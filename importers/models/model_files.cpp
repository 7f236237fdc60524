#include "importers/models/model_files.h"

#include "importers/bsp/bsp_import.h"
#include "importers/bsp/q3_textures.h"
#include "importers/textures/textures.h"
#include "quake/alias_models.h"
#include "scene/names.h"

#include <algorithm>
#include <filesystem>
#include <map>

namespace bt::models {
namespace {

std::string extensionOf(const std::string& path) {
  return lowercase(std::filesystem::path(path).extension().string());
}

// A Quake skin through the game palette, its fullbright indices (224..255) glowing as they do on
// the game's textures (importers/textures miptex).
Material paletteSkin(const quake::AliasModel& model, const Palette& palette, const std::string& name) {
  Material m;
  m.name = name;
  m.width = model.skinWidth;
  m.height = model.skinHeight;
  m.source = TextureSource::Miptex;
  m.baseColor = Image{model.skinWidth, model.skinHeight, std::vector<uint8_t>(model.skinIndices.size() * 4, 255)};
  Image glow{model.skinWidth, model.skinHeight, std::vector<uint8_t>(model.skinIndices.size() * 4, 0)};
  bool glows = false;
  for (size_t i = 0; i < model.skinIndices.size(); ++i) {
    const uint8_t* rgb = &palette.rgb[size_t(model.skinIndices[i]) * 3];
    std::copy_n(rgb, 3, &m.baseColor.rgba[i * 4]);
    if (model.skinIndices[i] >= 224) {
      std::copy_n(rgb, 3, &glow.rgba[i * 4]);
      glow.rgba[i * 4 + 3] = 255;
      glows = true;
    }
  }
  if (glows) m.emissive = std::move(glow);
  return m;
}

uint32_t addMaterial(Scene& scene, Material m) {
  scene.materials.push_back(std::move(m));
  return uint32_t(scene.materials.size() - 1);
}

// The material a skin or shader name names: the level's own when it has one, else loaded now.
// Quake 3 names an image with its extension, and the renderer looks it up without (R_FindShader).
uint32_t skinMaterial(const game::GameInstall& install, std::string name, bool quake3, bool load, Scene& scene) {
  if (quake3) name = std::filesystem::path(name).replace_extension().generic_string();
  if (const auto existing = scene.findMaterial(name)) return *existing;
  Material m;
  m.name = name;
  if (!load) {
    // --no-textures: the placeholder, as every texture of the level
  } else if (quake3) {
    std::vector<Material> one{m};
    std::vector<std::string> filesRead;
    bsp::resolveQuake3Materials(one, install.files, scene.diagnostics, &filesRead);
    for (const std::string& f : filesRead) scene.addInputFile(f);
    m = std::move(one.front());
  } else if (const auto bytes = install.files.read(name)) {
    try {
      const Image image = decodeImage(*bytes, name);
      m.baseColor = image;
      m.width = image.width;
      m.height = image.height;
      m.source = TextureSource::LooseImage;
      m.sourcePath = install.files.describe(name).value_or(name);
    } catch (const ImportError& e) {
      scene.diagnostics.push_back({Severity::Warning, e.diagnostic().file, 0, 0, "model skin not drawn: " + e.diagnostic().message});
    }
  }
  if (m.missing()) m.baseColor = checkerPlaceholder(m.width, m.height);
  return addMaterial(scene, std::move(m));
}

LoadedModel aliasParts(const quake::AliasModel& model, const std::vector<uint32_t>& materials, const Scene& scene) {
  LoadedModel loaded;
  for (size_t i = 0; i < model.surfaces.size(); ++i) {
    ModelPart part;
    const Material& m = scene.materials[materials[i]];
    part.faceTemplate.material = materials[i];
    part.faceTemplate.texture = m.name;
    for (const quake::AliasCorner& c : model.surfaces[i].corners)
      part.corners.push_back({dvec3(c.position), double(c.st.x) * m.width, double(c.st.y) * m.height});
    loaded.parts.push_back(std::move(part));
  }
  return loaded;
}

LoadedModel loadAlias(const game::GameInstall& install, const std::string& path, int skin, const std::vector<uint8_t>& bytes, bool load,
                      Scene& scene) {
  const std::string where = install.files.describe(path).value_or(path);
  const quake::AliasModel model = quake::readAliasModel(bytes, where, skin);
  std::vector<uint32_t> materials;
  if (!model.skinIndices.empty()) { // .mdl: its own skin, through the game palette
    std::string from;
    std::optional<Palette> palette;
    if (load) palette = game::installPalette(install, false, scene.sourcePath, scene.diagnostics, &from);
    if (!from.empty()) scene.addInputFile(from);
    const std::string name = skin > 0 ? path + "#" + std::to_string(skin) : path;
    Material m = palette ? paletteSkin(model, *palette, name) : Material{};
    if (palette)
      m.sourcePath = where;
    else
      m.name = name, m.baseColor = checkerPlaceholder(m.width, m.height);
    materials.assign(model.surfaces.size(), addMaterial(scene, std::move(m)));
  } else {
    const bool quake3 = extensionOf(path) == ".md3";
    for (const quake::AliasSurface& s : model.surfaces) materials.push_back(skinMaterial(install, s.skin, quake3, load, scene));
  }
  return aliasParts(model, materials, scene);
}

// Quake's b_*.bsp item models: the faces of the level's world model (model 0), each material
// renamed after the model, as each .bsp carries textures of its own.
LoadedModel loadBspModel(const game::GameInstall& install, const std::string& path, const ImportOptions& options, Scene& scene) {
  ImportOptions sub;
  sub.textures.game = options.textures.game;
  sub.textures.load = options.textures.load;
  const Scene model = bsp::importBsp(install.files.describe(path).value_or(path), sub);
  for (const std::string& f : model.inputFiles) scene.addInputFile(f);
  std::map<uint32_t, size_t> partOf; // the model's material → part
  LoadedModel loaded;
  for (const Face& f : model.faces) {
    if (f.brush == kNoBrush || model.brushes[f.brush].entity != 0 || f.winding.size() < 3) continue;
    auto [it, added] = partOf.try_emplace(f.material, loaded.parts.size());
    if (added) {
      Material m = model.materials[f.material];
      m.name = path + ":" + m.name;
      ModelPart& part = loaded.parts.emplace_back();
      part.faceTemplate.texture = f.texture;
      part.faceTemplate.material = addMaterial(scene, std::move(m));
    }
    ModelPart& part = loaded.parts[it->second];
    auto corner = [&](const dvec3& p) { return MeshVertex{p, f.frame.s(p), f.frame.t(p)}; };
    for (size_t k = 1; k + 1 < f.winding.size(); ++k)
      for (const dvec3& p : {f.winding[0], f.winding[k], f.winding[k + 1]}) part.corners.push_back(corner(p));
  }
  return loaded;
}

} // namespace

std::optional<LoadedModel> loadModel(const game::GameInstall& install, const std::string& path, int skin, const ImportOptions& options,
                                     Scene& scene) {
  if (!install.files.fileHolding(path)) return std::nullopt;
  if (extensionOf(path) == ".bsp") return loadBspModel(install, path, options, scene);
  const std::optional<std::vector<uint8_t>> bytes = install.files.read(path);
  if (!bytes) return std::nullopt;
  if (const auto holder = install.files.fileHolding(path)) scene.addInputFile(holder->string());
  return loadAlias(install, path, skin, *bytes, options.textures.load, scene);
}

} // namespace bt::models
