#pragma once
// The pictures of a frame's buffers (hsr/io.hpp's depthPicture, idPicture, overdrawPicture,
// picture), made in pictures.cpp: pure functions of the frame, apart from the file writers
// (writers.cpp) so that the web page's module, which writes no files, has them too.

#include <cstddef>

#include "hsr/render.hpp"

namespace hsr::detail {

// The frame's pixel count, 0 for an empty frame
inline std::size_t framePixels(const Frame& frame) {
  if (frame.width <= 0 || frame.height <= 0) return 0;
  return static_cast<std::size_t>(frame.width) * static_cast<std::size_t>(frame.height);
}

}  // namespace hsr::detail
