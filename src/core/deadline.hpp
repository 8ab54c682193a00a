#pragma once
// A time limit for long exact computations (the hidden-line drawing's): checked now and then
// by the work, which stops by throwing DeadlinePassed, so the caller can say so and fall back.

#include <chrono>
#include <cstdint>
#include <stdexcept>

namespace hsr::detail {

struct Deadline {
  std::chrono::steady_clock::time_point at = std::chrono::steady_clock::time_point::max();
  bool passed() const { return std::chrono::steady_clock::now() > at; }
};

struct DeadlinePassed : std::runtime_error {
  DeadlinePassed() : std::runtime_error("the time limit was reached") {}
};

// Throws DeadlinePassed when `deadline` is set and has passed; looked at every 64th `step`.
inline void checkDeadline(const Deadline* deadline, std::uint64_t step) {
  if (deadline && (step & 63) == 0 && deadline->passed()) throw DeadlinePassed();
}

}  // namespace hsr::detail
