// libFuzzer target: bytes -> hsr::readBsp -> render at 32x24. The BSP file's reader is fed
// what the fuzzer makes, in two ways chosen by the first byte: as it is (so the header's
// checks are exercised), or with the header's size and CRC-32 made right for the rest (so that
// mutations reach the payload's parser instead of stopping at the checksum). A tree that loads
// is rendered from its scene's framing. hsr::Error is the expected answer to a bad file;
// anything else (crash, sanitizer report, huge allocation, hang) is a finding.

#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "hsr/bsp.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  if ((data[0] & 1) && bytes.size() >= 24) {
    const std::uint64_t payload = bytes.size() - 24;
    const auto crc = static_cast<std::uint32_t>(crc32_z(
        crc32_z(0, nullptr, 0), reinterpret_cast<const Bytef*>(bytes.data() + 24), payload));
    for (int i = 0; i < 4; ++i) bytes[12 + i] = static_cast<char>(crc >> (8 * i));
    for (int i = 0; i < 8; ++i) bytes[16 + i] = static_cast<char>(payload >> (8 * i));
  }
  try {
    const hsr::Bsp bsp = hsr::readBsp(bytes, "fuzz.bsp");
    hsr::RenderOptions options;
    options.threads = 1;
    hsr::render(bsp, hsr::frameScene(bsp.scene(), 32, 24), options);
  } catch (const hsr::Error&) {
  }
  return 0;
}
