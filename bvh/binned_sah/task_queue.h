// The work queue of the binned SAH builder (see builder.h): the subtrees its threads take.
#pragma once

#include "bvh/binned_sah/simd_box.h"

#include <cstddef>
#include <vector>

#ifndef BT_SAH_ISA
#error "include from a binned_sah_<isa>.cpp, which names the instruction set's namespace"
#endif

namespace bt::BT_SAH_ISA {
namespace {

// A node to build with its subtree: where it goes (see the slot layout in build()), which of the
// two BoxRef buffers holds its boxes, and their bounds.
struct NodeTask {
  uint32_t slot, descendants;
  uint32_t begin, end;
  uint32_t depth;
  int buffer;
  int owner; // the thread whose task queue its child tasks go to
  Box4 bounds;
};

// One thread's task queue. The thread takes its newest task, the deepest, whose boxes it has
// just partitioned and still has in cache; an idle thread steals the oldest, the biggest, so
// that steals are few and each thread mostly builds subtrees of its own.
// A ring buffer: queued tasks are subtrees that no thread has started, so they hold disjoint
// boxes, and at most n / kTaskMinBoxes are queued at once.
class TaskQueue {
public:
  explicit TaskQueue(size_t capacity) : tasks_(capacity) {}
  bool empty() const { return size_ == 0; }
  void push(const NodeTask& task) { tasks_[(oldest_ + size_++) % tasks_.size()] = task; }
  NodeTask take(bool newest) {
    --size_;
    if (newest) return tasks_[(oldest_ + size_) % tasks_.size()];
    const NodeTask& task = tasks_[oldest_];
    oldest_ = (oldest_ + 1) % tasks_.size();
    return task;
  }

private:
  std::vector<NodeTask> tasks_;
  size_t oldest_ = 0, size_ = 0;
};

} // namespace
} // namespace bt::BT_SAH_ISA
