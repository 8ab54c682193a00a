#pragma once
// Reading a mesh file's header before assimp does. assimp 5.2 sizes its arrays from the
// counts in OFF and PLY headers before it reads any data, so a few bytes claiming billions of
// elements make it allocate and clear gigabytes; and it silently misreads a few inputs. These
// checks read each header the way assimp 5.2.5's own reader does (its line splitting, its
// number parsing, its keywords, which `format` line counts) and refuse, with one line, a file
// whose bytes cannot hold what its header declares.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace hsr::detail {

// The path's extension in lower case (".PLY" -> ".ply").
std::string lowerExtension(const std::filesystem::path& path);

// What the import must change for assimp to read a file right.
struct HeaderFix {
  // A binary PLY whose header ends in a bare "\n" and whose data starts with the byte 0x0A:
  // assimp 5.2 drops that byte as the second half of a "\r\n" and reads every value a byte
  // off (1 file in 256 with such headers). Nonzero: the offset of the header's last '\n',
  // before which a '\r' makes assimp read the data right.
  std::uint64_t insert_cr_at = 0;
};

// Throws hsr::Error naming the file when its header (OBJ, OFF or PLY, by extension; PLY also
// by content, as assimp recognises it) declares more than its `bytes` can hold, ends the way
// assimp 5.2 cannot read (a PLY header without end_header spins forever), or holds what
// assimp is known to misread or overflow on. Reads the first 64 KiB, and for PLY walks the
// data once without storing it: O(file size), constant memory. Safe on untrusted input.
HeaderFix checkHeaderAgainstSize(const std::filesystem::path& path, std::uintmax_t bytes);

// What the C++ runtime printed in the import child when an exception escaped inside the
// importer ("terminate called after throwing an instance of 'T'\n  what():  message"), as one
// phrase for the refusal ("an exception it did not catch: T: message"); empty if nothing of
// the kind.
std::string uncaughtException(std::string_view child_stderr);

}  // namespace hsr::detail
