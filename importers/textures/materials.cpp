// loadMaterials: resolve every texture name of a scene to images, the way Quake-family tools do.
//
// Order of search for a name: the WADs (--wad, then worldspawn "wad"), then loose image folders
// (--textures, the unpacked folder of a WAD that is not there, TrenchBroom's "_tb_textures",
// <mapdir>/textures, <mapdir>/../textures), then the game install's file system (mods, the
// base game, their archives: importers/game/). Companion maps come from the loose folders.
#include "importers/textures/missing_textures.h"
#include "importers/textures/textures.h"

#include "importers/game/game_install.h"
#include "importers/textures/png_indices.h"
#include "scene/names.h"
#include "scene/parallel_for.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <system_error>
#include <unordered_map>

namespace bt {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> splitList(std::string_view list) {
  std::vector<std::string> items;
  size_t start = 0;
  while (start <= list.size()) {
    size_t end = list.find(';', start);
    if (end == std::string_view::npos) end = list.size();
    std::string_view item = list.substr(start, end - start);
    while (!item.empty() && std::isspace(static_cast<unsigned char>(item.front()))) item.remove_prefix(1);
    while (!item.empty() && std::isspace(static_cast<unsigned char>(item.back()))) item.remove_suffix(1);
    if (!item.empty()) items.emplace_back(item);
    start = end + 1;
  }
  return items;
}

bool isDirectory(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}
bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// Extensions of loose textures, most preferred first. .wal (Quake 2) last: a PNG beside a .wal
// is a replacement made on purpose.
constexpr std::array<std::string_view, 5> kImageExtensions{".png", ".tga", ".jpg", ".jpeg", ".wal"};

int extensionRank(const fs::path& file) {
  const std::string ext = lowercase(file.extension().string());
  for (size_t i = 0; i < kImageExtensions.size(); ++i)
    if (ext == kImageExtensions[i]) return static_cast<int>(i);
  return -1;
}

bool isWal(const fs::path& file) {
  return lowercase(file.extension().string()) == ".wal";
}

// One folder of loose textures, indexed once by lower-case relative stem ("e1u1/floor1_3"),
// which makes lookups case-insensitive like the engines' file systems.
class LooseFolder {
public:
  explicit LooseFolder(fs::path root) : root_(std::move(root)) {
    // Bounded so that pointing --textures at a whole disk does not hang the import.
    constexpr int kMaxDepth = 6;
    constexpr size_t kMaxFiles = 200000;
    std::error_code ec;
    fs::recursive_directory_iterator it(root_, fs::directory_options::skip_permission_denied, ec), end;
    size_t files = 0;
    for (; !ec && it != end && files < kMaxFiles; it.increment(ec)) {
      if (it.depth() >= kMaxDepth) it.disable_recursion_pending();
      std::error_code fileEc;
      if (!it->is_regular_file(fileEc)) continue;
      const fs::path& file = it->path();
      const int rank = extensionRank(file);
      if (rank < 0) continue;
      ++files;
      fs::path relative = file.lexically_relative(root_);
      relative.replace_extension();
      auto [slot, inserted] = byStem_.try_emplace(lowercase(relative.generic_string()), file);
      if (!inserted && rank < extensionRank(slot->second)) slot->second = file;
    }
  }

  const fs::path& root() const { return root_; }
  const fs::path* find(std::string_view stem) const {
    auto it = byStem_.find(lowercase(stem));
    return it == byStem_.end() ? nullptr : &it->second;
  }

private:
  fs::path root_;
  std::unordered_map<std::string, fs::path> byStem_;
};

// The companion maps a base texture may have, by file-name suffix.
enum class Companion { Normal, Gloss, Roughness, Metallic, Emissive };
struct CompanionSuffix {
  std::string_view suffix;
  Companion kind;
};
constexpr std::array<CompanionSuffix, 7> kCompanionSuffixes{{
    {"_norm", Companion::Normal},
    {"_normal", Companion::Normal},
    {"_rough", Companion::Roughness},
    {"_gloss", Companion::Gloss},
    {"_metal", Companion::Metallic},
    {"_glow", Companion::Emissive},
    {"_luma", Companion::Emissive},
}};

// Everything a scene's textures may come from, opened on first use.
class TextureLibrary {
public:
  TextureLibrary(const Scene& scene, const TextureSearch& search, Diagnostics& diagnostics)
      : search_(search), diagnostics_(diagnostics), sceneFile_(scene.sourcePath),
        install_(game::openGameInstall(search.game, scene.sourcePath, scene.format)) {
    for (const Diagnostic& d : install_.problems) diagnostics_.push_back(d);
    mapDir_ = scene.sourcePath.empty() ? fs::path(".") : fs::path(scene.sourcePath).parent_path();
    if (mapDir_.empty()) mapDir_ = ".";
    const Entity* world = scene.worldspawn();
    for (const std::string& wad : search.wads) addWad(wad, "--wad", /*relativeToMap=*/false);
    if (world)
      for (const std::string& wad : splitList(world->value("wad"))) addWad(wad, "worldspawn \"wad\"", /*relativeToMap=*/true);

    for (const std::string& dir : search.textureDirs) {
      if (isDirectory(dir))
        addFolder(dir);
      else
        warn(fmt::format("texture folder '{}' (--textures) does not exist", dir));
    }
    for (const fs::path& dir : unpackedWadFolders_) addFolder(dir);
    // TrenchBroom keeps the texture folders of a map in this key, relative to the game dir; for
    // maps that live beside their textures that is also the map's folder.
    if (world)
      for (const std::string& dir : splitList(world->value("_tb_textures")))
        if (isDirectory(mapDir_ / dir)) addFolder(mapDir_ / dir);
    // Loose textures beside the map, and in the game dir when the map is in <game>/maps/.
    for (const fs::path& dir : {mapDir_ / "textures", (mapDir_ / ".." / "textures").lexically_normal()})
      if (isDirectory(dir)) addFolder(dir);
  }

  // The texture called `name` from the first place that has it, or std::nullopt. Texture files
  // that exist but cannot be decoded are reported and skipped.
  std::optional<Material> find(const std::string& name) {
    const std::vector<std::string> spellings = textureFileStems(name);
    for (Wad& wad : wads_) {
      if (auto material = loadFromWad(wad, name, spellings)) return material;
    }
    for (const LooseFolder& folder : folders_)
      for (const std::string& stem : spellings)
        if (const fs::path* file = folder.find(stem))
          if (auto material = loadLoose(*file, name)) return material;
    return findInGame(name, spellings);
  }

  // Decodes, on all cores, the loose image that find() reads first for each material still
  // missing. find() itself stays in order, with its diagnostics, and takes the decoded images
  // (errors included) from here; a name that a WAD supplies, or that find() skips, has had its
  // image decoded for nothing.
  void decodeAhead(const std::vector<Material>& materials) {
    std::vector<fs::path> files;
    std::set<fs::path> listed;
    for (const Material& m : materials)
      if (m.missing())
        if (const fs::path* file = firstLooseFile(m.name); file && !isWal(*file) && listed.insert(*file).second) files.push_back(*file);
    std::vector<Decoded> decoded(files.size());
    parallelFor(files.size(), 0, [&](size_t i) {
      try {
        decoded[i].image = loadImage(files[i]);
      } catch (const ImportError& e) {
        decoded[i].error = e.diagnostic();
      }
    });
    for (size_t i = 0; i < files.size(); ++i) decoded_.emplace(files[i], std::move(decoded[i]));
  }

  void addCompanions(Material& material) {
    std::set<Companion> found;
    for (const std::string& stem : textureFileStems(material.name))
      for (const CompanionSuffix& c : kCompanionSuffixes) {
        if (found.contains(c.kind) || (c.kind == Companion::Gloss && found.contains(Companion::Roughness)) ||
            (c.kind == Companion::Roughness && found.contains(Companion::Gloss)))
          continue;
        for (const LooseFolder& folder : folders_) {
          const fs::path* file = folder.find(stem + std::string(c.suffix));
          if (!file || isWal(*file)) continue; // companions are images
          filesRead_.push_back(file->string());
          try {
            applyCompanion(material, c.kind, loadImage(*file));
            found.insert(c.kind);
          } catch (const ImportError& e) {
            warn(e.what());
          }
          break;
        }
      }
  }

  // Where a loose image of `name` would have been found: each spelling with each extension in
  // each loose folder (lower case, as the folders are indexed).
  std::vector<std::string> lookedFor(const std::string& name) const {
    std::vector<std::string> files;
    for (const std::string& stem : textureFileStems(name))
      for (const LooseFolder& folder : folders_)
        for (std::string_view ext : kImageExtensions) files.push_back((folder.root() / (lowercase(stem) + std::string(ext))).string());
    return files;
  }

  // Every WAD, palette and image file read so far, in the order read (repeats possible).
  const std::vector<std::string>& filesRead() const { return filesRead_; }

  std::string describeSearch() const {
    std::string text;
    for (const Wad& wad : wads_) text += (text.empty() ? "" : ", ") + wad.path.string();
    for (const LooseFolder& folder : folders_) text += (text.empty() ? "" : ", ") + folder.root().string() + "/";
    for (const std::string& mount : install_.files.describeMounts()) text += (text.empty() ? "" : ", ") + mount;
    return text.empty() ? "no WADs or texture folders" : text;
  }

private:
  struct Decoded {
    Image image;
    std::optional<Diagnostic> error;
  };

  // loadImage(file), decoded ahead where decodeAhead() did.
  Image decodedImage(const fs::path& file) {
    auto it = decoded_.find(file);
    if (it == decoded_.end()) return loadImage(file);
    Decoded d = std::move(it->second);
    decoded_.erase(it);
    if (d.error) throw ImportError(*d.error);
    return std::move(d.image);
  }

  // A loose texture in the game's file system: <textures>/<name>.<ext> (Quake 2's .wal, images
  // of source ports), loose files or inside the game's archives.
  std::optional<Material> findInGame(const std::string& name, const std::vector<std::string>& spellings) {
    if (install_.files.empty()) return std::nullopt;
    const std::string folder =
        install_.profile && !install_.profile->textures.empty() ? std::string(install_.profile->textures) + "/" : "textures/";
    for (const std::string& stem : spellings)
      for (std::string_view ext : kImageExtensions) {
        const std::string file = folder + stem + std::string(ext);
        std::optional<std::vector<uint8_t>> bytes;
        try {
          bytes = install_.files.read(file);
        } catch (const ImportError& e) { // a corrupt archive entry
          warn("texture skipped: " + e.diagnostic().message, e.diagnostic().file);
        }
        if (!bytes) continue;
        filesRead_.push_back(install_.files.fileHolding(file)->string());
        if (auto material = decodeGameTexture(*bytes, *install_.files.describe(file), name)) return material;
      }
    return std::nullopt;
  }

  std::optional<Material> decodeGameTexture(const std::vector<uint8_t>& bytes, const std::string& where, const std::string& name) {
    try {
      Material material;
      if (isWal(where)) {
        const Palette* palette = quake2Palette(mapDir_);
        if (!palette) return std::nullopt;
        material = decodeWal(bytes, *palette, where);
      } else {
        material.baseColor = decodeImage(bytes, where);
        material.width = material.baseColor.width;
        material.height = material.baseColor.height;
        material.source = TextureSource::LooseImage;
      }
      material.name = name;
      material.sourcePath = where;
      return material;
    } catch (const ImportError& e) {
      warn("texture skipped: " + e.diagnostic().message, e.diagnostic().file);
      return std::nullopt;
    }
  }

  // The first file find() tries among the loose folders.
  const fs::path* firstLooseFile(const std::string& name) const {
    const std::vector<std::string> spellings = textureFileStems(name);
    for (const LooseFolder& folder : folders_)
      for (const std::string& stem : spellings)
        if (const fs::path* file = folder.find(stem)) return file;
    return nullptr;
  }

  struct Wad {
    fs::path path;
    std::unique_ptr<WadFile> file; // opened on first lookup
    bool failed = false;
  };

  void warn(std::string message, std::string file = {}) {
    diagnostics_.push_back(Diagnostic{Severity::Warning, file.empty() ? sceneFile_ : file, 0, 0, std::move(message)});
  }

  void addFolder(const fs::path& dir) {
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(dir, ec);
    if (!seenFolders_.insert(ec ? dir : canonical).second) return;
    folders_.emplace_back(dir.lexically_normal());
  }

  // A WAD named by --wad (relative to the working dir) or by the "wad" key (relative to the map;
  // qbsp also tries the bare file name beside the map, which is how Half-Life's absolute
  // Windows paths "\half-life\valve\halflife.wad" still resolve).
  void addWad(const std::string& entry, std::string_view origin, bool relativeToMap) {
    std::string spelled = entry;
    std::replace(spelled.begin(), spelled.end(), '\\', '/');
    const fs::path given(spelled);
    std::vector<fs::path> candidates;
    if (given.is_absolute() || !relativeToMap) candidates.push_back(given);
    if (relativeToMap && given.is_relative()) candidates.push_back(mapDir_ / given);
    if (given.has_filename()) {
      candidates.push_back(mapDir_ / given.filename());
      candidates.push_back(mapDir_ / ".." / given.filename());
    }
    // Normalised so that "maps/../x.wad" resolves even when the map's own folder is virtual
    // (a path inside a .pk3) or gone.
    for (fs::path& c : candidates) c = c.lexically_normal();
    for (const fs::path& candidate : candidates) {
      if (!isFile(candidate)) continue;
      std::error_code ec;
      const fs::path canonical = fs::weakly_canonical(candidate, ec);
      if (seenWads_.insert(ec ? candidate : canonical).second) wads_.push_back(Wad{candidate, {}, false});
      return;
    }
    if (addWadFromGame(given)) return;
    // LibreQuake (and other projects) keep each WAD as a folder of images, named like the WAD,
    // and build the .wad from it; use the folder when the WAD itself is not there.
    for (const fs::path& candidate : candidates) {
      fs::path folder = candidate;
      folder.replace_extension();
      if (isDirectory(folder)) {
        unpackedWadFolders_.push_back(folder);
        return;
      }
    }
    std::string tried;
    for (const fs::path& c : candidates) tried += (tried.empty() ? "" : ", ") + c.string();
    warn(fmt::format("WAD '{}' ({}) not found (tried {})", entry, origin, tried));
  }

  // The game's files hold the WAD under some tail of the path the key gives: a key written on
  // the mapper's machine ("C:\\quake\\id1\\gfx\\base.wad", "/home/me/q/id1/base.wad") names it
  // by the part below the game folder, or by its bare name.
  bool addWadFromGame(const fs::path& given) {
    std::vector<fs::path> parts;
    for (const fs::path& part : given.relative_path()) parts.push_back(part);
    std::vector<std::string> names;
    for (size_t first = 0; first < parts.size(); ++first) {
      fs::path tail;
      for (size_t i = first; i < parts.size(); ++i) tail /= parts[i];
      names.push_back(tail.generic_string());
    }
    // Quake keeps its WADs in gfx/ ("gfx/base.wad"), where a key that names only the file means them.
    if (given.has_filename()) names.push_back("gfx/" + given.filename().string());
    for (const std::string& name : names) {
      if (!game::staysInTheGame(name)) continue;
      const auto where = install_.files.describe(name);
      if (!where) continue;
      if (!seenWads_.insert(*where).second) return true;
      filesRead_.push_back(install_.files.fileHolding(name)->string());
      Wad wad{*where, {}, false};
      try {
        wad.file = std::make_unique<WadFile>(WadFile::fromBytes(*install_.files.read(name), *where));
      } catch (const ImportError& e) {
        warn("WAD skipped: " + e.diagnostic().message, e.diagnostic().file);
        wad.failed = true;
      }
      wads_.push_back(std::move(wad));
      return true;
    }
    return false;
  }

  const WadFile* openWad(Wad& wad) {
    if (wad.failed) return nullptr;
    if (!wad.file) {
      try {
        filesRead_.push_back(wad.path.string()); // listed even when corrupt: a save that fixes it reloads
        wad.file = std::make_unique<WadFile>(WadFile::open(wad.path));
      } catch (const ImportError& e) {
        wad.failed = true;
        diagnostics_.push_back(Diagnostic{Severity::Warning, e.diagnostic().file, 0, 0, "WAD skipped: " + e.diagnostic().message});
        return nullptr;
      }
    }
    return wad.file.get();
  }

  // Never invented: --palette, else gfx/palette.lmp up the tree from the map and the WADs,
  // else a palette lump inside one of the WADs.
  const Palette* quakePalette() {
    if (paletteResolved_) return palette_ ? &*palette_ : nullptr;
    paletteResolved_ = true;
    std::vector<fs::path> startDirs{mapDir_};
    for (const Wad& wad : wads_) startDirs.push_back(wad.path.parent_path().empty() ? "." : wad.path.parent_path());
    try {
      fs::path file;
      palette_ = findPalette(search_.palette, startDirs, &file);
      if (!file.empty()) filesRead_.push_back(file.string());
    } catch (const ImportError& e) {
      warn("palette not usable: " + e.diagnostic().message, e.diagnostic().file);
    }
    for (size_t i = 0; !palette_ && i < wads_.size(); ++i)
      if (const WadFile* file = openWad(wads_[i])) palette_ = file->palette();
    if (!palette_) palette_ = gamePalette(/*quake2=*/false);
    return palette_ ? &*palette_ : nullptr;
  }

  // The game's own palette through its file system, else the built-in one (with a note).
  std::optional<Palette> gamePalette(bool quake2) {
    std::string file;
    std::optional<Palette> palette = game::installPalette(install_, quake2, sceneFile_, diagnostics_, &file);
    if (!file.empty()) filesRead_.push_back(file);
    return palette;
  }

  std::optional<Material> loadFromWad(Wad& wad, const std::string& name, const std::vector<std::string>& spellings) {
    const WadFile* file = openWad(wad);
    if (!file) return std::nullopt;
    for (const std::string& spelling : spellings) {
      const WadFile::Entry* entry = file->findTexture(spelling);
      if (!entry) continue;
      const Palette* palette = file->halfLife() ? nullptr : quakePalette();
      if (!file->halfLife() && !palette) return std::nullopt; // only when even the built-in one is gone
      try {
        std::optional<Material> material = file->loadTexture(spelling, palette);
        material->name = name;
        return material;
      } catch (const ImportError& e) {
        diagnostics_.push_back(Diagnostic{Severity::Warning, e.diagnostic().file, 0, 0, "texture skipped: " + e.diagnostic().message});
        return std::nullopt;
      }
    }
    return std::nullopt;
  }

  // Quake 2's palette for .wal files: --palette, pics/colormap.pcx up the tree from `startDir`
  // or the map, the game's files, else the built-in one. Throws ImportError for a bad --palette.
  const Palette* quake2Palette(const fs::path& startDir) {
    if (!quake2Palette_) {
      fs::path paletteFile;
      quake2Palette_ = findQuake2Palette(search_.palette, {startDir, mapDir_}, &paletteFile);
      if (!paletteFile.empty()) filesRead_.push_back(paletteFile.string());
      if (!*quake2Palette_) quake2Palette_ = gamePalette(/*quake2=*/true);
    }
    return *quake2Palette_ ? &**quake2Palette_ : nullptr;
  }

  std::optional<Material> loadLoose(const fs::path& file, const std::string& name) {
    filesRead_.push_back(file.string());
    try {
      Material material;
      if (isWal(file)) {
        const Palette* palette = quake2Palette(file.parent_path());
        if (!palette) return std::nullopt;
        material = decodeWal(readTextureFile(file), *palette, file.string());
      } else {
        material.baseColor = decodedImage(file);
        material.width = material.baseColor.width;
        material.height = material.baseColor.height;
        material.source = TextureSource::LooseImage;
        applyQuakePaletteConventions(material, name, file);
      }
      material.name = name;
      material.sourcePath = file.string();
      return material;
    } catch (const ImportError& e) {
      diagnostics_.push_back(Diagnostic{Severity::Warning, e.diagnostic().file, 0, 0, "texture skipped: " + e.diagnostic().message});
      return std::nullopt;
    }
  }

  // Loose images of Quake textures are usually the palette images saved as PNG, which loses
  // the palette indices that carry two conventions; recover them from the colours.
  void applyQuakePaletteConventions(Material& material, const std::string& name, const fs::path& file) {
    const bool fence = !name.empty() && name.front() == '{';
    const bool fullbrights = lowercase(file.stem().string()).ends_with("_fbr");
    if (!fence && !fullbrights) return;
    const bool keyed = fence && keyOutIndex255(material.baseColor, file);
    const Palette* palette = quakePalette();
    if (!palette) return;
    if (fence && !keyed) keyOutTransparentColour(material.baseColor, *palette);
    if (fullbrights) recoverFullbrights(material, *palette);
  }

  static bool hasAlpha(const Image& image) {
    for (size_t i = 3; i < image.rgba.size(); i += 4)
      if (image.rgba[i] != 255) return true;
    return false;
  }

  // '{' textures saved as 8-bit colour-mapped PNGs (LibreQuake's): index 255 is see-through,
  // whatever colour the file's palette gives it. False when the file is no such PNG.
  static bool keyOutIndex255(Image& image, const fs::path& file) {
    if (hasAlpha(image)) return true; // the image has its own alpha: keep it
    const auto indices = readPngPaletteIndices(file);
    if (!indices || indices->size() * 4 != image.rgba.size()) return false;
    for (size_t i = 0; i < indices->size(); ++i)
      if ((*indices)[i] == 255) std::fill_n(&image.rgba[i * 4], 4, uint8_t{0});
    return true;
  }

  static uint32_t packRgb(const uint8_t* rgb) { return uint32_t{rgb[0]} << 16 | uint32_t{rgb[1]} << 8 | rgb[2]; }

  // '{' textures whose image has no alpha: texels of palette colour 255 are see-through.
  static void keyOutTransparentColour(Image& image, const Palette& palette) {
    const size_t texels = image.rgba.size() / 4;
    for (size_t i = 0; i < texels; ++i)
      if (image.rgba[i * 4 + 3] != 255) return; // the image has its own alpha: keep it
    const uint32_t key = packRgb(&palette.rgb[255 * 3]);
    for (size_t i = 0; i < texels; ++i)
      if (packRgb(&image.rgba[i * 4]) == key) std::fill_n(&image.rgba[i * 4], 4, uint8_t{0});
  }

  // LibreQuake marks textures that use fullbright colours with a "_fbr" file-name suffix: texels
  // of a fullbright colour (indices 224..254) become emissive. A colour that also appears among
  // indices 0..223 is ambiguous and stays lit normally.
  void recoverFullbrights(Material& material, const Palette& palette) {
    if (fullbrightColours_.empty()) {
      std::vector<uint32_t> normal;
      for (int i = 0; i < 224; ++i) normal.push_back(packRgb(&palette.rgb[i * 3]));
      for (int i = 224; i < 255; ++i) {
        const uint32_t colour = packRgb(&palette.rgb[i * 3]);
        if (std::find(normal.begin(), normal.end(), colour) == normal.end()) fullbrightColours_.push_back(colour);
      }
      std::sort(fullbrightColours_.begin(), fullbrightColours_.end());
    }
    const Image& base = material.baseColor;
    Image emissive{base.width, base.height, std::vector<uint8_t>(base.rgba.size(), 0)};
    bool any = false;
    for (size_t i = 0; i < base.rgba.size(); i += 4) {
      emissive.rgba[i + 3] = 255;
      const uint8_t* texel = &base.rgba[i];
      if (texel[3] == 0 || !std::binary_search(fullbrightColours_.begin(), fullbrightColours_.end(), packRgb(texel))) continue;
      std::copy_n(texel, 3, &emissive.rgba[i]);
      any = true;
    }
    if (any) material.emissive = std::move(emissive);
  }

  static void applyCompanion(Material& material, Companion kind, Image image) {
    switch (kind) {
    case Companion::Normal: material.normal = std::move(image); break;
    case Companion::Roughness: material.roughness = std::move(image); break;
    case Companion::Gloss:
      // Gloss maps store smoothness; the material model wants roughness = 1 - gloss.
      for (size_t i = 0; i < image.rgba.size(); i += 4) {
        image.rgba[i] = static_cast<uint8_t>(255 - image.rgba[i]);
        image.rgba[i + 1] = image.rgba[i + 2] = image.rgba[i];
      }
      material.roughness = std::move(image);
      break;
    case Companion::Metallic: material.metallic = std::move(image); break;
    case Companion::Emissive: material.emissive = std::move(image); break;
    }
  }

  const TextureSearch& search_;
  Diagnostics& diagnostics_;
  std::string sceneFile_;
  game::GameInstall install_;
  fs::path mapDir_;
  std::vector<Wad> wads_;
  std::set<fs::path> seenWads_;
  std::vector<fs::path> unpackedWadFolders_;
  std::vector<LooseFolder> folders_;
  std::set<fs::path> seenFolders_;
  bool paletteResolved_ = false;
  std::optional<Palette> palette_;
  std::vector<uint32_t> fullbrightColours_;             // sorted, from palette_
  std::optional<std::optional<Palette>> quake2Palette_; // outer: looked for yet; inner: found
  std::map<fs::path, Decoded> decoded_;                 // by decodeAhead(), until find() takes them
  std::vector<std::string> filesRead_;
};

void replaceLeadingSpelling(std::vector<std::string>& out, std::string_view name, std::string_view prefix,
                            std::initializer_list<std::string_view> alternatives) {
  if (!name.starts_with(prefix)) return;
  const std::string_view rest = name.substr(prefix.size());
  for (std::string_view alt : alternatives) out.push_back(std::string(alt) + std::string(rest));
}

} // namespace

std::vector<std::string> textureFileStems(std::string_view name) {
  std::vector<std::string> stems{std::string(name)};
  // Quake's liquids start with '*', which engines and PNG texture packs cannot put in file names
  // the same way: Quake 2-era engines spell it '#', LibreQuake's folders "star_". Animated
  // textures start with '+' ("+0button"), spelled "plus_" there. Accept every spelling.
  replaceLeadingSpelling(stems, name, "*", {"#", "star_"});
  replaceLeadingSpelling(stems, name, "#", {"*", "star_"});
  replaceLeadingSpelling(stems, name, "star_", {"*", "#"});
  replaceLeadingSpelling(stems, name, "+", {"plus_"});
  replaceLeadingSpelling(stems, name, "plus_", {"+"});
  // Quake 3 shader names include "textures/"; the folders we index are often textures/ itself.
  replaceLeadingSpelling(stems, name, "textures/", {""});
  // LibreQuake names the images of textures with fullbright texels "<name>_fbr".
  const size_t spellings = stems.size();
  for (size_t i = 0; i < spellings; ++i) stems.push_back(stems[i] + "_fbr");
  return stems;
}

void loadMaterials(Scene& scene, const TextureSearch& search) {
  if (!search.load) {
    for (Material& material : scene.materials)
      if (material.missing() && material.baseColor.empty()) material.baseColor = checkerPlaceholder(material.width, material.height);
    return;
  }

  TextureLibrary library(scene, search, scene.diagnostics);
  library.decodeAhead(scene.materials);
  std::vector<std::string> missing;
  for (Material& material : scene.materials) {
    if (material.missing()) {
      if (std::optional<Material> found = library.find(material.name)) {
        // Texture coordinates are in texels of the size the compiler saw. When the importer knows
        // it (a .bsp miptex header), a loose image is a replacement drawn over that same size.
        const bool sizeKnown = material.width != Material{}.width || material.height != Material{}.height;
        if (sizeKnown && found->source == TextureSource::LooseImage) {
          found->width = material.width;
          found->height = material.height;
        }
        material = std::move(*found);
      } else {
        missing.push_back(material.name);
        material.baseColor = checkerPlaceholder(material.width, material.height);
        continue;
      }
    }
    library.addCompanions(material);
  }
  for (const std::string& file : library.filesRead()) scene.addInputFile(file);

  if (!missing.empty()) {
    std::string names;
    for (const std::string& n : missing) names += (names.empty() ? "" : ", ") + n;
    scene.diagnostics.push_back(Diagnostic{
        Severity::Warning, scene.sourcePath, 0, 0,
        fmt::format("{} texture(s) not found, drawn as a checker: {} (searched {})", missing.size(), names, library.describeSearch())});
  }
}

std::vector<std::string> missingTextureFiles(const Scene& scene, const TextureSearch& search) {
  std::vector<std::string> files;
  const bool anyMissing = std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.missing(); });
  if (!search.load || !anyMissing) return files;
  Diagnostics ignored; // the import reported them
  const TextureLibrary library(scene, search, ignored);
  for (const Material& material : scene.materials)
    if (material.missing())
      for (std::string& file : library.lookedFor(material.name)) files.push_back(std::move(file));
  return files;
}

} // namespace bt
