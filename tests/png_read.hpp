#pragma once
// Reading PNG outputs back in tests, independently of hsr's writer: stb_image decodes them.
// One translation unit (png_read.cpp) holds the decoder.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace hsr::testing {

// A decoded picture as 8-bit RGB, row 0 = the top row (as PNG stores it). A file or buffer
// that does not decode gives width = height = 0 and `error` says why.
struct DecodedPng {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // width * height * 3
  std::string error;

  bool ok() const { return width > 0 && height > 0; }
};

DecodedPng decodePng(const std::filesystem::path& file);
DecodedPng decodePngBytes(std::string_view bytes);

}  // namespace hsr::testing
