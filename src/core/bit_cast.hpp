#pragma once
// std::bit_cast for every standard library hsr is built with: libc++ 13, which Debian's
// Emscripten ships for the web page's build, has no std::bit_cast; GCC and Clang both have the
// builtin it is made of. And std::nextafter(x, infinity) on its bits, inline (the library's is
// a call, which a ray's walk makes per triangle it tests).

#include <cmath>
#include <cstdint>
#include <limits>

namespace hsr::detail {

template <class To, class From>
constexpr To bitCast(const From& from) noexcept {
  static_assert(sizeof(To) == sizeof(From), "bitCast: the two types differ in size");
  return __builtin_bit_cast(To, from);
}

// The next float above x: std::nextafter(x, +infinity), bit for bit (pinned by a test)
inline float nextUp(float x) {
  if (std::isnan(x) || x == std::numeric_limits<float>::infinity()) return x;
  if (x == 0.0f) return std::numeric_limits<float>::denorm_min();
  const std::uint32_t bits = bitCast<std::uint32_t>(x);
  return bitCast<float>(x > 0.0f ? bits + 1 : bits - 1);
}

}  // namespace hsr::detail
