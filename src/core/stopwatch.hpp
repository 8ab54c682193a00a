#pragma once
// The one way a stage is timed: a stopwatch started when made, read in milliseconds. Every
// stage time in Stats and every build time comes from it.

#include <chrono>

namespace hsr::detail {

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}

  // Milliseconds since the start.
  double ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_)
        .count();
  }
  void restart() { start_ = std::chrono::steady_clock::now(); }
  // Milliseconds since the start, and a new start: one stage after another.
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - start_).count();
    start_ = now;
    return ms;
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace hsr::detail
