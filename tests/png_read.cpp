#include "png_read.hpp"

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace hsr::testing {

namespace {

DecodedPng take(stbi_uc* pixels, int w, int h) {
  DecodedPng png;
  if (pixels == nullptr) {
    png.error = stbi_failure_reason();
    return png;
  }
  png.width = w;
  png.height = h;
  png.rgb.assign(pixels, pixels + static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  stbi_image_free(pixels);
  return png;
}

}  // namespace

DecodedPng decodePng(const std::filesystem::path& file) {
  int w = 0, h = 0, channels = 0;
  stbi_uc* pixels = stbi_load(file.c_str(), &w, &h, &channels, 3);
  return take(pixels, w, h);
}

DecodedPng decodePngBytes(std::string_view bytes) {
  int w = 0, h = 0, channels = 0;
  stbi_uc* pixels = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                                          static_cast<int>(bytes.size()), &w, &h, &channels, 3);
  return take(pixels, w, h);
}

}  // namespace hsr::testing
