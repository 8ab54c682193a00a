// Atomic outputs: a temporary name in the target's directory, written, flushed to the disk,
// then renamed over the target (a directory: exchanged with it). See hsr/output.hpp.

#include "hsr/output.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <mutex>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "hsr/error.hpp"

namespace fs = std::filesystem;

namespace hsr {
namespace {

constexpr std::string_view kManifest = "manifest.json";

// ---- The temporaries of this process, for the signal handler ---------------------------------
// Fixed slots of absolute paths: the handler may not allocate or lock, only read these.
constexpr int kSlots = 64;
constexpr std::size_t kSlotPath = 4096;
enum SlotState : int { kFree = 0, kFilling = 1, kFile = 2, kDirectory = 3 };
struct Slot {
  std::atomic<int> state{kFree};
  char path[kSlotPath];
};
Slot g_slots[kSlots];

int claimSlot(const fs::path& path, SlotState kind) {
  const std::string s = fs::absolute(path).string();
  if (s.size() >= kSlotPath) return -1;  // not cleaned on a signal, still removed on failure
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (g_slots[i].state.compare_exchange_strong(expected, kFilling)) {
      std::memcpy(g_slots[i].path, s.c_str(), s.size() + 1);
      g_slots[i].state.store(kind);
      return i;
    }
  }
  return -1;
}

void releaseSlot(int slot) {
  if (slot >= 0) g_slots[slot].state.store(kFree);
}

// ---- The outputs this process has replaced, for the signal handler's report -------------------
// The first kReplacedKept paths in fixed arrays, each noted before its rename (pending) and
// marked done after it: a signal that comes between the two, on any thread, finds it pending.
constexpr int kReplacedKept = 16;
enum ReplacedState : int { kPending = 1, kDone = 2 };
char g_replaced[kReplacedKept][kSlotPath];
std::atomic<int> g_replaced_state[kReplacedKept];
std::atomic<int> g_replaced_count{0};
std::mutex g_replaced_mutex;  // writers one at a time (the handler only reads, never locks)

// Notes `path` as about to be replaced; returns its entry for replacedDone.
int noteReplacing(const fs::path& path) {
  const std::lock_guard<std::mutex> lock(g_replaced_mutex);
  std::error_code ec;
  const std::string s = fs::absolute(path, ec).string();
  const int n = g_replaced_count.load();
  if (n < kReplacedKept) {
    if (s.size() < kSlotPath)
      std::memcpy(g_replaced[n], s.c_str(), s.size() + 1);
    else
      g_replaced[n][0] = '\0';
    g_replaced_state[n].store(kPending);
  }
  g_replaced_count.store(n + 1);  // after the path: the handler reads only what is complete
  return n;
}

void replacedDone(int entry) {
  if (entry < kReplacedKept) g_replaced_state[entry].store(kDone);
}

const char* keptPath(int entry) noexcept {
  return g_replaced[entry][0] != '\0' ? g_replaced[entry] : "(a path too long to keep)";
}

void writeText(int fd, const char* text) noexcept {
  std::size_t left = std::strlen(text);
  while (left > 0) {
    const ssize_t n = ::write(fd, text, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    text += n, left -= static_cast<std::size_t>(n);
  }
}

// Removes a flat directory's files and the directory, with system calls only (async-signal-safe).
void removeFlatDirectory(const char* path) noexcept {
  const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    alignas(8) char buf[4096];
    for (;;) {
      const long n = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
      if (n <= 0) break;
      for (long at = 0; at < n;) {
        // struct linux_dirent64: ino (8), off (8), reclen (2), type (1), name
        unsigned short reclen;
        std::memcpy(&reclen, buf + at + 16, sizeof reclen);
        const char* name = buf + at + 19;
        if (std::strcmp(name, ".") != 0 && std::strcmp(name, "..") != 0) ::unlinkat(fd, name, 0);
        at += reclen;
      }
    }
    ::close(fd);
  }
  ::rmdir(path);
}

// ---- Errors ------------------------------------------------------------------------------------
[[noreturn]] void fail(const fs::path& path, std::string_view what, int error) {
  throw Error(fmt::format("{}: {}: {}", path.string(), what, std::strerror(error)));
}

// A temporary name beside `target`: hidden, naming the target, this process and a counter, and
// within the 255 bytes a file name may have.
fs::path temporaryBeside(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  std::string name = target.filename().string();
  if (name.size() > 160) name.resize(160);
  const fs::path dir = target.parent_path();
  return dir / fmt::format(".{}.hsr-tmp-{}-{}", name, ::getpid(), counter++);
}

void createParent(const fs::path& target) {
  const fs::path parent = target.parent_path();
  if (parent.empty()) return;
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec)
    throw Error(fmt::format("{}: cannot create its directory {}: {}", target.string(),
                            parent.string(), ec.message()));
}

// Writes every piece to fd; 0 or the error.
int writePieces(int fd, std::initializer_list<std::string_view> pieces) {
  for (std::string_view piece : pieces) {
    while (!piece.empty()) {
      const ssize_t n = ::write(fd, piece.data(), piece.size());
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return n < 0 ? errno : ENOSPC;
      piece.remove_prefix(static_cast<std::size_t>(n));
    }
  }
  return 0;
}

void writeInPlace(const fs::path& path, std::initializer_list<std::string_view> pieces) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) fail(path, "cannot write", errno);
  int error = writePieces(fd, pieces);
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) fail(path, "cannot write", error);
}

// Writes every piece to a new file at `temporary`, then flushes it to the disk; on failure the
// file is removed and the error names `target`.
void writeNewFile(const fs::path& temporary, const fs::path& target,
                  std::initializer_list<std::string_view> pieces) {
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) fail(target, "cannot write", errno);
  int error = writePieces(fd, pieces);
  if (error == 0 && ::fdatasync(fd) != 0 && errno != EINVAL) error = errno;
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) {
    ::unlink(temporary.c_str());
    fail(target, "cannot write", error);
  }
}

void writeRegularFile(const fs::path& path, std::initializer_list<std::string_view> pieces) {
  createParent(path);
  fs::path temporary = temporaryBeside(path);
  const int slot = claimSlot(temporary, kFile);
  try {
    writeNewFile(temporary, path, pieces);
  } catch (...) {
    releaseSlot(slot);
    throw;
  }
  const int entry = noteReplacing(path);
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    releaseSlot(slot);
    fail(path, "cannot put it in place", error);  // its entry stays pending: old, as it says
  }
  replacedDone(entry);
  releaseSlot(slot);
}

bool isHsrManifest(const fs::path& manifest) {
  std::error_code ec;
  const auto size = fs::file_size(manifest, ec);
  if (ec || size > (1u << 20)) return false;
  std::ifstream in(manifest, std::ios::binary);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  return j.is_object() && j.contains("written_by") && j["written_by"] == "hsr";
}

}  // namespace

void removeTemporaryOutputs() noexcept {
  for (Slot& s : g_slots) {
    const int state = s.state.load();
    if (state == kFile) ::unlink(s.path);
    if (state == kDirectory) removeFlatDirectory(s.path);
  }
}

void reportReplacedOutputs(int fd) noexcept {
  const int n = g_replaced_count.load();
  int done = n > kReplacedKept ? n - kReplacedKept : 0;
  const char* pending = nullptr;
  for (int i = 0; i < n && i < kReplacedKept; ++i) {
    if (g_replaced_state[i].load() == kDone)
      done++;
    else
      pending = keptPath(i);
  }
  if (done == 0 && pending == nullptr) {
    writeText(fd,
              "hsr: stopped by a signal before it replaced any output: every output is as an "
              "earlier run left it\n");
    return;
  }
  writeText(fd, "hsr: stopped by a signal after it replaced ");
  char number[24];
  char* first = number + sizeof number - 1;  // the digits written from the end
  *first = '\0';
  for (int v = done; v > 0 || first == number + sizeof number - 1; v /= 10)
    *--first = static_cast<char>('0' + v % 10);
  writeText(fd, first);
  writeText(fd, done == 1 ? " output" : " outputs");
  for (int i = 0, listed = 0; i < n && i < kReplacedKept; ++i) {
    if (g_replaced_state[i].load() != kDone) continue;
    writeText(fd, listed++ == 0 ? ": " : ", ");
    writeText(fd, keptPath(i));
  }
  if (n > kReplacedKept) writeText(fd, ", ...");
  if (pending != nullptr) {
    writeText(fd, "; ");
    writeText(fd, pending);
    writeText(fd, " was being put in place (the earlier one or the new one, whole)");
  }
  writeText(fd, "; the others it would have written are as an earlier run left them\n");
}

void writeFileAtomically(const fs::path& path, std::initializer_list<std::string_view> pieces) {
  if (path.empty() || !path.has_filename())
    throw Error(fmt::format("'{}': not a file name", path.string()));
  fs::path target = path;
  struct stat st;
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw Error(path.string() + ": is a directory");
    if (!S_ISREG(st.st_mode)) {
      // A device, FIFO or terminal (/dev/stdout, /dev/full): nothing to rename, so written in
      // place, every write checked.
      writeInPlace(path, pieces);
      return;
    }
    // A symbolic link to a file keeps pointing at it: the file it names is replaced
    struct stat link;
    if (::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) {
      std::error_code ec;
      target = fs::canonical(path, ec);
      if (ec) fail(path, "cannot resolve it", ec.value());
    }
  } else if (errno != ENOENT) {
    fail(path, "cannot write", errno);  // a loop of links, a directory it may not search...
  }
  writeRegularFile(target, pieces);
}

// ---- Directories written as a whole -------------------------------------------------------------

void checkOutputDirectory(const fs::path& dir, const std::vector<std::string>& own_names) {
  if (dir.empty()) throw Error("'': not a directory name");
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw Error(fmt::format("{}: {}", dir.string(), ec.message()));
  if (!fs::exists(st)) return;
  if (!fs::is_directory(st)) throw Error(dir.string() + ": exists and is not a directory");
  if (isHsrManifest(dir / kManifest)) return;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    bool own = false;
    for (const std::string& n : own_names) own = own || n == name;
    if (!own)
      throw Error(fmt::format(
          "{}: holds files hsr did not write ('{}'); an output directory is replaced as a whole, "
          "so name a new or empty one",
          dir.string(), name));
  }
  if (ec) throw Error(fmt::format("{}: cannot list it: {}", dir.string(), ec.message()));
}

OutputDirectory::OutputDirectory(fs::path dir, std::vector<std::string> own_names)
    : dir_(std::move(dir)) {
  checkOutputDirectory(dir_, own_names);
  if (!dir_.has_filename()) dir_ = dir_.parent_path();  // "out/raw/" names out/raw
  createParent(dir_);
  for (int attempt = 0;; ++attempt) {
    temporary_ = temporaryBeside(dir_);
    if (::mkdir(temporary_.c_str(), 0777) == 0) break;
    if (errno != EEXIST || attempt > 100) fail(dir_, "cannot create it", errno);
  }
  slot_ = claimSlot(temporary_, kDirectory);
}

OutputDirectory::~OutputDirectory() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(temporary_, ec);
  }
  releaseSlot(slot_);
}

void OutputDirectory::write(std::string_view name, std::initializer_list<std::string_view> pieces) {
  if (name.empty() || name.find('/') != std::string_view::npos || name == "." || name == ".." ||
      name == kManifest)
    throw Error(fmt::format("{}: '{}' is not a file name it can hold", dir_.string(), name));
  writeNewFile(temporary_ / name, dir_ / name, pieces);
  std::size_t size = 0;
  for (std::string_view p : pieces) size += p.size();
  files_.emplace_back(std::string(name), size);
}

void OutputDirectory::commit(std::string_view about) {
  nlohmann::ordered_json m;
  m["written_by"] = "hsr";
  if (!about.empty()) {
    const nlohmann::ordered_json extra = nlohmann::ordered_json::parse(about);
    for (auto it = extra.begin(); it != extra.end(); ++it) m[it.key()] = it.value();
  }
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const auto& [name, bytes] : files_) files.push_back({{"name", name}, {"bytes", bytes}});
  m["files"] = std::move(files);
  const std::string text =
      m.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
  writeNewFile(temporary_ / kManifest, dir_ / kManifest, {text});
  // The directory's entries on the disk before it is renamed into place
  if (const int fd = ::open(temporary_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
  const int entry = noteReplacing(dir_);
  if (::rename(temporary_.c_str(), dir_.c_str()) == 0) {
    replacedDone(entry);
  } else {
    if (errno != ENOTEMPTY && errno != EEXIST) fail(dir_, "cannot put it in place", errno);
    // An earlier output is there (checked to be hsr's): exchange the two in one step, so that a
    // reader sees the old set or the new one, then remove the old one from the temporary name.
    if (::renameat2(AT_FDCWD, temporary_.c_str(), AT_FDCWD, dir_.c_str(), RENAME_EXCHANGE) != 0) {
      if (errno != EINVAL && errno != ENOSYS) fail(dir_, "cannot put it in place", errno);
      // A file system without exchange: move the old one aside first (the name is briefly
      // absent, never a mix).
      const fs::path old = temporaryBeside(dir_);
      if (::rename(dir_.c_str(), old.c_str()) != 0) fail(dir_, "cannot move it aside", errno);
      if (::rename(temporary_.c_str(), dir_.c_str()) != 0) {
        const int error = errno;
        ::rename(old.c_str(), dir_.c_str());
        fail(dir_, "cannot put it in place", error);
      }
      temporary_ = old;
    }
    replacedDone(entry);  // the new set in place; the old one's removal follows
    std::error_code ec;
    fs::remove_all(temporary_, ec);
  }
  committed_ = true;
}

}  // namespace hsr
