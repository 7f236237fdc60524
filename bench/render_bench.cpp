// CPU tracer throughput: Mrays/s for primary and bounce rays (closest hit through TraceScene,
// what the integrator spends its time in), on one thread and on all, plus whole-frame render
// speed in both lighting modes. Maps come from ../shared (skipped when absent) and maps/.
//   build/bench/bench_render [--benchmark_filter=...]
#include "bench/loaded_level.h"
#include "importers/import.h"
#include "renderer/cpu/cpu_renderer.h"
#include "lighting/light_grid.h"

#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <memory>
#include <thread>

namespace {

using namespace bt;

using bench::LoadedLevel;

const std::string kShared = BRUSHTRACE_SHARED_DIR;
const std::map<std::string, std::string> kMaps = {
    {"e1m1", kShared + "/maps/quake_map_source/e1m1.map"},
    {"lqdm5", kShared + "/maps/librequake/lq1/maps/src/dm/lqdm5.map"},
    {"start", std::string(BRUSHTRACE_SOURCE_DIR) + "/maps/start.map"},
};

constexpr int kWidth = 320, kHeight = 180;

// Runs fn(i) for i in [0, n) on `threads` threads in contiguous chunks. Not bt::parallelFor,
// which hands out one index at a time: a shared counter per ray would cost as much as a ray,
// and this measures the rays.
template <class Fn> void forEachInChunks(size_t n, int threads, const Fn& fn) {
  std::vector<std::thread> pool;
  const size_t chunk = (n + size_t(threads) - 1) / size_t(threads);
  for (int t = 1; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (size_t i = size_t(t) * chunk; i < std::min(n, size_t(t + 1) * chunk); ++i) fn(i);
    });
  for (size_t i = 0; i < std::min(n, chunk); ++i) fn(i);
  for (std::thread& th : pool) th.join();
}

// Primary rays of a kWidth x kHeight frame, and one cosine bounce ray from each primary hit.
struct RaySet {
  std::vector<Ray> primary;
  std::vector<Ray> bounce;
};

RaySet makeRays(const LoadedLevel& m) {
  RaySet set;
  const Camera camera(m.pose, kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) set.primary.push_back(camera.ray(x + 0.5f, y + 0.5f));
  for (size_t i = 0; i < set.primary.size(); ++i) {
    const SurfaceHit hit = traceVisible(m.rs, set.primary[i]);
    if (!hit.found) continue;
    Rng rng = pixelRng(uint32_t(i), 0, 0, 0);
    const glm::vec3 dir = sampleCosineHemisphere(hit.normal, rng.next2());
    set.bounce.push_back(Ray{offsetRayOrigin(hit.position, hit.normal), 0.0f, dir, std::numeric_limits<float>::infinity()});
  }
  return set;
}

void BM_Rays(benchmark::State& state, const std::string& mapName, bool bounce) {
  const LoadedLevel* m = bench::loadLevel(kMaps.at(mapName));
  if (!m) {
    state.SkipWithError("map not found (../shared missing?)");
    return;
  }
  const RaySet rays = makeRays(*m);
  const std::vector<Ray>& batch = bounce ? rays.bounce : rays.primary;
  const int threads = state.range(0) > 0 ? int(state.range(0)) : int(std::thread::hardware_concurrency());
  std::vector<uint32_t> hits(batch.size());
  for (auto _ : state) {
    forEachInChunks(batch.size(), threads, [&](size_t i) {
      const auto hit = m->rs.tracer.closestHit(batch[i]);
      hits[i] = hit ? hit->face : kNoFace;
    });
    benchmark::DoNotOptimize(hits.data());
  }
  state.counters["Mrays/s"] = benchmark::Counter(double(batch.size()) * double(state.iterations()) / 1e6, benchmark::Counter::kIsRate);
  state.counters["Mrays/s/thread"] =
      benchmark::Counter(double(batch.size()) * double(state.iterations()) / 1e6 / threads, benchmark::Counter::kIsRate);
  state.counters["brushes"] = double(m->scene.brushes.size());
  state.counters["threads"] = threads;
}

// Renders m at kWidth x kHeight, spp samples per pixel, for as long as the benchmark asks, and
// reports Msamples/s.
void timeRenders(benchmark::State& state, const LoadedLevel& m, LightingMode mode, int spp, int threads) {
  RenderSettings s;
  s.width = kWidth;
  s.height = kHeight;
  s.spp = spp;
  s.integrator.mode = mode;
  s.threads = threads;
  for (auto _ : state) benchmark::DoNotOptimize(renderCpu(m.rs, Camera(m.pose, kWidth, kHeight), s).beauty.data());
  state.counters["Msamples/s"] =
      benchmark::Counter(double(kWidth) * kHeight * spp * double(state.iterations()) / 1e6, benchmark::Counter::kIsRate);
}

void BM_Render(benchmark::State& state, const std::string& mapName, LightingMode mode) {
  const LoadedLevel* m = bench::loadLevel(kMaps.at(mapName));
  if (!m) {
    state.SkipWithError("map not found");
    return;
  }
  timeRenders(state, *m, mode, 1, state.range(0) > 0 ? int(state.range(0)) : 0);
}

// Faithful `_bounce`: LibreQuake's lq_e3m1 (worldspawn `_bounce 3`: about a thousand bounce
// lights after merging, a few hundred in a cell) with its textures, 4 spp, with its bounce lights
// (range(0) = 1: kBounceShadowRays shadow rays per hit among them) and without (0).
const LoadedLevel* loadBounceLevel(bool bounceLights) {
  static std::map<bool, std::unique_ptr<LoadedLevel>> cache;
  if (auto it = cache.find(bounceLights); it != cache.end()) return it->second.get();
  const std::filesystem::path lq = kShared + "/maps/librequake";
  std::unique_ptr<LoadedLevel> level;
  if (std::filesystem::exists(lq / "lq1/maps/src/e3/lq_e3m1.map")) {
    ImportOptions options;
    for (const auto& dir : std::filesystem::directory_iterator(lq / "texture-wads"))
      if (dir.is_directory()) options.textures.textureDirs.push_back(dir.path().string());
    level = std::make_unique<LoadedLevel>();
    level->scene = importScene((lq / "lq1/maps/src/e3/lq_e3m1.map").string(), options);
    RenderSceneOptions renderOptions;
    renderOptions.bounceLights = bounceLights;
    Diagnostics diagnostics;
    level->rs = buildRenderScene(level->scene, renderOptions, diagnostics);
    level->pose = defaultCameraPose(level->scene);
  }
  return cache.emplace(bounceLights, std::move(level)).first->second.get();
}

void BM_RenderBounce(benchmark::State& state) {
  const LoadedLevel* m = loadBounceLevel(state.range(0) != 0);
  if (!m) {
    state.SkipWithError("lq_e3m1 not found (../shared missing?)");
    return;
  }
  timeRenders(state, *m, LightingMode::Faithful, 4, 0);
  state.counters["lights"] = double(m->rs.lights.size());
  // What a hit looks at: the bounce lights its cell lists, on average over the cells.
  const LightGrid& grid = m->rs.lightGrid;
  const size_t cells = size_t(grid.header.dims[0]) * grid.header.dims[1] * grid.header.dims[2];
  double listed = 0.0;
  for (size_t c = 0; c < cells; ++c)
    listed += double(trailingBounceLights(m->rs.lights, {grid.indices.data() + grid.cells[c].first, grid.cells[c].count}));
  state.counters["bounce_lights_per_cell"] = listed / double(cells);
}

} // namespace

// range(0): threads, 0 = all cores.
BENCHMARK_CAPTURE(BM_Rays, e1m1_primary, std::string("e1m1"), false)->Arg(1)->Arg(0)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Rays, e1m1_bounce, std::string("e1m1"), true)->Arg(1)->Arg(0)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Rays, lqdm5_primary, std::string("lqdm5"), false)->Arg(1)->Arg(0)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Rays, lqdm5_bounce, std::string("lqdm5"), true)->Arg(1)->Arg(0)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Render, start_faithful, std::string("start"), LightingMode::Faithful)
    ->Arg(1)
    ->Arg(0)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Render, start_physical, std::string("start"), LightingMode::Physical)
    ->Arg(1)
    ->Arg(0)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Render, e1m1_faithful, std::string("e1m1"), LightingMode::Faithful)
    ->Arg(0)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Render, e1m1_physical, std::string("e1m1"), LightingMode::Physical)
    ->Arg(0)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// range(0): 1 with lq_e3m1's bounce lights, 0 without.
BENCHMARK(BM_RenderBounce)->ArgName("bounce_lights")->Arg(0)->Arg(1)->UseRealTime()->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
