// The reference the binned builder is measured against: an exact full-sweep SAH builder that
// tries every split between consecutive centroids on every axis (MacDonald and Booth), with the
// same leaf rule (shouldSplit) and cost model. O(n log^2 n); for tests only.
#pragma once

#include "bvh/sah_builder.h"

#include <span>

namespace bt::test {

FlatBvh buildFullSweepSah(std::span<const Aabb> boxes, int leafSize);

} // namespace bt::test
