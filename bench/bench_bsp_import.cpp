// Import time of the largest oracle .bsp (LibreQuake's lq_e4m3, 2.2 MB BSP29): parse every lump,
// rebuild the brushes from hull 0, find each side's face and frame, read the lightmaps. Textures
// are left out (-notex file; their search is the textures part's benchmark). Target: < 200 ms.
#include "importers/bsp/bsp_file.h"
#include "importers/bsp/bsp_import.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace {

std::filesystem::path largestOracleBsp() {
  std::filesystem::path best;
  std::uintmax_t bestSize = 0;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(BRUSHTRACE_SHARED_DIR) / "oracle", ec))
    if (entry.path().extension() == ".bsp" && entry.file_size() > bestSize) {
      bestSize = entry.file_size();
      best = entry.path();
    }
  return best;
}

std::vector<uint8_t> readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void BM_ReadLumps(benchmark::State& state) {
  const auto path = largestOracleBsp();
  if (path.empty()) return state.SkipWithError("../shared/oracle not found");
  const auto bytes = readBytes(path);
  for (auto _ : state) benchmark::DoNotOptimize(bt::bsp::readBspFile(bytes, path.string()));
  state.SetBytesProcessed(static_cast<int64_t>(bytes.size()) * state.iterations());
  state.SetLabel(path.filename().string());
}
BENCHMARK(BM_ReadLumps)->Unit(benchmark::kMillisecond);

void BM_ImportScene(benchmark::State& state) {
  const auto path = largestOracleBsp();
  if (path.empty()) return state.SkipWithError("../shared/oracle not found");
  const auto bytes = readBytes(path);
  size_t faces = 0;
  for (auto _ : state) {
    const bt::bsp::BspFile bsp = bt::bsp::readBspFile(bytes, path.string());
    const bt::Scene scene = bt::bsp::sceneFromBsp(bsp);
    faces = scene.faces.size();
    benchmark::DoNotOptimize(scene.faces.data());
  }
  state.counters["brush_sides"] = static_cast<double>(faces);
  state.counters["sides/s"] = benchmark::Counter(static_cast<double>(faces) * state.iterations(), benchmark::Counter::kIsRate);
  state.SetLabel(path.filename().string());
}
BENCHMARK(BM_ImportScene)->Unit(benchmark::kMillisecond);

} // namespace

BENCHMARK_MAIN();
