// The binned SAH builder compiled for the x86-64 baseline (SSE2), which every x86-64 CPU runs.
#define BT_SAH_ISA sse2
#include "bvh/binned_sah/builder.h"
#include "bvh/binned_sah/isa_builds.h"

namespace bt::sse2 {

FlatBvh buildBinnedSah(std::span<const Aabb> boxes, const SahBuildSettings& settings) {
  return BinnedSahBuilder(boxes, settings).build();
}

} // namespace bt::sse2
