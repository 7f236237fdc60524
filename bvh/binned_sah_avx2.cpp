// The binned SAH builder compiled with -mavx2 (bvh/CMakeLists.txt), run where the CPU has AVX2
// (sah_builder.cpp). The code is the same SSE intrinsics as the baseline's; this compilation
// encodes them with three operands (VEX), which drops the register copies that two-operand SSE
// needs, for fewer instructions per build. FMA is not enabled, so no multiply and add are
// contracted: every rounding is the baseline's and both build the same tree (tested).
//
// Everything of the builder is in bt::avx2's unnamed namespace, so nothing compiled here for
// AVX2 can stand in for the baseline's code, but for the standard library's templates: one
// that both compilations instantiate for the same types is merged by the linker, which keeps
// either copy, and an AVX2 copy would then run on CPUs without AVX2. So the builder leaves what
// would grow a std::vector to the baseline (resizeSlots()), and ctest's bvh_avx2_isolation
// checks that no function outside bt::avx2 in this file's object uses an AVX instruction.
#define BT_SAH_ISA avx2
#include "bvh/binned_sah/builder.h"
#include "bvh/binned_sah/isa_builds.h"

namespace bt::avx2 {

FlatBvh buildBinnedSah(std::span<const Aabb> boxes, const SahBuildSettings& settings) {
  return BinnedSahBuilder(boxes, settings).build();
}

} // namespace bt::avx2
