#pragma once
// The one error type of the library: bad input (files, arguments, scene values) is reported
// by throwing hsr::Error with a message naming the file, line or polygon at fault.

#include <stdexcept>
#include <string>

namespace hsr {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace hsr
