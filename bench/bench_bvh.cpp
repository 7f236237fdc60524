// BVH benchmarks: build speed and SAH cost on generated levels of 5k, 50k and 500k
// brushes and on the largest shared maps, and closest-hit Mrays/s for primary-like and
// bounce-like rays, one thread and all threads.
//
//   build/bench/bench_bvh                                  everything
//   build/bench/bench_bvh --benchmark_filter=Build        builds only
//   build/bench/bench_bvh_generated                        the generated levels alone: linked
//                                     without the importers (and OpenImageIO's hundreds of MB of
//                                     libraries), so it travels to another machine
//                                     (scripts/gpu-check.sh runs it on 2 cores there)
//
// Two build figures, items_per_second = brushes/s:
//   BvhBuild/<scene>/threads:N        the builder's brushes/s: the binned SAH builder
//                                     (buildBinnedSah) over the brush boxes. SAH = its cost,
//                                     SAH/fullsweep = that over the exact full-sweep reference.
//   TraceSceneBuild/<scene>/threads:N all of TraceScene::build: GPU faces, brushes with
//                                     axial-first sides and their bounds, the BVH, leaf order.
// BvhBuild also reports cpu_ms/build: the CPU time of all the process's threads per build
// (Google Benchmark's CPU column counts the timing thread alone), which shows how much more
// work a build with more threads does than one with a single thread.
// For traces items_per_second is rays/s (all threads together).
#include "bvh/trace_scene.h"
#ifdef BT_BENCH_SHARED_MAPS
#include "importers/import.h"
#endif
#include "tests/bvh/full_sweep_sah.h"
#include "tests/bvh/generated_scenes.h"

#include <benchmark/benchmark.h>

#include <glm/geometric.hpp>

#include <ctime>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <random>
#include <thread>

namespace {

using namespace bt;

struct BenchScene {
  std::string name;
  Scene scene;
  std::vector<dvec3> openPoints; // where rays start
  std::unique_ptr<TraceScene> trace;
  std::vector<Aabb> boxes;   // of trace->brushes(), what the BVH builder sees
  double fullSweepSah = 0.0; // of the reference builder on `boxes`; 0 when not computed
  std::vector<Ray> primary, bounce;
};

// Scenes are made once per process and shared by every benchmark that names them.
BenchScene& benchScene(const std::string& name) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<BenchScene>> cache;
  std::lock_guard lock(mutex);
  auto& slot = cache[name];
  if (slot) return *slot;
  slot = std::make_unique<BenchScene>();
  BenchScene& s = *slot;
  s.name = name;
#ifdef BT_BENCH_SHARED_MAPS
  if (name.ends_with(".map")) {
    s.scene = importScene((std::filesystem::path(BRUSHTRACE_SHARED_DIR) / "maps" / name).string(), {.textures = {.load = false}});
    // Start rays at points in the void between brushes: random points no brush contains.
    const TraceScene probe = TraceScene::build(s.scene);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const Bounds b = probe.bounds();
    for (int tries = 0; s.openPoints.size() < 64 && tries < 100000; ++tries) {
      const dvec3 p = b.min + b.extent() * dvec3(u(rng), u(rng), u(rng));
      const auto up = probe.closestHit({glm::vec3(p), 0.0f, {0, 0, 1}});
      const auto down = probe.closestHit({glm::vec3(p), 0.0f, {0, 0, -1}});
      if (up && down && !up->inside && !down->inside) s.openPoints.push_back(p); // under a roof, over a floor
    }
  } else
#endif
  {
    test::GeneratedLevel level = test::generateLevel(std::stoi(name), 1);
    s.scene = std::move(level.scene);
    s.openPoints = std::move(level.openPoints);
  }
  s.trace = std::make_unique<TraceScene>(TraceScene::build(s.scene));
  for (const GpuBrush& g : s.trace->brushes())
    s.boxes.push_back({{g.boundsMin[0], g.boundsMin[1], g.boundsMin[2]}, {g.boundsMax[0], g.boundsMax[1], g.boundsMax[2]}});
  if (s.boxes.size() <= 50000) // the full sweep is too slow beyond
    s.fullSweepSah = sahCost(test::buildFullSweepSah(s.boxes, BvhBuildOptions{}.leafSize).nodes);

  // Primary-like: 16 pinhole cameras of 64 x 64 pixels, 90 degree field of view.
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int camera = 0; camera < 16; ++camera) {
    const glm::vec3 eye(s.openPoints[(camera * 7919) % s.openPoints.size()]);
    const float yaw = u(rng) * 2.0f * std::numbers::pi_v<float>;
    const glm::vec3 forward(std::cos(yaw), std::sin(yaw), -0.2f), right(std::sin(yaw), -std::cos(yaw), 0.0f);
    const glm::vec3 up = glm::cross(right, forward);
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const float px = (x + 0.5f) / 32.0f - 1.0f, py = (y + 0.5f) / 32.0f - 1.0f;
        s.primary.push_back({eye, 0.0f, glm::normalize(forward + right * px + up * py)});
      }
  }
  // Bounce-like: from where the primary rays hit, cosine-distributed about the face normal.
  for (const Ray& r : s.primary) {
    const auto hit = s.trace->closestHit(r);
    if (!hit || hit->inside) continue;
    const GpuFace& f = s.trace->faces()[hit->face];
    const glm::vec3 n(f.plane[0], f.plane[1], f.plane[2]);
    const glm::vec3 a = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 t = glm::normalize(glm::cross(a, n)), b = glm::cross(n, t);
    const float r1 = u(rng), phi = 2.0f * std::numbers::pi_v<float> * u(rng);
    const glm::vec3 d = t * (std::sqrt(r1) * std::cos(phi)) + b * (std::sqrt(r1) * std::sin(phi)) + n * std::sqrt(1.0f - r1);
    s.bounce.push_back({offsetRayOrigin(r.origin + r.direction * hit->t, n), 0.0f, d});
  }
  return s;
}

#ifdef BT_BENCH_SHARED_MAPS
const char* kLargestSharedMap = "unvanquished-chasm/maps/chasm.map";     // 3724 brushes
const char* kSecondSharedMap = "librequake/lq1/maps/src/e4/lq_e4m3.map"; // 3399 brushes
#endif

// User + system CPU time of every thread of the process, in seconds.
double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The builder's own figure: the binned SAH builder alone, on the brush boxes.
void BM_BvhBuild(benchmark::State& state, const std::string& scene) {
  const BenchScene& s = benchScene(scene);
  const int threads = static_cast<int>(state.range(0));
  const double cpuBefore = processCpuSeconds();
  for (auto _ : state) {
    FlatBvh bvh = buildBinnedSah(s.boxes, {.threads = threads});
    benchmark::DoNotOptimize(bvh.nodes.data());
  }
  // Google Benchmark's CPU time is the timing thread's alone; this counts the builder's threads too.
  state.counters["cpu_ms/build"] = 1e3 * (processCpuSeconds() - cpuBefore) / std::max<double>(static_cast<double>(state.iterations()), 1.0);
  const double sah = sahCost(buildBinnedSah(s.boxes, {.threads = threads}).nodes); // the same for any thread count
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.boxes.size()));
  state.counters["SAH"] = sah;
  state.counters["brushes"] = static_cast<double>(s.boxes.size());
  if (s.fullSweepSah > 0.0) state.counters["SAH/fullsweep"] = sah / s.fullSweepSah;
}

// Everything TraceScene::build does on top: converting faces and brushes to their GPU structs.
void BM_TraceSceneBuild(benchmark::State& state, const std::string& scene) {
  const BenchScene& s = benchScene(scene);
  const int threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    TraceScene ts = TraceScene::build(s.scene, {.threads = threads});
    benchmark::DoNotOptimize(ts.nodes().data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.scene.brushes.size()));
  state.counters["brushes"] = static_cast<double>(s.scene.brushes.size());
}

void BM_ClosestHit(benchmark::State& state, const std::string& scene, bool bounce) {
  const BenchScene& s = benchScene(scene);
  const std::vector<Ray>& rays = bounce ? s.bounce : s.primary;
  size_t i = static_cast<size_t>(state.thread_index()) * 4099 % rays.size();
  int64_t hits = 0;
  for (auto _ : state) {
    hits += s.trace->closestHit(rays[i]).has_value();
    if (++i == rays.size()) i = 0;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["hit%"] = benchmark::Counter(100.0 * hits / std::max<int64_t>(state.iterations(), 1), benchmark::Counter::kAvgThreads);
}

void registerAll() {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::string> scenes = {"5000", "50000", "500000"};
#ifdef BT_BENCH_SHARED_MAPS
  const bool shared = std::filesystem::exists(std::filesystem::path(BRUSHTRACE_SHARED_DIR) / "maps" / kLargestSharedMap);
  if (shared) scenes.insert(scenes.end(), {kLargestSharedMap, kSecondSharedMap});
#endif
  for (const std::string& scene : scenes) {
    const std::string label = scene.ends_with(".map") ? std::filesystem::path(scene).stem().string() : scene;
    for (auto* bench : {benchmark::RegisterBenchmark(("BvhBuild/" + label).c_str(), BM_BvhBuild, scene),
                        benchmark::RegisterBenchmark(("TraceSceneBuild/" + label).c_str(), BM_TraceSceneBuild, scene)}) {
      bench->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->UseRealTime();
      if (cores > 2) bench->Arg(cores);
    }
    if (scene == "500000") continue; // traces at 5k, 50k and on the maps
    for (bool bounce : {false, true})
      benchmark::RegisterBenchmark(((bounce ? "ClosestHit/bounce/" : "ClosestHit/primary/") + label).c_str(), BM_ClosestHit, scene, bounce)
          ->Threads(1)
          ->Threads(cores)
          ->UseRealTime();
  }
}

} // namespace

int main(int argc, char** argv) {
  registerAll();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
