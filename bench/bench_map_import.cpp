// .map import speed on the largest shared map (LibreQuake lq_e4m3.map, 3.9 MB):
//   MapParse       tokenizer + parser into the document model (MB/s)
//   MapFullImport  parse + planes + windings + texture frames + materials (faces/s, ms per import)
#include "importers/map/map_parser.h"
#include "importers/map/map_scene.h"

#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <iterator>

namespace {

const std::string kLargestMap = "maps/librequake/lq1/maps/src/e4/lq_e4m3.map";

std::string readLargestMap(benchmark::State& state) {
  const std::filesystem::path path = std::filesystem::path(BRUSHTRACE_SHARED_DIR) / kLargestMap;
  std::ifstream in(path, std::ios::binary);
  if (!in) state.SkipWithError(("shared map not found: " + path.string()).c_str());
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void MapParse(benchmark::State& state) {
  const std::string text = readLargestMap(state);
  for (auto _ : state) {
    bt::map::MapDocument doc = bt::map::parseMap(text, kLargestMap);
    benchmark::DoNotOptimize(doc.entities.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(text.size()));
}
BENCHMARK(MapParse)->Unit(benchmark::kMillisecond);

void MapFullImport(benchmark::State& state) {
  const std::string text = readLargestMap(state);
  size_t faces = 0;
  for (auto _ : state) {
    const bt::Scene scene = bt::map::buildScene(bt::map::parseMap(text, kLargestMap));
    faces = scene.faces.size();
    benchmark::DoNotOptimize(scene.faces.data());
  }
  state.counters["faces"] = static_cast<double>(faces);
  state.counters["faces/s"] = benchmark::Counter(static_cast<double>(faces), benchmark::Counter::kIsIterationInvariantRate);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(text.size()));
}
BENCHMARK(MapFullImport)->Unit(benchmark::kMillisecond);

} // namespace

BENCHMARK_MAIN();
