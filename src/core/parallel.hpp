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
