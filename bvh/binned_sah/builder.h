// The binned SAH builder's skeleton: the top-down loop over nodes, its threads and their work
// queue. The ideas it is built from each have a header of their own in this folder: SSE boxes
// (simd_box.h), binning (binning.h), the small-subtree sweep (small_subtree.h), the partition
// (partition.h), the task queue (task_queue.h), the parallel root split (root_split.h) and hole
// squeezing (slot_holes.h).
//
// Compiled once per instruction set: binned_sah_<isa>.cpp defines BT_SAH_ISA, the namespace its
// compilation lives in (bt::sse2, bt::avx2), and includes this. Everything here is in an
// unnamed namespace within it, as it is private to that one translation unit.
#pragma once

#include "bvh/binned_sah/isa_builds.h"
#include "bvh/binned_sah/root_split.h"
#include "bvh/binned_sah/slot_holes.h"
#include "bvh/binned_sah/small_subtree.h"
#include "bvh/binned_sah/task_queue.h"

#include <algorithm>
#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>

#ifndef BT_SAH_ISA
#error "include from a binned_sah_<isa>.cpp, which names the instruction set's namespace"
#endif

namespace bt::BT_SAH_ISA {
namespace {

// Below this depth, nodes are split at the median along the widest centroid axis instead of by
// SAH, which bounds the depth at kMedianSplitDepth + log2(n) <= kBvhMaxDepth for n <= 2^24
// boxes. SAH trees of real levels stay well above it; only pathological inputs (geometric
// series of box sizes) reach it.
constexpr uint32_t kMedianSplitDepth = kBvhMaxDepth - 24;
// Subtrees of at least this many boxes go to the build's task queue, where an idle thread can
// take them; smaller ones are built by the thread that reached them. A task costs a lock, but
// the last subtrees, built while other threads have nothing left to take, are at most a few
// times this size, so that no thread waits long for another's (bench/README.md has the figures).
constexpr uint32_t kTaskMinBoxes = 256;
// A build too small to hand out a few tasks of a few thousand boxes is not worth starting a
// thread for.
constexpr uint32_t kThreadsMinBoxes = 4096;
constexpr uint32_t kMinBins = 8;                                 // see binCountFor()
constexpr uint32_t kSampledBinningMin = 2048, kBinSamples = 512; // see sampleStrideFor()

// Top-down binned SAH build. Each node: find the split (binned over the three axes at once,
// from a sample of the boxes in big nodes, an exact sweep for a few boxes), decide by shouldSplit(), move the boxes to the other BoxRef
// buffer partitioned, recurse. Subtrees of kTaskMinBoxes or more go to the task queue of the
// thread that reached them, which the other threads steal from when theirs is empty (see
// TaskQueue); every choice depends on the boxes alone, never on which thread
// builds what, so the tree is the same for any thread count.
//
// Before the build, the same threads read the input boxes, chunk by chunk: done by one thread,
// that pass held the others idle. After it, the thread that finishes the last task squeezes the
// holes that tasks leave out of the slots, in place (see layOut()).
class BinnedSahBuilder {
public:
  BinnedSahBuilder(std::span<const Aabb> boxes, const SahBuildSettings& settings)
      : settings_(settings), input_(boxes), count_(static_cast<uint32_t>(boxes.size())) {
    settings_.binCount = std::clamp(settings_.binCount, 2, kMaxBins);
    settings_.leafSize = std::max(settings_.leafSize, 1);
    const int threads = settings.threads > 0 ? settings.threads : static_cast<int>(std::thread::hardware_concurrency());
    threads_ = count_ < kThreadsMinBoxes ? 1 : std::max(threads, 1);
    // Uninitialised on purpose: every slot and entry is written before it is read.
    refs_[0].reset(new BoxRef[count_]);
    refs_[1].reset(new BoxRef[count_]);
    const size_t slotCount = count_ == 0 ? 0 : 2 * size_t{count_} - 1;
    order_.resize(count_);
    // The slots are the result, cut to the tree's size at the end (see build()). With threads,
    // the first thread sizes it while the others start (see sizeSlots()); everything the
    // threads use is allocated here, before they start: nothing they do can throw and leave the
    // others waiting at a barrier.
    if (threads_ == 1) {
      resizeSlots(nodes_, slotCount);
    } else {
      nodes_.reserve(slotCount);
    }
    slots_ = nodes_.data();
    // A hole per task at most (see build()). SAH trees of levels have about 2 n / kTaskMinBoxes
    // tasks (a node splits its boxes roughly in two); only pathological ones, splitting a few
    // boxes off at a time, have more, and these grow.
    holes_.reserve(2 * size_t{count_} / kTaskMinBoxes + 1);
  }

  FlatBvh build() {
    if (count_ == 0) return {};
    // Slot layout while building: a node in slot s with n boxes owns the 2n - 2 slots from
    // `descendants` on for its subtree: its two children first, then the left child's
    // descendants, then the right child's. A subtree built by the thread that reached it is
    // built left before right, so the right child's descendants go right after the left
    // child's, wherever they end: that is the depth-first layout, without holes, and all of
    // it with one thread. A left child handed to the task queue gets all its 2 nL - 2 slots,
    // as its size is not known yet, and the right child's descendants go after them; a task
    // that uses fewer leaves a hole at the end of its slots. So every slot is known before
    // the subtrees are built, threads never share a counter, and the tree is the same for any
    // thread count. The final layout squeezes the holes out (see layOut()).
    if (threads_ == 1) {
      NodeTask root{0, 1, 0, count_, 0, 0, 0, {}};
      Box4 centroids; // left to the root, which bins (see partition())
      const uint32_t invalid = readBoxes(0, count_, root.bounds, centroids);
      if (invalid != kNoBox) throwInvalidBox(invalid);
      resizeSlots(nodes_, 1 + buildNode(root)); // shrinks: no allocation
    } else {
      const uint32_t invalid = buildWithThreads();
      if (invalid != kNoBox) throwInvalidBox(invalid);
    }
    FlatBvh result;
    result.nodes = std::move(nodes_);
    result.order = std::move(order_);
    return result;
  }

private:
  static constexpr uint32_t kNoBox = std::numeric_limits<uint32_t>::max();
  // The threads split the root chunk by chunk (see buildWithThreads()): chunks of at least this
  // many boxes, and enough of them per thread that one thread can take over from a late one.
  static constexpr uint32_t kRootChunkMinBoxes = 2048;
  static constexpr uint32_t kRootChunksPerThread = 8;

  // Copies input boxes [begin, end) into refs_[0] and grows their bounds and centroid bounds.
  // Stops at the first box that is empty or has a non-finite bound and returns its index
  // (kNoBox when all are valid).
  uint32_t readBoxes(uint32_t begin, uint32_t end, Box4& bounds, Box4& centroids) {
    static_assert(sizeof(Aabb) == 24);
    const __m128 zero = _mm_setzero_ps();
    BoxRef* refs = refs_[0].get();
    for (uint32_t i = begin; i < end; ++i) {
      // An Aabb is six packed floats: min.xyz at 0, max.xyz at 12. Loading max from 8 on, as
      // (min.z, max.x, max.y, max.z), stays inside the box, also for the last one.
      const float* box = &input_[i].min.x;
      const __m128 lo = _mm_and_ps(_mm_loadu_ps(box), xyzMask());
      const __m128 hi = _mm_and_ps(_mm_shuffle_ps(_mm_loadu_ps(box + 2), _mm_loadu_ps(box + 2), _MM_SHUFFLE(3, 3, 2, 1)), xyzMask());
      // x - x is 0 for a finite x, NaN for an infinite or NaN one. Lane 3 is 0 in both.
      const __m128 finite = _mm_and_ps(_mm_cmpeq_ps(_mm_sub_ps(lo, lo), zero), _mm_cmpeq_ps(_mm_sub_ps(hi, hi), zero));
      if (_mm_movemask_ps(_mm_and_ps(finite, _mm_cmple_ps(lo, hi))) != 0xf) return i;
      _mm_storeu_ps(&refs[i].min.x, lo);
      _mm_storeu_ps(&refs[i].max.x, hi); // pad = lane 3 = 0
      refs[i].index = i;
      bounds.grow(lo, hi);
      const __m128 c = _mm_add_ps(lo, hi);
      centroids.grow(c, c);
    }
    return kNoBox;
  }

  [[noreturn]] void throwInvalidBox(uint32_t i) const {
    // Finite bounds keep every doubled centroid ordered (at worst +-inf, never NaN), which the
    // exact sweep's ranking and the partitions rely on.
    throw std::invalid_argument(input_[i].empty() ? "buildBinnedSah: empty box" : "buildBinnedSah: box with an infinite or NaN bound");
  }

  // The root split by all threads together (see root_split.h), then its subtrees through the task
  // queue. Returns the first invalid box, kNoBox if none.
  uint32_t buildWithThreads() {
    // Queued tasks hold disjoint boxes, kTaskMinBoxes or more (the root's children may have
    // fewer), so a queue of n / kTaskMinBoxes + 2 never overflows.
    queues_.assign(threads_, TaskQueue(count_ / kTaskMinBoxes + 2));
    const uint32_t chunkCount = std::clamp<uint32_t>(count_ / kRootChunkMinBoxes, 1, kRootChunksPerThread * threads_);
    RootChunks chunks(count_, threads_, chunkCount, binCountFor(count_));
    StagedJobs stages(chunkCount);
    NodeTask root{0, 1, 0, count_, 0, 0, 0, {}};
    uint32_t firstInvalid = kNoBox;
    bool together = false; // whether the threads split the root, or leave it to the task queue
    // The root's split counts as an unfinished task, so that work() waits for its children.
    unfinished_ = 1;
    const BoxRef* src = refs_[root.buffer].get();
    BoxRef* dst = refs_[1 - root.buffer].get();
    const auto readChunk = [&](uint32_t c) {
      chunks.invalid[c] = readBoxes(chunks.begin(c), chunks.begin(c + 1), chunks.chunkBounds[c][0], chunks.chunkBounds[c][1]);
    };
    const auto run = [&](int thread) {
      if (thread == 0) sizeSlots();
      stages.run(
          kRead, readChunk, [&] { firstInvalid = chunks.joinRead(root.bounds); }, true);
      if (firstInvalid != kNoBox) return;
      const auto binChunk = [&](uint32_t c) { chunks.binChunk(thread, c, src); };
      stages.run(
          kBin, binChunk, [&] { together = splitRootTogether(chunks, root); }, true);
      const auto partitionChunk = [&](uint32_t c) { chunks.partitionChunk(c, src, dst); };
      if (together)
        stages.run(
            kPartition, partitionChunk, [&] { queueRootChildren(root, chunks.split); }, false);
      work(thread); // returns once the last task is done and the tree laid out
    };
    {
      std::vector<std::jthread> helpers;
      for (int t = 1; t < threads_; ++t) helpers.emplace_back(run, t);
      run(0);
    }
    return firstInvalid;
  }

  // The bin stage's join: whether the threads split the root together. If not, the root goes to
  // the queue as an ordinary task, which takes over the unfinished count.
  bool splitRootTogether(RootChunks& chunks, const NodeTask& root) {
    const Split& split = chunks.joinBins();
    if (split.axis >= 0 && shouldSplit(count_, settings_.leafSize, root.bounds.halfArea(), split.childCost)) {
      chunks.place();
      return true;
    }
    std::lock_guard lock(mutex_);
    queues_[0].push(root);
    ++queuedTasks_;
    wake_.notify_one();
    return false;
  }

  // The partition stage's join: the root's node, and its children to the task queue.
  void queueRootChildren(const NodeTask& root, const Split& split) {
    waitForSlots();
    writeBounds(slots_[root.slot], root);
    NodeTask left{}, right{};
    setChildren(root, split.leftCount, left, right);
    right.descendants = left.descendants + 2 * split.leftCount - 2; // the left child is a task
    left.buffer = right.buffer = 1 - root.buffer;
    left.bounds = split.leftBounds, right.bounds = split.rightBounds;
    {
      std::lock_guard lock(mutex_);
      queues_[0].push(right);
      queues_[0].push(left);
      queuedTasks_ += 2;
      ++unfinished_; // two tasks in, the root's split out
    }
    wake_.notify_all();
  }

  // With threads, the slots (the result's array) are sized by the first thread while the others
  // start on the root's split, which writes no slot until it joins. Zero-filling them, which
  // std::vector's resize() cannot be kept from, takes a good part of a build (the pages are
  // fresh); done in the read stage, it held the other thread idle at its end. Within
  // the capacity reserved in the constructor, so it does not allocate.
  void sizeSlots() {
    resizeSlots(nodes_, 2 * size_t{count_} - 1);
    slotsSized_.store(true);
    slotsSized_.notify_all();
  }
  // Called before a thread writes a slot.
  void waitForSlots() const { slotsSized_.wait(false); }

  // Takes tasks until every task, including those that running tasks will still add, is done.
  // The thread that finishes the last one lays the tree out (see layOut()) before letting the
  // others go.
  void work(int thread) {
    waitForSlots();
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return queuedTasks_ > 0 || unfinished_ == 0; });
      if (queuedTasks_ == 0) return;
      NodeTask task = takeTask(thread);
      task.owner = thread;
      lock.unlock();
      const uint32_t used = buildNode(task);
      lock.lock();
      if (const uint32_t reserved = 2 * (task.end - task.begin) - 2; used < reserved) holes_.add(task.descendants + used, reserved - used);
      if (unfinished_ == 1) {
        layOut();
        unfinished_ = 0;
        wake_.notify_all();
      } else {
        --unfinished_;
      }
    }
  }

  // The thread's own newest task, or else the oldest of the first other thread that has one.
  // Called with mutex_ held and a task queued.
  NodeTask takeTask(int thread) {
    --queuedTasks_;
    for (int i = 0;; ++i) {
      TaskQueue& queue = queues_[(thread + i) % threads_];
      if (!queue.empty()) return queue.take(i == 0);
    }
  }

  void addTask(const NodeTask& task) {
    {
      std::lock_guard lock(mutex_);
      queues_[task.owner].push(task);
      ++queuedTasks_;
      ++unfinished_;
    }
    wake_.notify_one();
  }

  // Returns the slots that the leaf's descendants use: none.
  uint32_t makeLeaf(GpuBvhNode& node, const NodeTask& t) {
    node.leftFirst = t.begin;
    node.count = t.end - t.begin;
    const BoxRef* boxes = refs_[t.buffer].get();
    for (uint32_t i = t.begin; i < t.end; ++i) order_[i] = boxes[i].index;
    return 0;
  }

  // Writes the node's bounds with two stores, whose lane 3 lands in leftFirst and count: every
  // caller writes those afterwards.
  static void writeBounds(GpuBvhNode& node, const NodeTask& t) {
    static_assert(offsetof(GpuBvhNode, leftFirst) == 12 && offsetof(GpuBvhNode, count) == 28);
    _mm_storeu_ps(node.boundsMin, t.bounds.min);
    _mm_storeu_ps(node.boundsMax, t.bounds.max);
  }

  // Makes t's node the parent of `left` (t's first leftCount boxes) and `right` (the others):
  // their slots and boxes; their bounds and buffer are the caller's, and so is where the right
  // child's descendants go (see build()).
  void setChildren(const NodeTask& t, uint32_t leftCount, NodeTask& left, NodeTask& right) {
    GpuBvhNode& node = slots_[t.slot];
    node.leftFirst = t.descendants;
    node.count = 0;
    left.slot = t.descendants, right.slot = t.descendants + 1;
    left.descendants = t.descendants + 2;
    left.begin = t.begin, left.end = right.begin = t.begin + leftCount, right.end = t.end;
    left.depth = right.depth = t.depth + 1;
    left.owner = right.owner = t.owner;
  }

  // Builds t's subtree and returns how many slots from t.descendants on it uses: its node count
  // less one, plus the holes that its tasks may leave (see build()).
  uint32_t buildNode(const NodeTask& t) {
    const uint32_t count = t.end - t.begin;
    if (count <= kSmallSubtreeMax) return buildSmallSubtree(t);
    GpuBvhNode& node = slots_[t.slot];
    writeBounds(node, t);
    if (t.depth >= kMedianSplitDepth) return buildAtMedian(t);
    BoxRef* boxes = refs_[t.buffer].get() + t.begin;
    // Initialised from the call, not assigned: a Split is over a hundred bytes.
    const Split split = findBinnedSplit(boxes, count, sampleStrideFor(t), centroidBoundsOf(boxes, count), binCountFor(count));
    if (split.axis < 0) return buildAtMedian(t);
    if (!shouldSplit(count, settings_.leafSize, t.bounds.halfArea(), split.childCost)) return makeLeaf(node, t);
    NodeTask left{}, right{};
    Box4 bounds[2];
    const uint32_t leftCount = partition(boxes, refs_[1 - t.buffer].get() + t.begin, count, split, bounds);
    left.buffer = right.buffer = 1 - t.buffer;
    left.bounds = bounds[1], right.bounds = bounds[0];
    return buildChildren(t, leftCount, left, right);
  }

  // Makes `left` and `right`, whose bounds and buffer are set, t's children and builds them (or
  // hands the left one to the task queue); returns the slots that t's subtree uses.
  uint32_t buildChildren(const NodeTask& t, uint32_t leftCount, NodeTask& left, NodeTask& right) {
    setChildren(t, leftCount, left, right);
    uint32_t leftUsed = 2 * leftCount - 2; // all of its slots, for a task
    if (threads_ > 1 && leftCount >= kTaskMinBoxes) {
      addTask(left);
    } else {
      leftUsed = buildNode(left);
    }
    right.descendants = left.descendants + leftUsed;
    return 2 + leftUsed + buildNode(right);
  }

  // A node too deep for SAH (see kMedianSplitDepth), or with every centroid in one point so
  // that no SAH split exists: a leaf, or split at the median when too big for one. Its bounds
  // are written.
  uint32_t buildAtMedian(const NodeTask& t) {
    const uint32_t count = t.end - t.begin;
    if (count <= static_cast<uint32_t>(settings_.leafSize)) return makeLeaf(slots_[t.slot], t);
    BoxRef* boxes = refs_[t.buffer].get() + t.begin;
    NodeTask left{}, right{};
    const uint32_t leftCount = medianSplit(boxes, count, centroidBoundsOf(boxes, count));
    left.buffer = right.buffer = t.buffer;
    left.bounds = boundsOf(boxes, leftCount);
    right.bounds = boundsOf(boxes + leftCount, count - leftCount);
    return buildChildren(t, leftCount, left, right);
  }

  // The subtree of t, of kSmallSubtreeMax boxes or fewer (see SmallBoxes).
  uint32_t buildSmallSubtree(const NodeTask& t) {
    static_assert(kSmallSubtreeMax == 8);
    const BoxRef* refs = refs_[t.buffer].get() + t.begin;
    SmallBoxes boxes;
    switch (t.end - t.begin) {
    case 1: return buildSmallNode(boxes, loadSmallSubtree<1>(refs, boxes), t);
    case 2: return buildSmallNode(boxes, loadSmallSubtree<2>(refs, boxes), t);
    case 3: return buildSmallNode(boxes, loadSmallSubtree<3>(refs, boxes), t);
    case 4: return buildSmallNode(boxes, loadSmallSubtree<4>(refs, boxes), t);
    case 5: return buildSmallNode(boxes, loadSmallSubtree<5>(refs, boxes), t);
    case 6: return buildSmallNode(boxes, loadSmallSubtree<6>(refs, boxes), t);
    case 7: return buildSmallNode(boxes, loadSmallSubtree<7>(refs, boxes), t);
    default: return buildSmallNode(boxes, loadSmallSubtree<8>(refs, boxes), t);
    }
  }

  // Builds a node of a small subtree and its own subtree, as buildNode() does.
  uint32_t buildSmallNode(const SmallBoxes& boxes, const SmallNode& n, const NodeTask& t) {
    writeBounds(slots_[t.slot], t);
    if (n.count == 1) return makeSmallLeaf(boxes, n, t);
    if (t.depth >= kMedianSplitDepth) return buildSmallAtMedian(boxes, n, t);
    switch (n.count) {
    case 2: return buildSmallPair(boxes, n, t);
    case 3: return buildSmallInterior<3>(boxes, n, t);
    case 4: return buildSmallInterior<4>(boxes, n, t);
    case 5: return buildSmallInterior<5>(boxes, n, t);
    case 6: return buildSmallInterior<6>(boxes, n, t);
    case 7: return buildSmallInterior<7>(boxes, n, t);
    default: return buildSmallInterior<8>(boxes, n, t);
    }
  }

  template <uint32_t M> uint32_t buildSmallInterior(const SmallBoxes& boxes, const SmallNode& n, const NodeTask& t) {
    const SmallSplit split = findSmallSplit<M>(boxes, n);
    if (split.axis < 0) return buildSmallAtMedian(boxes, n, t);
    if (!shouldSplit(M, settings_.leafSize, t.bounds.halfArea(), split.childCost)) return makeSmallLeaf(boxes, n, t);
    SmallNode children[2];
    Box4 bounds[2];
    splitSmallNode<M>(boxes, n, split, children, bounds);
    NodeTask left{}, right{};
    setChildren(t, split.leftCount, left, right);
    left.buffer = right.buffer = t.buffer;
    left.bounds = bounds[1], right.bounds = bounds[0];
    const uint32_t leftUsed = buildSmallNode(boxes, children[1], left);
    right.descendants = left.descendants + leftUsed;
    return 2 + leftUsed + buildSmallNode(boxes, children[0], right);
  }

  // A node of two boxes, the most common interior node (SAH splits to about one box per leaf): a
  // leaf, or two one-box leaves with the lower centroid first. The one split puts one box on
  // each side and costs the same on every axis, so the first axis on which the centroids differ
  // takes it, as a sweep would choose.
  uint32_t buildSmallPair(const SmallBoxes& boxes, const SmallNode& n, const NodeTask& t) {
    const uint32_t a = n.slots[0], b = n.slots[1];
    const int differ = _mm_movemask_ps(_mm_cmpneq_ps(_mm_load_ps(boxes.centroid2[a]), _mm_load_ps(boxes.centroid2[b]))) & 7;
    if (differ == 0) return buildSmallAtMedian(boxes, n, t);
    const int axis = std::countr_zero(static_cast<unsigned>(differ));
    Box4 boxA, boxB;
    boxA.grow(boxes.lo[a], boxes.hi[a]);
    boxB.grow(boxes.lo[b], boxes.hi[b]);
    const double childCost = kSahBrushCost * (static_cast<double>(boxA.halfArea()) + boxB.halfArea());
    if (!shouldSplit(2, settings_.leafSize, t.bounds.halfArea(), childCost)) return makeSmallLeaf(boxes, n, t);
    const bool aFirst = boxes.centroid2[a][axis] <= boxes.centroid2[b][axis];
    GpuBvhNode& node = slots_[t.slot];
    node.leftFirst = t.descendants;
    node.count = 0;
    for (uint32_t child = 0; child < 2; ++child) {
      const uint32_t slot = (child == 0) == aFirst ? a : b;
      GpuBvhNode& leaf = slots_[t.descendants + child];
      _mm_storeu_ps(leaf.boundsMin, boxes.lo[slot]);
      _mm_storeu_ps(leaf.boundsMax, boxes.hi[slot]);
      leaf.leftFirst = t.begin + child;
      leaf.count = 1;
      order_[t.begin + child] = boxes.index[slot];
    }
    return 2;
  }

  // As makeLeaf(), the boxes in node order.
  uint32_t makeSmallLeaf(const SmallBoxes& boxes, const SmallNode& n, const NodeTask& t) {
    GpuBvhNode& node = slots_[t.slot];
    node.leftFirst = t.begin;
    node.count = n.count;
    for (uint32_t i = 0; i < n.count; ++i) order_[t.begin + i] = boxes.index[n.slots[i]];
    return 0;
  }

  // buildAtMedian() for a node of a small subtree, whose boxes it first writes to its place in
  // t's buffer, in node order (the small subtree read them from there and no longer needs them).
  uint32_t buildSmallAtMedian(const SmallBoxes& boxes, const SmallNode& n, const NodeTask& t) {
    if (n.count <= static_cast<uint32_t>(settings_.leafSize)) return makeSmallLeaf(boxes, n, t);
    BoxRef* refs = refs_[t.buffer].get() + t.begin;
    for (uint32_t i = 0; i < n.count; ++i) {
      const uint32_t slot = n.slots[i];
      _mm_storeu_ps(&refs[i].min.x, boxes.lo[slot]);
      _mm_storeu_ps(&refs[i].max.x, boxes.hi[slot]); // pad = lane 3 = 0
      refs[i].index = boxes.index[slot];
    }
    return buildAtMedian(t);
  }

  // Nodes of kSampledBinningMin boxes or more choose their split from every stride-th box, 512
  // to 1023 of them: that places the SAH's planes about as well as all of their boxes, for the
  // cost of binning a few. Smaller nodes bin every box: fewer samples in smaller nodes cost SAH
  // (bench/README.md). Never the root, which the
  // build's threads bin together (see buildWithThreads()).
  static uint32_t sampleStrideFor(const NodeTask& t) {
    const uint32_t count = t.end - t.begin;
    return t.depth == 0 || count < kSampledBinningMin ? 1 : count / kBinSamples;
  }

  // A node with few boxes gets fewer bins, as sweeping bins costs more than binning its boxes
  // there: 5/8 bin per box, at most 24 below 256 boxes, which costs fewer instructions than
  // more bins and keeps the SAH (bench/README.md has the figures). The SAH moves by a percent or two either way with the bin count on these levels (their
  // brushes sit on grids that bins of some widths fit better), so changes here need measuring.
  int binCountFor(uint32_t count) const {
    const int perBoxes = static_cast<int>(std::max(count * 5 / 8, kMinBins));
    const int cap = count < 256 ? std::min(settings_.binCount, 24) : settings_.binCount;
    return std::min(cap, perBoxes);
  }

  static uint32_t medianSplit(BoxRef* boxes, uint32_t count, const Box4& centroids) {
    const glm::vec3 extent = centroids.aabb().max - centroids.aabb().min;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t middle = count / 2;
    std::nth_element(boxes, boxes + middle, boxes + count,
                     [axis](const BoxRef& a, const BoxRef& b) { return a.centroid2(axis) < b.centroid2(axis); });
    return middle;
  }

  // Squeezes out the holes that tasks leave in the slots (see build()).
  void layOut() {
    resizeSlots(nodes_, holes_.squeeze(slots_, 2 * count_ - 1)); // shrinks: no allocation
  }

  SahBuildSettings settings_;
  std::span<const Aabb> input_;
  int threads_ = 1;
  uint32_t count_ = 0;
  std::unique_ptr<BoxRef[]> refs_[2]; // a node's boxes are in one; partitioning moves them to the other
  GpuBvhNode* slots_ = nullptr;       // nodes_'s storage, before the layout
  std::vector<uint32_t> order_;
  std::vector<GpuBvhNode> nodes_; // the result: slots_ laid out depth first
  SlotHoles holes_;               // with threads: the slots that tasks reserved but did not use

  std::atomic<bool> slotsSized_{false}; // see sizeSlots()
  std::mutex mutex_;                    // guards queues_, queuedTasks_, unfinished_ and holes_
  std::condition_variable wake_;
  std::vector<TaskQueue> queues_; // one per thread
  uint32_t queuedTasks_ = 0;
  uint32_t unfinished_ = 0; // tasks queued or running
};

} // namespace
} // namespace bt::BT_SAH_ISA
