// ConfinedIOSystem: every file an import opens is checked on its open descriptor (no race
// between the check and the read): a regular file, inside the model's folder. See the header.

#include "io/confined_io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <utility>

#include <assimp/DefaultIOStream.h>
#include <fmt/format.h>

namespace fs = std::filesystem;

namespace hsr::detail {
namespace {

// assimp's stream over a FILE*, whose constructor only its friends and heirs may call.
class FileStream : public Assimp::DefaultIOStream {
 public:
  FileStream(std::FILE* file, const std::string& name) : DefaultIOStream(file, name) {}
};

const char* kindOf(mode_t mode) {
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

bool inside(const fs::path& p, const fs::path& root) {
  const auto [r, q] = std::mismatch(root.begin(), root.end(), p.begin(), p.end());
  return r == root.end() && q != p.end();
}

}  // namespace

ConfinedIOSystem::ConfinedIOSystem(const fs::path& model, bool allow_outside,
                                   std::function<void(std::uint64_t)> on_open)
    : model_name_(model.string()), allow_outside_(allow_outside), on_open_(std::move(on_open)) {
  std::error_code ec;
  model_ = fs::canonical(model, ec);
  root_ = fs::canonical(fs::absolute(model).parent_path(), ec);
}

Assimp::IOStream* ConfinedIOSystem::refuse(std::string why) {
  if (refusal_.empty()) refusal_ = std::move(why);
  return nullptr;
}

bool ConfinedIOSystem::Exists(const char* file) const {
  struct stat st {};
  return file != nullptr && ::stat(file, &st) == 0;
}

Assimp::IOStream* ConfinedIOSystem::Open(const char* file, const char* mode) {
  if (file == nullptr || mode == nullptr) return nullptr;
  if (std::strpbrk(mode, "wa+") != nullptr)
    return refuse(fmt::format("{}: the importer asked to write {}; refused", model_name_, file));
  // Opened without blocking (a FIFO with no writer would stall the import), then checked.
  const int fd = ::open(file, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return nullptr;  // missing: the format decides (most skip a missing material file)
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    const char* kind = kindOf(st.st_mode);
    ::close(fd);
    return refuse(fmt::format("{}: references {}, which is {}, not a file; refused", model_name_,
                              file, kind));
  }
  // Where the open descriptor really is, symbolic links resolved
  std::error_code ec;
  const fs::path real = fs::read_symlink(fmt::format("/proc/self/fd/{}", fd), ec);
  const bool is_model = !ec && real == model_;
  if (!is_model && !allow_outside_ && (ec || !inside(real, root_))) {
    ::close(fd);
    return refuse(fmt::format(
        "{}: references {}{}, outside the model's folder {}; refused (--allow-outside-refs "
        "reads it)",
        model_name_, file, ec || real == fs::path(file) ? "" : " (" + real.string() + ")",
        root_.string()));
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  if (!is_model && on_open_) on_open_(static_cast<std::uint64_t>(st.st_size));
  std::FILE* f = ::fdopen(fd, "rb");
  if (f == nullptr) {
    ::close(fd);
    return nullptr;
  }
  return new FileStream(f, file);
}

}  // namespace hsr::detail
