// HSR_CHECK's failure path: one line on stderr, then abort (a core dump, a debugger stop, a
// fuzzer finding).

#include "core/check.hpp"

#include <cstdio>
#include <cstdlib>

namespace hsr::detail {

void checkFailed(const char* file, int line, const std::string& what) {
  std::fprintf(stderr, "hsr: internal check failed at %s:%d: %s\n", file, line, what.c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace hsr::detail
