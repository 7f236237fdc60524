// Hole squeezing for the binned SAH builder (see builder.h): the slots that its tasks reserved
// but did not use, taken out of the finished tree.
#pragma once

#include "scene/gpu_structs.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#ifndef BT_SAH_ISA
#error "include from a binned_sah_<isa>.cpp, which names the instruction set's namespace"
#endif

namespace bt::BT_SAH_ISA {
namespace {

// The final layout is the slots in their order with the holes squeezed out, which is the
// depth-first layout (see BinnedSahBuilder::build()). Each stretch between two holes moves down
// by the size of the holes before it, in place, in slot order: a slot moves to one before it, so
// none is overwritten before it has moved. Done by one thread: in place, the threads could not
// move stretches side by side without one overwriting another's before it moved, and a second
// array of slots to lay out from cost more (its pages, fresh each build) than the threads saved.
class SlotHoles {
public:
  // Allocated before the build's threads start: adding a hole then never allocates up to n.
  void reserve(size_t n) {
    holes_.reserve(n);
    holeEnds_.reserve(n);
    holeShifts_.reserve(n);
  }
  void add(uint32_t begin, uint32_t size) { holes_.push_back({begin, size}); }

  // Squeezes the holes out of slots[0, slotCount); returns the slots left.
  uint32_t squeeze(GpuBvhNode* slots, uint32_t slotCount) {
    std::sort(holes_.begin(), holes_.end(), [](const Hole& a, const Hole& b) { return a.begin < b.begin; });
    uint32_t shift = 0;
    for (const Hole& hole : holes_) {
      shift += hole.size;
      holeEnds_.push_back(hole.begin + hole.size);
      holeShifts_.push_back(shift);
    }
    const uint32_t total = slotCount - shift;
    uint32_t from = 0;
    shift = 0;
    for (size_t h = 0; h <= holes_.size(); ++h) {
      const uint32_t end = h < holes_.size() ? holes_[h].begin : slotCount;
      moveStretch(slots, from, end, shift);
      if (h < holes_.size()) from = holeEnds_[h], shift = holeShifts_[h];
    }
    return total;
  }

private:
  struct Hole {
    uint32_t begin, size;
  };

  // How far slot i moves down: the size of the holes before it.
  uint32_t shiftOf(uint32_t i) const {
    const size_t before = std::upper_bound(holeEnds_.begin(), holeEnds_.end(), i) - holeEnds_.begin();
    return before == 0 ? 0 : holeShifts_[before - 1];
  }

  // Moves slots [from, end), a stretch between two holes, down by `shift`, and their child
  // indices with them. A node's children lie after it, mostly in the same stretch; a child
  // past the stretch's end (the right child of a node whose left child was a task) looks its
  // shift up.
  void moveStretch(GpuBvhNode* slots, uint32_t from, uint32_t end, uint32_t shift) const {
    for (uint32_t i = from; i < end; ++i) {
      GpuBvhNode node = slots[i];
      if (node.count == 0) node.leftFirst -= node.leftFirst < end ? shift : shiftOf(node.leftFirst);
      slots[i - shift] = node;
    }
  }

  std::vector<Hole> holes_;                     // sorted by squeeze()
  std::vector<uint32_t> holeEnds_, holeShifts_; // by squeeze(): each hole's end, the holes' size up to it
};

} // namespace
} // namespace bt::BT_SAH_ISA
