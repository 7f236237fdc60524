// The binned SAH builder's compilations, one per instruction set (binned_sah_<isa>.cpp), among
// which buildBinnedSah() picks at run time (sah_builder.cpp).
#pragma once

#include "bvh/sah_builder.h"

#include <cstddef>
#include <vector>

namespace bt {
// slots.resize(count) for the builders, compiled for the baseline (sah_builder.cpp): inlined into
// the AVX2 compilation, std::vector's growth would be an AVX2 copy of a function that the
// baseline also has, which the linker may keep for both (see binned_sah_avx2.cpp).
void resizeSlots(std::vector<GpuBvhNode>& slots, size_t count);

namespace sse2 {
FlatBvh buildBinnedSah(std::span<const Aabb> boxes, const SahBuildSettings& settings);
} // namespace sse2
#if defined(BT_SAH_BUILDER_AVX2)
namespace avx2 {
FlatBvh buildBinnedSah(std::span<const Aabb> boxes, const SahBuildSettings& settings);
} // namespace avx2
#endif
} // namespace bt
