#pragma once
// std::bit_cast for every standard library hsr is built with: libc++ 13, which Debian's
// Emscripten ships for the web page's build, has no std::bit_cast; GCC and Clang both have the
// builtin it is made of.

namespace hsr::detail {

template <class To, class From>
constexpr To bitCast(const From& from) noexcept {
  static_assert(sizeof(To) == sizeof(From), "bitCast: the two types differ in size");
  return __builtin_bit_cast(To, from);
}

}  // namespace hsr::detail
