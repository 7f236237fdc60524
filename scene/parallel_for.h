// One way to share independent work among threads, for the preparation steps that run on all
// cores (light grid, surface and bounce lights, texture decoding) and the CPU renderer's rows.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace bt {

// Runs fn(i) for every i in [0, count) on at most `threads` threads (0: one per core), the
// calling thread among them. Indices are handed out one at a time, so items of uneven cost
// still keep every thread busy; fn must not depend on which thread runs it.
template <typename Fn> void parallelFor(size_t count, unsigned threads, const Fn& fn) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  const size_t used = std::min<size_t>(threads, std::max<size_t>(count, 1));
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i = next++; i < count; i = next++) fn(i);
  };
  std::vector<std::thread> helpers;
  helpers.reserve(used - 1);
  for (size_t t = 1; t < used; ++t) helpers.emplace_back(work);
  work();
  for (std::thread& h : helpers) h.join();
}

} // namespace bt
