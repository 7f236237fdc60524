// The parallel root split of the binned SAH builder (see builder.h): all threads read, bin and
// partition the root's boxes together, chunk by chunk.
//
// Alone, the root's split (binning and partitioning every box) keeps the other threads idle for
// a good part of the build. Here the boxes are cut into chunks that the threads take one at
// a time, in three stages: read (and check) them, bin them, partition them. The thread that
// finishes a stage's last chunk does what joins the chunks (the root's bounds, the split from
// the merged bins, the root's child tasks) and opens the next stage. No thread waits for another
// to arrive: a helper that starts late (starting a thread takes a tenth of a millisecond, more
// on a busy machine) finds chunks left or none, and one that is descheduled holds up no more
// than its chunk. The merged bins are exactly those of one pass over all boxes and each chunk's
// boxes keep their order, so the tree is the same as a one-thread build's.
#pragma once

#include "bvh/binned_sah/partition.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstring>
#include <vector>

#ifndef BT_SAH_ISA
#error "include from a binned_sah_<isa>.cpp, which names the instruction set's namespace"
#endif

namespace bt::BT_SAH_ISA {
namespace {

enum RootStage : int { kRead, kBin, kPartition, kBuilt };

// Hands out the jobs (chunks) of each stage, one at a time, until none is left.
class StagedJobs {
public:
  explicit StagedJobs(uint32_t jobs) : jobs_(jobs) {}

  // Runs `job` on the jobs of stage s until none is left. The thread that finishes the last one
  // runs `join` and opens the next stage; the others wait for that (when `wait`).
  template <class Job, class Join> void run(RootStage s, Job&& job, Join&& join, bool wait) {
    for (uint32_t j; (j = nextJob_[s].fetch_add(1)) < jobs_;) {
      job(j);
      if (jobsDone_[s].fetch_add(1) + 1 == jobs_) {
        join();
        stage_.store(s + 1);
        stage_.notify_all();
      }
    }
    if (!wait) return;
    for (int now; (now = stage_.load()) <= s;) stage_.wait(now);
  }

private:
  uint32_t jobs_;
  std::atomic<int> stage_{kRead};
  std::array<std::atomic<uint32_t>, kBuilt> nextJob_{}, jobsDone_{};
};

// The root's boxes in chunks, and what each chunk's stage leaves for the stage's join.
struct RootChunks {
  // Everything the threads use is allocated here, before they start. Each thread's bins are
  // cleared here too, as a thread may start too late to bin any chunk.
  RootChunks(uint32_t boxCount, int threads, uint32_t chunkCount, int bins)
      : boxes(boxCount), chunks(chunkCount), binCount(bins), threadBins(threads), chunkCounts(size_t{chunks} * binCount),
        chunkBounds(chunks), invalid(chunks), leftBegin(chunks), rightBegin(chunks) {
    for (Bins& b : threadBins) b.clear(binCount);
  }

  uint32_t begin(uint32_t c) const { return static_cast<uint32_t>(uint64_t{boxes} * c / chunks); }

  // The read stage's join: the root's bounds and the bin mapping. Returns the first invalid box.
  uint32_t joinRead(Box4& rootBounds) {
    uint32_t firstInvalid = std::numeric_limits<uint32_t>::max();
    Box4 rootCentroids;
    for (uint32_t c = 0; c < chunks; ++c) {
      firstInvalid = std::min(firstInvalid, invalid[c]);
      rootBounds.grow(chunkBounds[c][0]);
      rootCentroids.grow(chunkBounds[c][1]);
    }
    mapping = binMappingFor(rootCentroids, binCount);
    return firstInvalid;
  }

  void binChunk(int thread, uint32_t c, const BoxRef* src) {
    const uint32_t first = begin(c), end = begin(c + 1);
    Bins chunkBins;
    binBoxes(src + first, end - first, 1, mapping, binCount, chunkBins);
    threadBins[thread].merge(chunkBins, binCount);
    std::memcpy(&chunkCounts[size_t{c} * binCount], chunkBins.count, sizeof(chunkCounts[0]) * binCount);
  }

  // The bin stage's join: the root's split, from the merged bins.
  const Split& joinBins() {
    Bins all = threadBins[0];
    for (size_t t = 1; t < threadBins.size(); ++t) all.merge(threadBins[t], binCount);
    split = bestBinnedSplit(all, boxes, mapping, binCount);
    return split;
  }

  // Where each chunk's boxes go: after those of the chunks before it, on either side.
  void place() {
    uint32_t left = 0, right = split.leftCount;
    for (uint32_t c = 0; c < chunks; ++c) {
      leftBegin[c] = left, rightBegin[c] = right;
      uint32_t leftInChunk = 0;
      for (int b = 0; b <= split.lastLeftBin; ++b) leftInChunk += static_cast<uint32_t>(chunkCounts[size_t{c} * binCount + b][split.axis]);
      left += leftInChunk;
      right += begin(c + 1) - begin(c) - leftInChunk;
    }
  }

  void partitionChunk(uint32_t c, const BoxRef* src, BoxRef* dst) const {
    const uint32_t first = begin(c), end = begin(c + 1);
    Box4 unused[2];
    partition<SplitKind::kBinned>(src + first, dst + leftBegin[c], dst + rightBegin[c], end - first, split, unused);
  }

  const uint32_t boxes, chunks;
  const int binCount;
  std::vector<Bins> threadBins;
  std::vector<std::array<int32_t, 4>> chunkCounts; // binCount per chunk: places its boxes in the partition
  std::vector<std::array<Box4, 2>> chunkBounds;    // [bounds, centroids]
  std::vector<uint32_t> invalid;                   // first invalid box
  std::vector<uint32_t> leftBegin, rightBegin;     // where the boxes go
  BinMapping mapping{};
  Split split;
};

} // namespace
} // namespace bt::BT_SAH_ISA
