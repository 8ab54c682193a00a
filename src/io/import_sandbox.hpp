#pragma once
// The import sandbox. assimp is third-party C++ that reads untrusted bytes, and some malformed
// files crash it (found by fuzzing: a binary PLY with a bodiless element segfaults inside its
// reader). So an import runs in a forked child process that sends the scene back through a
// pipe, under a memory budget sized by the file and a time limit (ImportLimits); a crash, a
// hang or runaway memory there becomes one clear hsr::Error here, never a crash. Where no pipe
// or child can be made, the import runs in process.

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "hsr/io.hpp"
#include "hsr/scene.hpp"

namespace hsr::detail {

// Limits on untrusted input, checked before anything is allocated for it.
constexpr std::uintmax_t kMaxFileBytes = 2ull << 30;  // 2 GiB
constexpr std::uint32_t kMaxCameras = 4096;           // a file's cameras kept to choose from

struct SandboxJob {
  std::string file;         // named in every refusal
  std::uint64_t bytes = 0;  // the model's size: the memory budget starts from it
  const ImportLimits& limits;
  // The import itself. `over_budget` is the line to throw on bad_alloc (in the child it is kept
  // current as referenced files are counted); `on_reference`, in the child, counts the bytes of
  // each file the model references into the budget (null in process); `in_child` says where it
  // runs (a child may leave its memory to _exit).
  std::function<Scene(const std::string& over_budget,
                      std::function<void(std::uint64_t)> on_reference, bool in_child)>
      run;
};

// The first line of a message (assimp's, the C++ runtime's), trimmed; "unknown error" if empty.
std::string firstLine(std::string_view message);

// The job's scene, or hsr::Error with one line naming the file.
Scene importInSandbox(const SandboxJob& job);

}  // namespace hsr::detail
