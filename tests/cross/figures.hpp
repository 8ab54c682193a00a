#pragma once
// Small helpers for the cross-checking tests: the
// "[ figures ]" lines that feed the README's Reliability table, and buffer hashes.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "test_util.hpp"

namespace hsr::testing {

// 13107200 -> "13,107,200".
inline std::string grouped(std::uint64_t v) {
  const std::string digits = std::to_string(v);
  std::string out;  // appended digit by digit: GCC 12 warns of inserts into a string, wrongly
  for (std::size_t k = 0; k < digits.size(); ++k) {
    if (k > 0 && (digits.size() - k) % 3 == 0) out.push_back(',');
    out.push_back(digits[k]);
  }
  return out;
}

// Percentage with enough digits to show small fractions: 0.0001%.
inline std::string percent(std::uint64_t part, std::uint64_t whole) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f%%", whole ? 100.0 * double(part) / double(whole) : 0.0);
  return buf;
}

// One line for the README's Reliability table.
inline void printFigures(const std::string& line) {
  std::printf("[ figures ] %s\n", line.c_str());
  std::fflush(stdout);
}

// FNV-1a, 64 bits, over the bytes of a buffer (floats by their bit patterns).
template <class T, class Alloc>
std::uint64_t fnv1a64(const std::vector<T, Alloc>& v) {
  std::uint64_t h = 0xCBF29CE484222325ull;
  const unsigned char* p = reinterpret_cast<const unsigned char*>(v.data());
  for (std::size_t i = 0; i < v.size() * sizeof(T); ++i) {
    h ^= p[i];
    h *= 0x100000001B3ull;
  }
  return h;
}

}  // namespace hsr::testing
