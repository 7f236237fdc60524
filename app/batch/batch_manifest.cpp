#include "app/batch/batch_manifest.h"

#include "app/batch/batch_files.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <glob.h>
#include <set>
#include <stdexcept>

namespace bt::app::batch {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

bool isLevelFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".map" || ext == ".bsp";
}

// A folder stands for every .map and .bsp under it, in name order.
std::vector<std::string> levelsUnder(const fs::path& folder) {
  std::vector<std::string> found;
  for (const auto& entry : fs::recursive_directory_iterator(folder, fs::directory_options::skip_permission_denied))
    if (entry.is_regular_file() && isLevelFile(entry.path())) found.push_back(entry.path().string());
  std::sort(found.begin(), found.end());
  return found;
}

// glob(3): *, ? and [...] within one folder level; matches come sorted.
std::vector<std::string> expandGlob(const std::string& pattern) {
  glob_t matches{};
  std::vector<std::string> found;
  if (glob(pattern.c_str(), 0, nullptr, &matches) == 0)
    for (size_t i = 0; i < matches.gl_pathc; ++i) found.emplace_back(matches.gl_pathv[i]);
  globfree(&matches);
  return found;
}

// Relative paths, and the archive of ARCHIVE:maps/x.bsp, are relative to the manifest's folder.
std::string resolve(const std::string& path, const fs::path& base) {
  if (path.empty() || fs::path(path).is_absolute()) return path;
  const size_t colon = path.find(':');
  if (colon != std::string::npos && fs::is_regular_file(base / path.substr(0, colon)))
    return (base / path.substr(0, colon)).lexically_normal().string() + path.substr(colon);
  if (fs::exists(base / path) || path.find_first_of("*?[") != std::string::npos) return (base / path).lexically_normal().string();
  return path; // a bare level name, found through the game install
}

// The last three parts of the path, readable in a file listing (lqdm5.map, e1m1.bsp); the
// hash beside it tells apart levels whose names agree.
std::string safeName(const std::string& path) {
  std::vector<std::string> parts;
  for (const auto& part : fs::path(path).lexically_normal()) parts.push_back(part.string());
  std::string name;
  for (size_t i = parts.size() > 3 ? parts.size() - 3 : 0; i < parts.size(); ++i) {
    if (!name.empty()) name += '_';
    for (char c : parts[i]) name += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
  }
  return name.substr(name.size() > 64 ? name.size() - 64 : 0);
}

template <class T> T value(const json& object, const char* key, T fallback) {
  return object.contains(key) ? object.at(key).get<T>() : fallback;
}

void requireKnownKeys(const json& object, std::initializer_list<const char*> known, const std::string& where) {
  if (!object.is_object()) throw std::runtime_error(where + ": expected an object");
  for (const auto& [key, _] : object.items())
    if (std::find_if(known.begin(), known.end(), [&](const char* k) { return key == k; }) == known.end())
      throw std::runtime_error(fmt::format("{}: unknown key '{}'", where, key));
}

ImportOptions importOptionsOf(const json& entry, const fs::path& base) {
  ImportOptions options;
  if (entry.contains("dialect")) {
    options.dialect = parseDialect(entry.at("dialect").get<std::string>());
    if (!options.dialect) throw std::runtime_error("unknown dialect " + entry.at("dialect").dump());
  }
  for (const auto& w : value(entry, "wads", json::array())) options.textures.wads.push_back(resolve(w.get<std::string>(), base));
  for (const auto& t : value(entry, "textures", json::array())) options.textures.textureDirs.push_back(resolve(t.get<std::string>(), base));
  options.textures.palette = resolve(value<std::string>(entry, "palette", ""), base);
  options.textures.load = !value(entry, "no_textures", false);
  options.textures.game.game = value<std::string>(entry, "game", "");
  options.textures.game.baseDir = resolve(value<std::string>(entry, "basedir", ""), base);
  options.textures.game.mods = value(entry, "mods", std::vector<std::string>{});
  return options;
}

Level makeLevel(const std::string& path, const ImportOptions& import, json entry) {
  entry["path"] = path;
  return {path, import, safeName(path) + "-" + sha256Hex(path).substr(0, 8), std::move(entry)};
}

// One manifest entry: a path, a glob or a folder (a string, or an object's "path" with import options).
void addLevels(const json& entry, const fs::path& base, std::vector<Level>& levels, const std::string& where) {
  const json object = entry.is_string() ? json{{"path", entry}} : entry;
  requireKnownKeys(object, {"path", "dialect", "wads", "textures", "palette", "no_textures", "game", "basedir", "mods"}, where);
  const std::string path = resolve(object.at("path").get<std::string>(), base);
  const ImportOptions import = importOptionsOf(object, base);
  std::vector<std::string> paths{path};
  if (fs::is_directory(path))
    paths = levelsUnder(path);
  else if (path.find_first_of("*?[") != std::string::npos)
    paths = expandGlob(path);
  if (paths.empty()) throw std::runtime_error(fmt::format("{}: '{}' matches no level", where, path));
  for (const std::string& p : paths) levels.push_back(makeLevel(p, import, object));
}

RenderJob renderJobOf(const json& j) {
  requireKnownKeys(j, {"size", "spp", "seconds", "lighting", "aovs", "spawn_cameras", "backend", "seed"}, "jobs.render");
  RenderJob r;
  if (j.contains("size") && std::sscanf(j.at("size").get<std::string>().c_str(), "%dx%d", &r.size.width, &r.size.height) != 2)
    throw std::runtime_error("jobs.render.size: expected WIDTHxHEIGHT");
  r.spp = value(j, "spp", r.spp);
  r.seconds = value(j, "seconds", r.seconds);
  r.lighting = value(j, "lighting", r.lighting);
  r.aovs = value(j, "aovs", r.aovs);
  r.spawnCameras = value(j, "spawn_cameras", r.spawnCameras);
  r.backend = value(j, "backend", r.backend);
  r.seed = value(j, "seed", r.seed);
  const std::set<std::string> lightings{"faithful", "physical"}, aovs{"beauty", "albedo", "normal", "depth", "face"},
      backends{"auto", "gl", "cpu"};
  if (r.size.width < 1 || r.size.height < 1 || r.spp < 1 || r.seconds < 0 || r.spawnCameras < 0)
    throw std::runtime_error("jobs.render: size, spp, seconds and spawn_cameras must be positive");
  for (const auto& l : r.lighting)
    if (!lightings.count(l)) throw std::runtime_error("jobs.render.lighting: unknown mode '" + l + "'");
  for (const auto& a : r.aovs)
    if (!aovs.count(a)) throw std::runtime_error("jobs.render.aovs: unknown AOV '" + a + "'");
  if (!backends.count(r.backend)) throw std::runtime_error("jobs.render.backend: expected auto, gl or cpu");
  return r;
}

Manifest parseManifest(const json& j, const fs::path& base) {
  requireKnownKeys(j, {"levels", "jobs", "limits"}, "manifest");
  Manifest m;
  const json& levels = j.at("levels");
  for (size_t i = 0; i < levels.size(); ++i) addLevels(levels[i], base, m.levels, fmt::format("levels[{}]", i));
  const json jobs = value(j, "jobs", json::object());
  requireKnownKeys(jobs, {"import", "roundtrip", "render"}, "jobs");
  m.jobs.import = value(jobs, "import", true);
  m.jobs.roundTrip = value(jobs, "roundtrip", true);
  if (jobs.contains("render"))
    m.jobs.render = jobs.at("render").is_boolean() && !jobs.at("render").get<bool>()
        ? std::nullopt
        : std::optional(renderJobOf(jobs.at("render").is_object() ? jobs.at("render") : json::object()));
  const json limits = value(j, "limits", json::object());
  requireKnownKeys(limits, {"seconds", "memory_mb"}, "limits");
  m.limits.seconds = value(limits, "seconds", m.limits.seconds);
  m.limits.memoryMb = value(limits, "memory_mb", m.limits.memoryMb);
  if (m.limits.seconds <= 0 || m.limits.memoryMb < 0) throw std::runtime_error("limits: seconds must be positive, memory_mb 0 or more");
  return m;
}

} // namespace

Manifest readManifest(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot be read");
  try {
    const json j = json::parse(in);
    return parseManifest(j, fs::absolute(path).parent_path());
  } catch (const json::exception& e) { // parse errors carry the line and column in their text
    throw std::runtime_error(fmt::format("{}: {}", path, e.what()));
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(fmt::format("{}: {}", path, e.what()));
  }
}

Manifest manifestForLevels(const std::vector<std::string>& paths) {
  Manifest m;
  for (const std::string& p : paths) addLevels(json(p), fs::current_path(), m.levels, p);
  return m;
}

json toJson(const Jobs& jobs) {
  json j{{"import", jobs.import}, {"roundtrip", jobs.roundTrip}, {"render", false}};
  if (const auto& r = jobs.render)
    j["render"] = {{"size", fmt::format("{}x{}", r->size.width, r->size.height)},
                   {"spp", r->spp},
                   {"seconds", r->seconds},
                   {"lighting", r->lighting},
                   {"aovs", r->aovs},
                   {"spawn_cameras", r->spawnCameras},
                   {"backend", r->backend},
                   {"seed", r->seed}};
  return j;
}

std::vector<Level> shardOf(const std::vector<Level>& levels, int k, int n) {
  std::vector<Level> shard;
  for (size_t i = size_t(k - 1); i < levels.size(); i += size_t(n)) shard.push_back(levels[i]);
  return shard;
}

} // namespace bt::app::batch
