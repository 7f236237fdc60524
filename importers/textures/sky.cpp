// The level's sky images (Scene::sky). A sky box is looked up as its engine looks it up: the
// worldspawn key names it and the game's files hold its six images (QuakeSpasm Sky_NewMap and
// Sky_LoadSkyBox, Quake/gl_sky.c; Quake 2 ref_gl R_SetSky, gl_warp.c). Without one, a Quake
// level's sky texture gives its two layers (Sky_LoadTexture).
#include "importers/game/game_install.h"
#include "importers/textures/textures.h"
#include "quake/entity_keys.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <optional>
#include <span>
#include <string_view>

namespace bt {

namespace {

// `suf` of the engines: the order Sky keeps the box's materials in.
constexpr std::array<std::string_view, 6> kSuffixes = {"rt", "bk", "lf", "ft", "up", "dn"};

// The key that names the sky box: Quake's `sky` (QuakeSpasm also reads Half-Life's `skyname` and
// Quake Live's `qlsky`, and drops a leading underscore: `_sky`), Half-Life's `skyname`, Quake 2's
// `sky` (g_spawn.c SP_worldspawn). Empty when the level names none.
std::string_view skyBoxKey(const Entity& world, std::string_view game) {
  static constexpr std::string_view kQuake[] = {"sky", "_sky", "skyname", "_skyname", "qlsky", "_qlsky"};
  static constexpr std::string_view kHalfLife[] = {"skyname"};
  static constexpr std::string_view kQuake2[] = {"sky"};
  const std::span<const std::string_view> names = game == "quake" || game == "hexen2" ? std::span<const std::string_view>(kQuake)
      : game == "halflife"                                                            ? std::span<const std::string_view>(kHalfLife)
                                                                                      : std::span<const std::string_view>(kQuake2);
  const quake::EntityKeys keys(world);
  for (std::string_view name : names)
    if (const std::string* value = keys.find(name); value && !value->empty()) return *value;
  return {};
}

// The image files the engine tries for one side, in its order: Quake 2's GL renderer and
// QuakeSpasm's Image_LoadImage take a .tga, else a .pcx; Half-Life's are .tga.
std::vector<std::string> sideFiles(const game::GameProfile& profile, std::string_view name, std::string_view suffix) {
  const std::string stem = fmt::format("{}/{}{}", profile.skies, name, suffix);
  if (profile.name == "halflife") return {stem + ".tga"};
  return {stem + ".tga", stem + ".pcx"};
}

// One side's image from the game's files; nullopt when they hold no such file. Throws
// ImportError when the file cannot be decoded.
std::optional<Material> readSide(const game::GameInstall& install, const std::string& file, Scene& scene) {
  const std::optional<std::vector<uint8_t>> bytes = install.files.read(file);
  if (!bytes) return std::nullopt;
  Material m;
  m.name = file;
  m.sourcePath = *install.files.describe(file);
  m.baseColor = decodeImage(*bytes, m.sourcePath);
  m.width = m.baseColor.width, m.height = m.baseColor.height;
  m.source = TextureSource::LooseImage;
  m.alphaTest = AlphaTest::None;
  scene.addInputFile(install.files.fileHolding(file)->string());
  return m;
}

// The worldspawn's sky box from the game's files; false when the level names none or one of its
// images is missing (then with one warning naming the files tried).
bool loadSkyBox(Scene& scene, const TextureSearch& search) {
  const Entity* world = scene.worldspawn();
  if (!search.load || !world) return false;
  // Most levels name no sky box: they cost no look at the game's files.
  if (skyBoxKey(*world, "quake").empty()) return false; // Quake's keys are the others' and more
  const game::GameInstall install = game::openGameInstall(search.game, scene.sourcePath, scene.format);
  if (!install.profile || install.profile->skies.empty() || install.profile->name == "quake3") return false; // Quake 3: a shader's skyParms
  const std::string_view name = skyBoxKey(*world, install.profile->name);
  if (name.empty()) return false;
  Sky sky{Sky::Kind::Box, std::string(name), uint32_t(scene.materials.size())};
  std::vector<Material> sides;
  std::vector<std::string> missing;
  for (std::string_view suffix : kSuffixes) {
    std::optional<Material> side;
    std::vector<std::string> tried;
    for (const std::string& file : sideFiles(*install.profile, name, suffix)) {
      try {
        side = readSide(install, file, scene);
      } catch (const ImportError& e) { // a corrupt image or archive entry: as if it were not there
        tried.push_back(fmt::format("{} ({})", file, e.diagnostic().message));
        continue;
      }
      if (side) break;
      tried.push_back(file);
    }
    if (side)
      sides.push_back(std::move(*side));
    else
      missing.insert(missing.end(), tried.begin(), tried.end());
  }
  if (!missing.empty()) {
    std::string list;
    for (const std::string& file : missing) list += (list.empty() ? "" : ", ") + file;
    scene.diagnostics.push_back(
        Diagnostic{Severity::Warning, scene.sourcePath, 0, 0,
                   fmt::format("sky box '{}' not drawn: no image for {} (looked in {}); the sky stays as the "
                               "level's sky texture draws it",
                               name, list, install.gameDirs.empty() ? std::string("no game install") : install.baseDir.string())});
    return false;
  }
  for (Material& side : sides) scene.materials.push_back(std::move(side));
  scene.sky = std::move(sky);
  return true;
}

// Quake's two layers of the level's sky texture: its right half (back) and its front layer, as
// two materials. QuakeSpasm draws one sky texture's layers on every sky face of a frame (the
// last of its sky texture chains); here, the last sky texture a face uses. A replacement image
// of another size than the miptex (loadMaterials) keeps the texture drawn on the face instead.
void takeQuakeSkyLayers(Scene& scene) {
  std::optional<uint32_t> last;
  for (const Face& face : scene.faces)
    if (face.material < scene.materials.size() && !scene.materials[face.material].skyFront.empty())
      last = std::max(last.value_or(0), face.material);
  if (!last) return;
  const Material& texture = scene.materials[*last];
  const Image& front = texture.skyFront;
  if (texture.baseColor.width != 2 * front.width || texture.baseColor.height != front.height) return;
  Material back, layer;
  back.name = texture.name + " (back layer)", layer.name = texture.name + " (front layer)";
  back.sourcePath = layer.sourcePath = texture.sourcePath;
  back.source = layer.source = texture.source;
  back.alphaTest = layer.alphaTest = AlphaTest::None;
  back.width = layer.width = front.width, back.height = layer.height = front.height;
  back.baseColor = front; // the size; every texel is overwritten below
  for (int y = 0; y < front.height; ++y)
    std::copy_n(texture.baseColor.texel(front.width, y), size_t(front.width) * 4,
                back.baseColor.rgba.begin() + ptrdiff_t(y) * front.width * 4);
  layer.baseColor = front;
  scene.sky = Sky{Sky::Kind::QuakeLayers, texture.name, uint32_t(scene.materials.size())};
  scene.materials.push_back(std::move(back));
  scene.materials.push_back(std::move(layer));
}

} // namespace

void loadSky(Scene& scene, const TextureSearch& search) {
  if (scene.sky) return; // Quake 3's, from its shaders (importers/bsp loadQuake3Sky)
  if (!loadSkyBox(scene, search)) takeQuakeSkyLayers(scene);
}

} // namespace bt
