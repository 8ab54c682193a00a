#pragma once
// The part of oneTBB's interface hsr uses, run serially on the calling thread: for a build
// without threads (HSR_SERIAL, the WebAssembly module; include core/parallel.hpp, not this).
// Each call does what oneTBB's would do with one thread: a parallel_for visits its whole range
// in order, a parallel_reduce folds it into one accumulator, parallel_invoke calls its
// functions one after the other, and enumerable_thread_specific holds one value. hsr's results
// do not depend on the thread count, so they are the same bytes as the threaded build's
// (web/test/ checks that).

#include <cstddef>
#include <functional>
#include <optional>
#include <utility>

namespace tbb {

template <class Value>
class blocked_range {
 public:
  blocked_range(Value begin, Value end, std::size_t = 1) : begin_(begin), end_(end) {}
  Value begin() const { return begin_; }
  Value end() const { return end_; }
  std::size_t size() const { return static_cast<std::size_t>(end_ - begin_); }
  bool empty() const { return !(begin_ < end_); }

 private:
  Value begin_, end_;
};

template <class Value>
class blocked_range2d {
 public:
  blocked_range2d(Value row_begin, Value row_end, std::size_t, Value col_begin, Value col_end,
                  std::size_t)
      : rows_(row_begin, row_end), cols_(col_begin, col_end) {}
  const blocked_range<Value>& rows() const { return rows_; }
  const blocked_range<Value>& cols() const { return cols_; }

 private:
  blocked_range<Value> rows_, cols_;
};

// parallel_for(first, last, f): f(i) for every i in [first, last)
template <class Index, class Function>
void parallel_for(Index first, Index last, const Function& f) {
  for (Index i = first; i < last; ++i) f(i);
}

// parallel_for(range, body): body(range), the whole range at once
template <class Range, class Body>
void parallel_for(const Range& range, const Body& body) {
  body(range);
}

template <class Range, class Value, class Body, class Join>
Value parallel_reduce(const Range& range, const Value& identity, const Body& body, const Join&) {
  return body(range, identity);
}

template <class... Functions>
void parallel_invoke(const Functions&... functions) {
  (functions(), ...);
}

template <class T>
class enumerable_thread_specific {
 public:
  enumerable_thread_specific() = default;
  template <class Init>
  explicit enumerable_thread_specific(Init init) : init_(std::move(init)) {}
  T& local() {
    if (!value_) {
      if (init_)
        value_.emplace(init_());
      else
        value_.emplace();
    }
    return *value_;
  }
  // The values made so far: none or one
  T* begin() { return value_ ? &*value_ : nullptr; }
  T* end() { return value_ ? &*value_ + 1 : nullptr; }
  const T* begin() const { return value_ ? &*value_ : nullptr; }
  const T* end() const { return value_ ? &*value_ + 1 : nullptr; }

 private:
  std::function<T()> init_;
  std::optional<T> value_;
};

class task_arena {
 public:
  task_arena() = default;
  explicit task_arena(int) {}
  template <class Function>
  auto execute(const Function& f) const {
    return f();
  }
  int max_concurrency() const { return 1; }
};

namespace this_task_arena {
inline int max_concurrency() { return 1; }
inline int current_thread_index() { return 0; }
}  // namespace this_task_arena

namespace info {
inline int default_concurrency() { return 1; }
}  // namespace info

}  // namespace tbb
