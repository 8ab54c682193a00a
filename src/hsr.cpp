// The umbrella header's one definition: the library's version (include/hsr/hsr.hpp).

#include "hsr/hsr.hpp"

#ifndef HSR_VERSION
#error "HSR_VERSION is set by CMakeLists.txt from the project's version"
#endif

namespace hsr {

std::string_view version() { return HSR_VERSION; }

}  // namespace hsr
