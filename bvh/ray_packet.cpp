// TraceScene::closestHits: the closest-hit walk of trace_scene.cpp for a packet of rays at once.
#include "bvh/ray_brush.h"
#include "bvh/trace_scene.h"

#include <bit>
#include <cstdint>
#include <stdexcept>

// On x86-64, the node test of two blocks at once in AVX where the CPU has it (picked at run time);
// the function alone is compiled for AVX, so nothing shared with the baseline build is.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define BT_PACKET_AVX 1
#include <immintrin.h>
#else
#define BT_PACKET_AVX 0
#endif

namespace bt {

using namespace trace_detail;

namespace {

constexpr int kLanes = int(TraceScene::kPacketLanes);
constexpr int kBlocks = int(TraceScene::kPacketRays / TraceScene::kPacketLanes);
static_assert(TraceScene::kPacketRays <= 64, "a packet's rays are the bits of one mask");

// kLanes floats that the compiler keeps in vector registers (GCC and Clang vector extensions:
// one SSE or NEON register); each lane's arithmetic is the scalar float arithmetic of
// nodeOverlaps, so a lane's answer is its ray's own.
using Floats = float __attribute__((vector_size(kLanes * sizeof(float))));

// std::min and std::max, lane by lane (the same operand picked at ties).
inline Floats lanesMin(Floats a, Floats b) {
  return b < a ? b : a;
}
inline Floats lanesMax(Floats a, Floats b) {
  return a < b ? b : a;
}

// The rays as lanes, kLanes to a block: origin, 1 / direction, tMin and the closest hit's t so
// far (nodeOverlaps' tLimit). A lane without a ray never overlaps (its tMin is infinite).
struct Lanes {
  Floats ox[kBlocks], oy[kBlocks], oz[kBlocks], ix[kBlocks], iy[kBlocks], iz[kBlocks], tMin[kBlocks], best[kBlocks];
};

// Which of the rays of `mask` overlap the node (nodeOverlaps<false>, lane by lane), and the
// near t of the first of them (what orders two children).
uint64_t overlapping(const Lanes& l, const GpuBvhNode& node, uint64_t mask, float& firstNear) {
  uint64_t out = 0;
  constexpr uint32_t kBlockBits = (1u << kLanes) - 1u;
  for (uint64_t left = mask; left != 0;) {
    const int b = std::countr_zero(left) / kLanes;
    const uint32_t active = uint32_t(left >> (b * kLanes)) & kBlockBits;
    left &= ~(uint64_t(kBlockBits) << (b * kLanes));
    const Floats x0 = (node.boundsMin[0] - l.ox[b]) * l.ix[b], x1 = (node.boundsMax[0] - l.ox[b]) * l.ix[b];
    const Floats y0 = (node.boundsMin[1] - l.oy[b]) * l.iy[b], y1 = (node.boundsMax[1] - l.oy[b]) * l.iy[b];
    const Floats z0 = (node.boundsMin[2] - l.oz[b]) * l.iz[b], z1 = (node.boundsMax[2] - l.oz[b]) * l.iz[b];
    const Floats near = lanesMax(lanesMax(lanesMin(x0, x1), lanesMin(y0, y1)), lanesMin(z0, z1));
    const Floats far = lanesMin(lanesMin(lanesMax(x0, x1), lanesMax(y0, y1)), lanesMax(z0, z1));
    const auto hit = (lanesMax(near, l.tMin[b]) <= lanesMin(far, l.best[b])) & (near <= far);
#if defined(__SSE2__)
    static_assert(kLanes == 4);
    uint32_t bits = uint32_t(_mm_movemask_ps(__m128(hit))) & active;
#else
    uint32_t bits = 0;
    for (int k = 0; k < kLanes; ++k) bits |= uint32_t(hit[k] != 0) << k;
    bits &= active;
#endif
    if (bits != 0 && out == 0) firstNear = near[std::countr_zero(bits)];
    out |= uint64_t(bits) << (b * kLanes);
  }
  return out;
}

#if BT_PACKET_AVX
// overlapping() for two blocks at a time, eight rays a register, lane by lane the same float
// operations: lanesMin(a, b) is _mm256_min_ps(b, a) and lanesMax(a, b) _mm256_max_ps(b, a) (the
// same operand at ties, zeros of both signs and NaN), the comparisons are ordered as the vector
// extension's. A block without active rays beside one with them is tested too and its bits
// dropped. (The intrinsics are written out: a lambda here would not be compiled for AVX.)
[[gnu::target("avx")]] uint64_t overlappingAvx(const Lanes& l, const GpuBvhNode& node, uint64_t mask, float& firstNear) {
  static_assert(kLanes == 4 && kBlocks % 2 == 0);
  uint64_t out = 0;
  const __m256 minX = _mm256_set1_ps(node.boundsMin[0]), minY = _mm256_set1_ps(node.boundsMin[1]), minZ = _mm256_set1_ps(node.boundsMin[2]);
  const __m256 maxX = _mm256_set1_ps(node.boundsMax[0]), maxY = _mm256_set1_ps(node.boundsMax[1]), maxZ = _mm256_set1_ps(node.boundsMax[2]);
  for (uint64_t left = mask; left != 0;) {
    const int b = std::countr_zero(left) / (2 * kLanes) * 2; // the pair's first block
    const uint32_t active = uint32_t(left >> (b * kLanes)) & 0xffu;
    left &= ~(uint64_t(0xffu) << (b * kLanes));
    const __m256 ox = _mm256_loadu_ps(reinterpret_cast<const float*>(&l.ox[b])),
                 ix = _mm256_loadu_ps(reinterpret_cast<const float*>(&l.ix[b]));
    const __m256 oy = _mm256_loadu_ps(reinterpret_cast<const float*>(&l.oy[b])),
                 iy = _mm256_loadu_ps(reinterpret_cast<const float*>(&l.iy[b]));
    const __m256 oz = _mm256_loadu_ps(reinterpret_cast<const float*>(&l.oz[b])),
                 iz = _mm256_loadu_ps(reinterpret_cast<const float*>(&l.iz[b]));
    const __m256 x0 = _mm256_mul_ps(_mm256_sub_ps(minX, ox), ix), x1 = _mm256_mul_ps(_mm256_sub_ps(maxX, ox), ix);
    const __m256 y0 = _mm256_mul_ps(_mm256_sub_ps(minY, oy), iy), y1 = _mm256_mul_ps(_mm256_sub_ps(maxY, oy), iy);
    const __m256 z0 = _mm256_mul_ps(_mm256_sub_ps(minZ, oz), iz), z1 = _mm256_mul_ps(_mm256_sub_ps(maxZ, oz), iz);
    const __m256 near = _mm256_max_ps(_mm256_min_ps(z1, z0), _mm256_max_ps(_mm256_min_ps(y1, y0), _mm256_min_ps(x1, x0)));
    const __m256 far = _mm256_min_ps(_mm256_max_ps(z1, z0), _mm256_min_ps(_mm256_max_ps(y1, y0), _mm256_max_ps(x1, x0)));
    const __m256 tMin = _mm256_loadu_ps(reinterpret_cast<const float*>(&l.tMin[b]));
    const __m256 best = _mm256_loadu_ps(reinterpret_cast<const float*>(&l.best[b]));
    const __m256 hit =
        _mm256_and_ps(_mm256_cmp_ps(_mm256_max_ps(tMin, near), _mm256_min_ps(best, far), _CMP_LE_OQ), _mm256_cmp_ps(near, far, _CMP_LE_OQ));
    const uint32_t bits = uint32_t(_mm256_movemask_ps(hit)) & active;
    if (bits != 0 && out == 0) {
      alignas(32) float nears[2 * kLanes];
      _mm256_store_ps(nears, near);
      firstNear = nears[std::countr_zero(bits)];
    }
    out |= uint64_t(bits) << (b * kLanes);
  }
  return out;
}
#endif

struct Walk {
  // No value-initialisation of the arrays (kilobytes per packet): load() fills what is read.
  explicit Walk(const TraceScene& scene) : ts(scene) {}
  const TraceScene& ts;
  Lanes lanes;
  RayContext rays[TraceScene::kPacketRays];
  Hit best[TraceScene::kPacketRays];
  uint64_t found = 0;

  // Every brush of a leaf against the rays of `mask` that reach it, as traverse() tests them.
  void leaf(const GpuBvhNode& node, uint64_t mask) {
    const std::span<const GpuBrush> brushes = ts.brushes();
    for (uint32_t i = node.leftFirst; i < node.leftFirst + node.count; ++i)
      for (uint64_t m = mask; m != 0; m &= m - 1) {
        const int k = std::countr_zero(m);
        Hit hit;
        if (hitBrush<false>(rays[k], brushes[i], ts.sides(), ts.faces(), best[k].t, hit) && closer(hit, best[k])) {
          best[k] = hit;
          best[k].slot = i;
          found |= uint64_t(1) << k;
          lanes.best[k / kLanes][k % kLanes] = hit.t;
        }
      }
  }

  // traverse<false, false>'s walk for all the rays of `mask` at once: depth first, the child
  // nearer to the first ray first; a node popped is tested again against the hits found since.
  template <bool Avx> void run(uint64_t mask) {
    const std::span<const GpuBvhNode> nodes = ts.nodes();
    const auto overlapping = [this](const GpuBvhNode& node, uint64_t rays, float& firstNear) {
#if BT_PACKET_AVX
      if constexpr (Avx) return overlappingAvx(lanes, node, rays, firstNear);
#endif
      return bt::overlapping(lanes, node, rays, firstNear);
    };
    struct Entry {
      uint32_t node;
      uint64_t mask;
    };
    Entry stack[kBvhMaxDepth];
    int top = 0;
    float near = 0.0f;
    uint32_t current = 0;
    mask = overlapping(nodes[0], mask, near);
    if (mask == 0) return;
    for (;;) {
      const GpuBvhNode& node = nodes[current];
      if (node.count > 0) {
        leaf(node, mask);
      } else {
        uint32_t a = node.leftFirst, b = node.leftFirst + 1;
        float nearA = 0.0f, nearB = 0.0f;
        uint64_t maskA = overlapping(nodes[a], mask, nearA), maskB = overlapping(nodes[b], mask, nearB);
        if (maskA != 0 && maskB != 0) {
          if (nearB < nearA) std::swap(a, b), std::swap(maskA, maskB);
          stack[top++] = {b, maskB};
          current = a, mask = maskA;
          continue;
        }
        if ((maskA | maskB) != 0) {
          current = maskA != 0 ? a : b, mask = maskA | maskB;
          continue;
        }
      }
      for (;;) {
        if (top == 0) return;
        --top;
        current = stack[top].node;
        mask = overlapping(nodes[current], stack[top].mask, near);
        if (mask != 0) break;
      }
    }
  }
};

// The rays of a packet into `walk`; returns the mask of those it takes (`single(k)` is called
// for each of the others).
template <class Single> uint64_t load(Walk& walk, std::span<const Ray> rays, const Single& single) {
  const TraceScene& ts = walk.ts;
  Lanes& l = walk.lanes;
  for (int b = 0; b < kBlocks; ++b) l.tMin[b] = Floats{} + kInfinity, l.best[b] = Floats{} - kInfinity;
  uint64_t mask = 0;
  for (size_t k = 0; k < rays.size(); ++k) {
    const RayContext& r = walk.rays[k] = RayContext(rays[k]);
    if (r.hasZeroComponent || !ts.triangleNodes().empty() || ts.nodes().empty()) {
      single(k);
      continue;
    }
    walk.best[k].t = r.tMax; // traceBoth's start
    walk.best[k].face = kNoFace;
    const int b = int(k) / kLanes, lane = int(k) % kLanes;
    l.ox[b][lane] = r.origin.x, l.oy[b][lane] = r.origin.y, l.oz[b][lane] = r.origin.z;
    l.ix[b][lane] = r.invDirection.x, l.iy[b][lane] = r.invDirection.y, l.iz[b][lane] = r.invDirection.z;
    l.tMin[b][lane] = r.tMin, l.best[b][lane] = r.tMax;
    mask |= uint64_t(1) << k;
  }
  return mask;
}

} // namespace

void TraceScene::closestHits(std::span<const Ray> rays, std::span<std::optional<Hit>> hits) const {
  if (rays.size() > kPacketRays || hits.size() != rays.size())
    throw std::invalid_argument("TraceScene::closestHits: up to kPacketRays rays, one hit each");
  Walk walk(*this);
  const uint64_t mask = load(walk, rays, [&](size_t k) { hits[k] = closestHit(rays[k]); });
#if BT_PACKET_AVX
  static const bool avx = __builtin_cpu_supports("avx");
#else
  constexpr bool avx = false;
#endif
  if (mask != 0) avx ? walk.run<true>(mask) : walk.run<false>(mask);
  for (uint64_t m = mask; m != 0; m &= m - 1) {
    const int k = std::countr_zero(m);
    hits[size_t(k)] = (walk.found >> k) & 1 ? std::optional<Hit>(walk.best[k]) : std::nullopt;
  }
}

} // namespace bt
