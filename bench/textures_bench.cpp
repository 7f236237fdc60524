// Texture loading: WAD decoding throughput and a whole LibreQuake map's materials.
// Run from the build folder: build/bench/bench_textures (needs ../shared beside the repo).
#include "importers/textures/textures.h"

#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>

namespace {

namespace fs = std::filesystem;
const fs::path kShared = BRUSHTRACE_SHARED_DIR;

// Every miptex of LibreQuake's lq_dev_legacy.wad (396 textures, 675 KiB) decoded with the palette.
void BM_DecodeWholeWad(benchmark::State& state) {
  const fs::path wadPath = kShared / "maps/librequake/texture-wads/lq_dev_legacy/lq_dev_legacy.wad";
  if (!fs::exists(wadPath)) return state.SkipWithError("shared data not found");
  const bt::Palette palette = bt::loadPalette(kShared / "maps/palettes/quake.lmp");
  const bt::WadFile wad = bt::WadFile::open(wadPath);
  size_t bytes = 0, textures = 0;
  for (auto _ : state) {
    for (const bt::WadFile::Entry& entry : wad.entries()) {
      auto material = wad.loadTexture(entry.name, &palette);
      benchmark::DoNotOptimize(material);
      bytes += entry.size;
      ++textures;
    }
  }
  state.SetBytesProcessed(static_cast<int64_t>(bytes));
  state.counters["textures/s"] = benchmark::Counter(static_cast<double>(textures), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DecodeWholeWad)->Unit(benchmark::kMillisecond);

// loadMaterials for every texture name of LibreQuake's lqdm8.map (its "wad" key names WADs kept
// as PNG folders): folder indexing, PNG decoding, _fbr fullbrights, companion lookups.
void BM_LoadMaterialsLibreQuakeMap(benchmark::State& state) {
  const fs::path mapPath = kShared / "maps/librequake/lq1/maps/src/dm/lqdm8.map";
  std::ifstream in(mapPath);
  if (!in) return state.SkipWithError("shared data not found");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // Valve 220 face lines: "( p ) ( p ) ( p ) NAME [ ...": the name follows the third point.
  std::set<std::string> names;
  const std::regex face(R"(\) (\S+) \[)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), face); it != std::sregex_iterator(); ++it) names.insert((*it)[1]);
  std::string wadKey;
  std::smatch m;
  if (std::regex_search(text, m, std::regex(R"re("wad" "([^"]*)")re"))) wadKey = m[1];

  size_t materials = 0;
  for (auto _ : state) {
    bt::Scene scene;
    scene.sourcePath = mapPath.string();
    bt::Entity world;
    world.keys = {{"classname", "worldspawn"}, {"wad", wadKey}};
    scene.entities.push_back(world);
    for (const std::string& name : names) scene.materials.push_back(bt::Material{.name = name});
    bt::loadMaterials(scene, bt::TextureSearch{});
    benchmark::DoNotOptimize(scene.materials.data());
    materials += scene.materials.size();
  }
  state.counters["materials"] = static_cast<double>(names.size());
  state.counters["materials/s"] = benchmark::Counter(static_cast<double>(materials), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_LoadMaterialsLibreQuakeMap)->Unit(benchmark::kMillisecond);

} // namespace

BENCHMARK_MAIN();
