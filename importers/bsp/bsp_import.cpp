#include "importers/bsp/bsp_import.h"
#include "importers/game/game_install.h"
#include "scene/names.h"

#include "importers/bsp/brushes.h"
#include "importers/bsp/entities.h"
#include "importers/bsp/lightmaps.h"
#include "importers/bsp/meshes.h"
#include "scene/curves.h"
#include "importers/bsp/pk3.h"
#include "importers/bsp/q3_shader_light.h"
#include "importers/bsp/q3_textures.h"
#include "importers/textures/textures.h"
#include "quake/entity_keys.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

namespace bt::bsp {

namespace {

// The model a brush entity uses: worldspawn is model 0; the others name theirs "*N".
std::optional<size_t> entityModel(const Entity& entity, const BspFile& bsp, Diagnostics& diagnostics) {
  if (entity.classname() == "worldspawn") return 0;
  const std::string* key = entity.find("model");
  if (!key || key->empty() || (*key)[0] != '*') return std::nullopt; // point entity or .mdl model
  const std::optional<int> model = quake::parseInteger(std::string_view(*key).substr(1));
  if (!model || *model <= 0 || size_t(*model) >= bsp.models.size()) {
    diagnostics.push_back({Severity::Warning, bsp.path, entity.line, 0,
                           fmt::format("entity '{}' names model \"{}\", which the file does not have ({} models); "
                                       "its brushes are skipped",
                                       entity.classname(), *key, bsp.models.size())});
    return std::nullopt;
  }
  return size_t(*model);
}

// "origin" "x y z"; brush entities are drawn at their origin, as the engines do.
dvec3 entityOrigin(const Entity& entity) {
  const std::string* value = entity.find("origin");
  return value ? quake::parseDvec3(*value).value_or(dvec3(0.0)) : dvec3(0.0);
}

std::vector<CompiledBrush> modelBrushes(const BspFile& bsp, size_t model) {
  switch (bsp.version) {
  case Version::Quake2_38: return quake2Brushes(bsp, model);
  case Version::Quake3_46: return quake3Brushes(bsp, model);
  default:
    if (auto listed = brushListBrushes(bsp, model)) return std::move(*listed);
    return hullBrushes(bsp, model);
  }
}

void translate(CompiledBrush& brush, const dvec3& offset) {
  for (CompiledSide& side : brush.sides) {
    side.plane.dist += glm::dot(side.plane.normal, offset);
    for (dvec3& p : side.winding) p += offset;
    side.frame.origin += offset; // the texture moves with the brush
  }
}

// The size Q1/HL miptex headers give each texture name (qbsp -notex keeps them; 0 when the
// compiler did not find the texture either).
std::map<std::string, std::pair<int, int>> miptexSizes(const BspFile& bsp) {
  std::map<std::string, std::pair<int, int>> sizes;
  for (const Miptex& m : bsp.miptex)
    if (m.present && m.width > 0 && m.height > 0 && m.width <= 1 << 16 && m.height <= 1 << 16)
      sizes.emplace(lowercase(m.name), std::pair{static_cast<int>(m.width), static_cast<int>(m.height)});
  return sizes;
}

// The scene sceneFromBsp builds: its materials by name, and what it skips on the way.
struct SceneBuilder {
  const BspFile& bsp;
  Scene& scene;
  std::map<std::string, std::pair<int, int>> sizes = miptexSizes(bsp);
  std::map<std::string, uint32_t> materialByName; // lowercase name -> index
  std::vector<bool> frameInTextureUnits;          // per face, Quake 3 only
  size_t q3SidesWithoutSurface = 0;
  size_t brushesWithoutVolume = 0;

  uint32_t materialFor(const std::string& name) {
    const std::string key = lowercase(name);
    auto [it, inserted] = materialByName.try_emplace(key, static_cast<uint32_t>(scene.materials.size()));
    if (inserted) {
      Material m;
      m.name = name;
      if (const auto s = sizes.find(key); s != sizes.end()) std::tie(m.width, m.height) = s->second;
      scene.materials.push_back(std::move(m));
    }
    return it->second;
  }

  void addBrush(CompiledBrush& compiled, uint32_t entity, const dvec3& offset) {
    if (!hasVolume(compiled)) {
      ++brushesWithoutVolume;
      return;
    }
    if (offset != dvec3(0.0)) translate(compiled, offset);
    bt::Brush brush;
    brush.entity = entity;
    brush.firstFace = static_cast<uint32_t>(scene.faces.size());
    for (CompiledSide& side : compiled.sides) {
      const uint32_t material = materialFor(side.texture);
      if (bsp.version == Version::Quake3_46 && !side.hasSurface) ++q3SidesWithoutSurface;
      bt::Face face;
      face.brush = static_cast<uint32_t>(scene.brushes.size());
      face.material = material;
      face.texture = std::move(side.texture);
      face.plane = side.plane;
      face.frame = side.frame;
      face.surface = side.surface;
      face.winding = std::move(side.winding);
      for (const dvec3& p : face.winding) brush.bounds.grow(p);
      frameInTextureUnits.push_back(side.frameInTextureUnits);
      scene.faces.push_back(std::move(face));
    }
    brush.faceCount = static_cast<uint32_t>(scene.faces.size()) - brush.firstFace;
    scene.bounds.grow(brush.bounds);
    scene.brushes.push_back(brush);
  }

  void warnAboutSkipped(const MeshCounts& meshes, bool worldClaimed) {
    if (meshes.skipped > 0)
      scene.diagnostics.push_back(
          {Severity::Warning, bsp.path, 0, 0,
           fmt::format("{} patch(es) skipped: sizes the engine refuses (each side odd, 3 to {})", meshes.skipped, kPatchMaxGridSize)});
    if (!worldClaimed && !bsp.models.empty())
      scene.diagnostics.push_back(
          {Severity::Warning, bsp.path, 0, 0, "the entities lump has no worldspawn; the world model (model 0) is not imported"});
    if (brushesWithoutVolume > 0)
      scene.diagnostics.push_back({Severity::Warning, bsp.path, 0, 0,
                                   fmt::format("{} brush(es) skipped: thinner than 0.01 units between two of their sides "
                                               "(no volume; the file's planes are corrupt)",
                                               brushesWithoutVolume)});
    if (q3SidesWithoutSurface > 0)
      scene.diagnostics.push_back({Severity::Note, bsp.path, 0, 0,
                                   fmt::format("{} brush sides have no draw surface lying on them (hidden, nodraw or caulk); they get a "
                                               "paraxial texture frame",
                                               q3SidesWithoutSurface)});
  }

  // Quake 3's frames are in texture units until the textures' sizes are known.
  void scaleFramesToTextures() {
    for (size_t f = 0; f < scene.faces.size(); ++f) {
      if (!frameInTextureUnits[f]) continue;
      bt::Face& face = scene.faces[f];
      const Material& m = scene.materials[face.material];
      face.frame.tangent *= static_cast<double>(m.width);
      face.frame.bitangent *= static_cast<double>(m.height);
    }
  }
};

} // namespace

Scene sceneFromBsp(const BspFile& bsp, const MaterialResolver& resolve, const std::optional<std::vector<uint8_t>>& litFile,
                   double curveMaxError) {
  Scene scene;
  scene.sourcePath = bsp.path;
  scene.format = toString(bsp.version);
  scene.entities = parseEntities(bsp.entities, bsp.path);
  SceneBuilder builder{bsp, scene};
  bool worldClaimed = false;
  std::vector<ModelPlacement> placements;
  MeshCounts meshes;

  for (size_t e = 0; e < scene.entities.size(); ++e) {
    Entity& entity = scene.entities[e];
    entity.firstBrush = static_cast<uint32_t>(scene.brushes.size());
    const std::optional<size_t> model = entityModel(entity, bsp, scene.diagnostics);
    if (!model || (*model == 0 && worldClaimed) || bsp.models.empty()) continue;
    worldClaimed |= *model == 0;
    std::vector<CompiledBrush> brushes = modelBrushes(bsp, *model);
    const dvec3 offset = *model == 0 ? dvec3(0.0) : entityOrigin(entity);
    placements.push_back({*model, static_cast<uint32_t>(e), offset});
    for (CompiledBrush& compiled : brushes) builder.addBrush(compiled, static_cast<uint32_t>(e), offset);
    entity.brushCount = static_cast<uint32_t>(scene.brushes.size()) - entity.firstBrush;
    if (bsp.version == Version::Quake3_46) {
      addQuake3Meshes(
          bsp, bsp.models[*model], uint32_t(e), offset, curveMaxError, scene,
          [&](int32_t shader) { return builder.materialFor(bsp.shaders[size_t(shader)].name); }, meshes);
      builder.frameInTextureUnits.resize(scene.faces.size(), true); // drawverts' st are in texture units
    }
  }
  builder.warnAboutSkipped(meshes, worldClaimed);

  scene.compiledLighting = std::make_shared<const CompiledLighting>(readCompiledLighting(bsp, placements, litFile, scene.diagnostics));
  if (resolve) resolve(scene);
  builder.scaleFramesToTextures();
  return scene;
}

} // namespace bt::bsp

// ---------------------------------------------------------------------------------------------
// Reading the file and resolving its textures

namespace bt::bsp {

namespace {

std::vector<uint8_t> readWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ImportError(Diagnostic{Severity::Error, path, 0, 0, "cannot open file"});
  std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw ImportError(Diagnostic{Severity::Error, path, 0, 0, "read error"});
  return bytes;
}

// Q1/HL levels usually carry their textures: decode every miptex with pixels (Quake's with the
// game palette, Half-Life's with their own). What is left is looked up like .map textures.
void decodeEmbeddedMiptex(const BspFile& bsp, Scene& scene, const TextureSearch& search, const game::GameInstall& install) {
  const bool halfLife = bsp.version == Version::HalfLife30;
  bool anyPixels = false;
  for (const Miptex& m : bsp.miptex) anyPixels |= m.present && m.hasPixels;
  if (!anyPixels) return;

  std::optional<Palette> palette;
  if (!halfLife) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(bsp.path).parent_path();
    try {
      // A level in <game>/maps/ finds <game>/gfx/palette.lmp walking up.
      fs::path paletteFile;
      palette = findPalette(search.palette, {dir.empty() ? fs::path(".") : dir}, &paletteFile);
      if (!paletteFile.empty()) scene.addInputFile(paletteFile.string());
    } catch (const ImportError& e) {
      scene.diagnostics.push_back({Severity::Warning, e.diagnostic().file, 0, 0, "palette not usable: " + e.diagnostic().message});
    }
    if (!palette) {
      // The game's gfx/palette.lmp (inside pak0.pak in a Quake install), else the built-in one.
      std::string file;
      palette = game::installPalette(install, /*quake2=*/false, bsp.path, scene.diagnostics, &file);
      if (!file.empty()) scene.addInputFile(file);
    }
    if (!palette) {
      scene.diagnostics.push_back({Severity::Warning, bsp.path, 0, 0,
                                   "the level's own textures need Quake's palette (gfx/palette.lmp beside the game, "
                                   "or --palette); they are looked up elsewhere instead"});
      return;
    }
  }
  for (Material& material : scene.materials) {
    if (!material.missing()) continue;
    for (const Miptex& m : bsp.miptex) {
      if (!m.present || !m.hasPixels || !textureNamesEqual(m.name, material.name)) continue;
      try {
        Material decoded = decodeMiptex(m.bytes, palette ? &*palette : nullptr, halfLife, bsp.path + " (miptex " + m.name + ")");
        decoded.name = material.name;
        decoded.sourcePath = bsp.path;
        material = std::move(decoded);
      } catch (const ImportError& e) {
        scene.diagnostics.push_back({Severity::Warning, bsp.path, 0, 0, "embedded texture skipped: " + e.diagnostic().message});
      }
      break;
    }
  }
}

// Quake 3 looks for textures in the game directory: the folder holding the .pk3 the level came
// from, or the parent of the level's maps/ folder; --textures folders come first.
// Then the game install's folders (game::openGameInstall: mods, the level's game folder, baseq3/
// or baseoa/), and the level's own archive wherever it is.
GameFiles quake3GameFiles(const std::optional<ArchivePath>& archive, const ImportOptions& options, const game::GameInstall& install) {
  GameFiles files;
  for (const std::string& dir : options.textures.textureDirs) files.addGameDir(dir, {".pk3"});
  for (const std::filesystem::path& dir : install.gameDirs) files.addGameDir(dir, {".pk3"});
  if (archive) files.addArchive(archive->archive);
  return files;
}

// The bytes of "archive:entry", from a .pak or a .pk3.
std::optional<std::vector<uint8_t>> readFromArchive(const ArchivePath& archive, const std::string& entry) {
  const std::unique_ptr<game::Archive> opened = game::openArchive(archive.archive);
  if (!opened) throw ImportError(Diagnostic{Severity::Error, archive.archive, 0, 0, "not an archive brushtrace reads (.pak, .pk3, .zip)"});
  return opened->read(entry);
}

} // namespace

Scene importBsp(const std::string& path, const ImportOptions& options) {
  const std::optional<ArchivePath> archive = splitArchivePath(path);
  std::vector<uint8_t> bytes;
  if (archive) {
    auto entry = readFromArchive(*archive, archive->entry);
    if (!entry) throw ImportError(Diagnostic{Severity::Error, path, 0, 0, "no such file in the archive"});
    bytes = std::move(*entry);
  } else {
    bytes = readWholeFile(path);
  }
  const BspFile bsp = readBspFile(bytes, path);

  // Coloured light lives in a .lit file beside the level (inside the same archive for a .pk3).
  std::optional<std::vector<uint8_t>> litFile;
  std::error_code litLookup; // a name the system cannot look up has no .lit beside it
  if (bsp.isQuake1Family()) {
    if (archive) {
      litFile = readFromArchive(*archive, std::filesystem::path(archive->entry).replace_extension(".lit").generic_string());
    } else if (const auto lit = std::filesystem::path(path).replace_extension(".lit"); std::filesystem::is_regular_file(lit, litLookup)) {
      litFile = readWholeFile(lit.string());
    }
  }

  const game::GameInstall install = game::openGameInstall(options.textures.game, path, toString(bsp.version));
  // Else the engine's: maps/<name>.lit in the game's files (a pak, a mod's maps/ folder).
  std::string litHolder;
  if (bsp.isQuake1Family() && !litFile) {
    const std::string lit = "maps/" + std::filesystem::path(archive ? archive->entry : path).stem().string() + ".lit";
    if (auto holder = install.files.fileHolding(lit)) {
      litFile = install.files.read(lit);
      litHolder = holder->string();
    }
  }
  MaterialResolver resolve = [&](Scene& scene) {
    // q3map2's light keys first: the early kinds of light (entitiesRead) need the sky shaders' suns.
    std::optional<GameFiles> quake3Files;
    Quake3Shaders shaders; // read once, for the light keys and the images
    if (bsp.version == Version::Quake3_46) {
      quake3Files = quake3GameFiles(archive, options, install);
      std::vector<std::string> filesRead;
      shaders = readQuake3Shaders(*quake3Files, scene.diagnostics, &filesRead);
      readQuake3ShaderLight(scene.materials, shaders, *quake3Files, scene.diagnostics, &filesRead);
      for (const std::string& file : filesRead) scene.addInputFile(file);
    }
    if (options.entitiesRead) options.entitiesRead(scene);
    if (options.textures.load) {
      if (bsp.isQuake1Family()) decodeEmbeddedMiptex(bsp, scene, options.textures, install);
      if (quake3Files) {
        std::vector<std::string> filesRead;
        resolveQuake3Materials(scene.materials, shaders, *quake3Files, scene.diagnostics, &filesRead);
        loadQuake3Sky(scene, *quake3Files, shaders, &filesRead);
        for (const std::string& file : filesRead) scene.addInputFile(file);
      }
    }
    // WADs, loose images and Quake 2 .wal files, companion maps, placeholders and the one
    // warning naming what is missing: the same search as for .map files.
    loadMaterials(scene, options.textures);
    loadSky(scene, options.textures);
  };
  Scene scene = sceneFromBsp(bsp, resolve, litFile, options.curveMaxError);
  // The level first: the .bsp, or the .pk3 it is in (which holds its .lit too).
  const std::string level = archive ? archive->archive : path;
  std::erase(scene.inputFiles, level);
  scene.inputFiles.insert(scene.inputFiles.begin(), level);
  if (!litHolder.empty())
    scene.addInputFile(litHolder);
  else if (litFile && !archive)
    scene.addInputFile(std::filesystem::path(path).replace_extension(".lit").string());
  return scene;
}

} // namespace bt::bsp
