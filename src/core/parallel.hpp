#pragma once
// Where hsr's threads come from: the one header every file that runs work in parallel
// includes. Natively that is oneTBB (parallel_for, parallel_reduce, parallel_invoke,
// enumerable_thread_specific, task_arena). A build without threads (HSR_SERIAL: the
// WebAssembly module of the web page, where Debian has no oneTBB) gets a serial stand-in with
// the same names and the same answers, since every result in hsr is the same at any thread
// count: core/serial_tbb.hpp.

#ifdef HSR_SERIAL
#include "core/serial_tbb.hpp"
#else
#include <tbb/blocked_range.h>
#include <tbb/blocked_range2d.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>
#endif

#include <memory>
#include <utility>
#include <vector>

namespace hsr::detail {

// The arena of `threads` workers that a calling thread renders in, made on its first use and
// kept for the thread's later calls. A fresh tbb::task_arena for every render was set up and
// torn down each time: at many small renders (a dataset's views, the test suites) that was a
// quarter of the run (3,150 renders of 256x256 frames: 1.1 s, 0.8 s with arenas kept).
inline tbb::task_arena& keptArena(int threads) {
  thread_local std::vector<std::pair<int, std::unique_ptr<tbb::task_arena>>> kept;
  for (auto& [count, arena] : kept)
    if (count == threads) return *arena;
  kept.emplace_back(threads, std::make_unique<tbb::task_arena>(threads));
  return *kept.back().second;
}

// Runs f with `threads` workers. Called from inside an arena (a render drawn from another's
// work), f runs there when that arena has the same count, else in an arena of its own made for
// this call: only threads outside every arena keep one (a worker's would outlive the pool).
template <class F>
void runWithThreads(int threads, const F& f) {
#ifndef HSR_SERIAL
  if (tbb::this_task_arena::current_thread_index() != tbb::task_arena::not_initialized) {
    if (tbb::this_task_arena::max_concurrency() == threads) {
      f();
    } else {
      tbb::task_arena(threads).execute(f);
    }
    return;
  }
#endif
  keptArena(threads).execute(f);
}

}  // namespace hsr::detail
