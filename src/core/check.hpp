#pragma once
// HSR_CHECK: internal invariants, always on (Release included), as pbrt's CHECK. A failed
// check is a programmer error, never bad input: it prints the expression, both values and
// file:line to stderr and aborts. Untrusted data must be refused with hsr::Error before it
// can reach a check.
//
//   HSR_CHECK(tiles > 0);
//   HSR_CHECK_EQ(frame.ids.size(), pixels);   // prints "frame.ids.size() == pixels (3 vs 4)"

#include <sstream>
#include <string>

namespace hsr::detail {

[[noreturn]] void checkFailed(const char* file, int line, const std::string& what);

template <class A, class B>
[[noreturn]] void checkOpFailed(const char* file, int line, const char* expr, const A& a,
                                const B& b) {
  std::ostringstream s;
  s << expr << " (" << a << " vs " << b << ")";
  checkFailed(file, line, s.str());
}

}  // namespace hsr::detail

#define HSR_CHECK(cond)                                                                  \
  do {                                                                                   \
    if (!(cond)) ::hsr::detail::checkFailed(__FILE__, __LINE__, "HSR_CHECK(" #cond ")"); \
  } while (false)

#define HSR_CHECK_OP_(a, op, b)                                                         \
  do {                                                                                  \
    const auto& hsr_check_a_ = (a);                                                     \
    const auto& hsr_check_b_ = (b);                                                     \
    if (!(hsr_check_a_ op hsr_check_b_))                                                \
      ::hsr::detail::checkOpFailed(__FILE__, __LINE__, #a " " #op " " #b, hsr_check_a_, \
                                   hsr_check_b_);                                       \
  } while (false)

#define HSR_CHECK_EQ(a, b) HSR_CHECK_OP_(a, ==, b)
#define HSR_CHECK_NE(a, b) HSR_CHECK_OP_(a, !=, b)
#define HSR_CHECK_LT(a, b) HSR_CHECK_OP_(a, <, b)
#define HSR_CHECK_LE(a, b) HSR_CHECK_OP_(a, <=, b)
#define HSR_CHECK_GT(a, b) HSR_CHECK_OP_(a, >, b)
#define HSR_CHECK_GE(a, b) HSR_CHECK_OP_(a, >=, b)
