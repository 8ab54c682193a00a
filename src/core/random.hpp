#pragma once
// The one pseudo-random generator of the project (built-in scenes, tests, benchmarks).

#include <cstdint>

namespace hsr::detail {

// SplitMix64 (Steele, Lea & Flood 2014): tiny and identical everywhere, unlike the
// std::*_distribution classes whose output differs between standard libraries.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : s_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1) with 24 random bits: exact in float, no rounding up to 1.
  float uniform() { return static_cast<float>(next() >> 40) * 0x1.0p-24f; }
  float uniform(float lo, float hi) { return lo + uniform() * (hi - lo); }

 private:
  std::uint64_t s_;
};

}  // namespace hsr::detail
