// The import sandbox (io/import_sandbox.hpp): a forked child runs the import under a memory
// budget and a time limit and answers through a pipe; the parent reads the answer and the
// child's stderr, reaps the child, and turns every way the child can fail into one line.
//
// Tests: tests/fault/fault_test.cpp (crashes, hangs, runaway memory, a dying parent) and
// tests/io/io_test.cpp; fuzz/fuzz_mesh.cpp runs every import through it.

#include "io/import_sandbox.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <cstdint>
#include <initializer_list>
#include <new>
#include <string>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "core/check.hpp"
#include "hsr/error.hpp"
#include "io/import_preflight.hpp"

#include <poll.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#if defined(__SANITIZE_ADDRESS__)
#define HSR_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define HSR_ASAN 1
#endif
#endif
#ifndef HSR_ASAN
#define HSR_ASAN 0
#endif
#if HSR_ASAN
#include <sanitizer/common_interface_defs.h>
// From the sanitizer runtime's allocator interface (clang ships its header, GCC 12 does not)
extern "C" {
std::size_t __sanitizer_get_current_allocated_bytes();
int __sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void*,
                                                                  std::size_t),
                                              void (*free_hook)(const volatile void*));
}
// The runtime's own locks, which clang 14's ASan does not hold across fork() (later
// compiler-rt releases take these same ones, in this order, in a fork handler). Weak: a
// runtime linked as a shared library (GCC's libasan) does not export them, and then they
// are null and the fork goes as before.
namespace __lsan {
void LockThreadRegistry() __attribute__((weak));
void UnlockThreadRegistry() __attribute__((weak));
void LockAllocator() __attribute__((weak));
void UnlockAllocator() __attribute__((weak));
}  // namespace __lsan
namespace __sanitizer {
void StackDepotLockAll() __attribute__((weak));
void StackDepotUnlockAll() __attribute__((weak));
}  // namespace __sanitizer
#endif
#ifndef HSR_FUZZING
#define HSR_FUZZING 0
#endif

namespace hsr::detail {

std::string firstLine(std::string_view s) {
  s = s.substr(0, s.find_first_of("\r\n"));
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  return s.empty() ? std::string("unknown error") : std::string(s);
}

namespace {

// ---- The pipe protocol: the scene as bytes -------------------------------------------------

void putU32(std::string& out, std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); }
void putF32(std::string& out, float v) { out.append(reinterpret_cast<const char*>(&v), 4); }
void putStr(std::string& out, const std::string& v) {
  putU32(out, static_cast<std::uint32_t>(v.size()));
  out += v;
}

static_assert(sizeof(glm::vec3) == 12, "positions are written as they lie in memory");

std::string serializeScene(const Scene& s) {
  std::string out;
  std::size_t corners = 0;
  for (PolygonId id = 0; id < s.polygonCount(); ++id) corners += s.polygon(id).size();
  // 12 bytes a vertex, 8 a polygon and 4 a corner, and the counts first (the reader reserves)
  out.reserve(64 + 12 * s.vertexCount() + 8 * s.polygonCount() + 4 * corners);
  putU32(out, static_cast<std::uint32_t>(s.vertexCount()));
  putU32(out, static_cast<std::uint32_t>(s.polygonCount()));
  putU32(out, static_cast<std::uint32_t>(corners));
  putStr(out, s.name);
  putU32(out, static_cast<std::uint32_t>(s.materials.size()));
  for (const Material& m : s.materials) {
    putF32(out, m.color.r);
    putF32(out, m.color.g);
    putF32(out, m.color.b);
    putF32(out, m.alpha);
    putStr(out, m.name);
  }
  putU32(out, static_cast<std::uint32_t>(s.cameras.size()));
  for (const SceneCamera& c : s.cameras) {
    for (const glm::vec3& v : {c.eye, c.target, c.up})
      for (int k = 0; k < 3; ++k) putF32(out, v[k]);
    putF32(out, c.fov_deg);
    putU32(out, c.ortho ? 1u : 0u);
    putF32(out, c.ortho_half_height);
    putF32(out, c.near);
    putF32(out, c.far);
  }
  putU32(out, static_cast<std::uint32_t>(s.objects.size()));
  for (const Object& o : s.objects) {
    putStr(out, o.name);
    putU32(out, o.vertex_count);
    // The positions as they lie in memory (three floats each), then each polygon as material,
    // count and local indices gathered into one piece: a million polygons, a million appends
    if (o.vertex_count > 0)
      out.append(reinterpret_cast<const char*>(&s.position(o.first_vertex)),
                 12 * std::size_t{o.vertex_count});
    putU32(out, o.polygon_count);
    std::vector<std::uint32_t> piece;
    for (PolygonId id = o.first_polygon; id < o.first_polygon + o.polygon_count; ++id) {
      const auto poly = s.polygon(id);
      piece.assign({s.material(id), static_cast<std::uint32_t>(poly.size())});
      for (std::uint32_t v : poly) piece.push_back(v - o.first_vertex);
      out.append(reinterpret_cast<const char*>(piece.data()), 4 * piece.size());
    }
  }
  return out;
}

class Reader {
 public:
  explicit Reader(std::string_view data) : data_(data) {}
  std::uint32_t u32() {
    std::uint32_t v;
    take(&v, 4);
    return v;
  }
  float f32() {
    float v;
    take(&v, 4);
    return v;
  }
  std::string str() {
    const std::uint32_t n = u32();
    if (n > data_.size() - pos_) throw Error("corrupt scene from the importer process");
    std::string v(data_.substr(pos_, n));
    pos_ += n;
    return v;
  }

 private:
  void take(void* dst, std::size_t n) {
    if (n > data_.size() - pos_) throw Error("corrupt scene from the importer process");
    std::memcpy(dst, data_.data() + pos_, n);
    pos_ += n;
  }
  std::string_view data_;
  std::size_t pos_ = 0;
};

Scene deserializeScene(std::string_view data) {
  Reader r(data);
  Scene s;
  const std::uint32_t vertices = r.u32(), polygons = r.u32(), corners = r.u32();
  if (12ull * vertices + 8ull * polygons + 4ull * corners > data.size())
    throw Error("corrupt scene from the importer process");
  s.reserve(vertices, polygons, corners);
  s.name = r.str();
  const std::uint32_t materials = r.u32();
  for (std::uint32_t i = 0; i < materials; ++i) {
    Material m;
    m.color.r = r.f32();
    m.color.g = r.f32();
    m.color.b = r.f32();
    m.alpha = r.f32();
    m.name = r.str();
    s.materials.push_back(m);
  }
  const std::uint32_t cameras = r.u32();
  if (cameras > kMaxCameras) throw Error("corrupt scene from the importer process");
  for (std::uint32_t i = 0; i < cameras; ++i) {
    SceneCamera c;
    for (glm::vec3* v : {&c.eye, &c.target, &c.up})
      for (int k = 0; k < 3; ++k) (*v)[k] = r.f32();
    c.fov_deg = r.f32();
    c.ortho = r.u32() != 0;
    c.ortho_half_height = r.f32();
    c.near = r.f32();
    c.far = r.f32();
    s.cameras.push_back(c);
  }
  const std::uint32_t objects = r.u32();
  std::vector<std::uint32_t> local;
  for (std::uint32_t o = 0; o < objects; ++o) {
    s.beginObject(r.str());
    const std::uint32_t verts = r.u32();
    for (std::uint32_t v = 0; v < verts; ++v) {
      glm::vec3 p;
      for (int k = 0; k < 3; ++k) p[k] = r.f32();
      s.addVertex(p);
    }
    const std::uint32_t polys = r.u32();
    for (std::uint32_t i = 0; i < polys; ++i) {
      const std::uint32_t material = r.u32();
      const std::uint32_t n = r.u32();
      local.clear();
      for (std::uint32_t k = 0; k < n; ++k) local.push_back(r.u32());
      s.addPolygon(local, material);
    }
  }
  return s;
}

bool writeAll(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

#if HSR_FUZZING
// Fuzzing: libFuzzer steers by the coverage counters of the process it runs in, and the
// import layer's own code (preflight, conversion) runs in the child. The child copies its
// counters (the linker's __sancov_cntrs section) into shared memory; the parent merges them.
extern "C" {
extern std::uint8_t __start___sancov_cntrs[] __attribute__((weak));
extern std::uint8_t __stop___sancov_cntrs[] __attribute__((weak));
}

class SharedCoverage {
 public:
  SharedCoverage() {
    if (__start___sancov_cntrs && +__stop___sancov_cntrs > +__start___sancov_cntrs)
      size_ = static_cast<std::size_t>(__stop___sancov_cntrs - __start___sancov_cntrs);
    if (size_ > 0) {
      void* p = ::mmap(nullptr, size_, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
      shared_ = p == MAP_FAILED ? nullptr : static_cast<std::uint8_t*>(p);
    }
  }
  ~SharedCoverage() {
    if (shared_) ::munmap(shared_, size_);
  }
  SharedCoverage(const SharedCoverage&) = delete;
  SharedCoverage& operator=(const SharedCoverage&) = delete;
  void publishFromChild() const {
    if (shared_) std::memcpy(shared_, __start___sancov_cntrs, size_);
  }
  void mergeIntoParent() const {
    if (!shared_) return;
    for (std::size_t i = 0; i < size_; ++i)
      __start___sancov_cntrs[i] = std::max(__start___sancov_cntrs[i], shared_[i]);
  }

 private:
  std::size_t size_ = 0;
  std::uint8_t* shared_ = nullptr;
};
#endif

// ---- fork() with other threads running ---------------------------------------------------
// Only the forking thread lives on in the child; a lock another thread held at that moment
// stays held there for good. glibc's malloc takes its locks across fork() for that reason;
// the sanitizer runtime's allocator does not, so under ASan a child forked while a oneTBB
// worker of the previous render was inside malloc or free waited for ever on the allocator's
// region lock (seen in CI, an import refused at its 120 s limit; reproduced by running the
// real-model pair test in a loop twice at a time: the child's stack ended in
// SizeClassAllocator64::GetFromAllocator). The parent takes those locks, forks, and both
// sides let go.
pid_t forkWithRuntimeLocks() {
#if HSR_ASAN
  const bool lock = __lsan::LockThreadRegistry && __lsan::UnlockThreadRegistry &&
                    __lsan::LockAllocator && __lsan::UnlockAllocator &&
                    __sanitizer::StackDepotLockAll && __sanitizer::StackDepotUnlockAll;
  if (lock) {
    __lsan::LockThreadRegistry();
    __lsan::LockAllocator();
    __sanitizer::StackDepotLockAll();
  }
  const pid_t pid = ::fork();
  if (lock) {
    __sanitizer::StackDepotUnlockAll();
    __lsan::UnlockAllocator();
    __lsan::UnlockThreadRegistry();
  }
  return pid;
#else
  return ::fork();
#endif
}

// ---- Memory -------------------------------------------------------------------------------
// Some headers claim counts that assimp allocates before it reads any data (fuzzing found OFF
// and PLY files of a few hundred bytes that made it allocate 16 GB). checkHeaderAgainstSize
// refuses the ones we know; this limit bounds every other: what the import may allocate
// beyond what the process held when the child forked, sized by the file (ImportLimits).
// Measured (VmPeak growth): Debian's 579 assimp test models need at most 224 MB (a
// subdivided AC file of 2.8 KB, a Blender file of 86 KB); the densest OBJ (1M "f 1 2 3"
// lines, 8 MB) needs 140 bytes per byte, a binary STL 35, PLY and OFF 4 to 7.
constexpr std::uint64_t kBudgetPerFileByte = 256;
constexpr std::uint64_t kMinImportBudget = 1ull << 30;  // 1 GiB
constexpr std::uint64_t kMaxImportBudget = 16ull << 30;

std::uint64_t budgetFor(std::uint64_t bytes) {
  return std::clamp(
      bytes > kMaxImportBudget / kBudgetPerFileByte ? kMaxImportBudget : bytes * kBudgetPerFileByte,
      kMinImportBudget, kMaxImportBudget);
}

std::string overBudget(const std::string& file, std::uint64_t budget, std::uint64_t bytes,
                       bool with_references) {
  return fmt::format(
      "{}: importing it needs more than {} MiB, the limit for {} bytes of {}; "
      "refused (a corrupt count in the file?)",
      file, budget >> 20, bytes, with_references ? "the file and the files it references" : "file");
}

std::string overOuterLimit(const std::string& file, std::uint64_t limit, std::uint64_t budget) {
  return fmt::format(
      "{}: the import ran out of memory under this process's own address-space "
      "limit ({} MiB, set by ulimit -v or prlimit), below the {} MiB an import of "
      "this file may use; raise that limit",
      file, limit >> 20, budget >> 20);
}

// This process's address space in bytes (/proc/self/statm), 0 if unknown.
std::uint64_t addressSpaceBytes() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return 0;
  unsigned long long pages = 0;
  const bool read = std::fscanf(f, "%llu", &pages) == 1;
  std::fclose(f);
  const long page = ::sysconf(_SC_PAGESIZE);
  return read && page > 0 ? pages * static_cast<std::uint64_t>(page) : 0;
}

#if HSR_ASAN
// ASan's allocator reserves its whole heap up front, so small allocations never grow the
// address space: in the child, the live heap is watched too, after every allocation. Past the
// limit the child answers as it would on bad_alloc and leaves.
struct HeapWatch {
  std::uint64_t limit = 0;
  int fd = -1;
  const std::string* answer = nullptr;
  void (*before_exit)() = nullptr;
} g_heap_watch;

void heapWatchHook(const volatile void*, std::size_t) {
  if (__sanitizer_get_current_allocated_bytes() <= g_heap_watch.limit) return;
  if (g_heap_watch.before_exit) g_heap_watch.before_exit();
  writeAll(g_heap_watch.fd, g_heap_watch.answer->data(), g_heap_watch.answer->size());
  ::_exit(0);
}
void heapWatchFreeHook(const volatile void*) {}  // the runtime takes both hooks or neither

bool containsAny(std::string_view text, std::initializer_list<std::string_view> needles) {
  for (std::string_view s : needles)
    if (text.find(s) != std::string_view::npos) return true;
  return false;
}

// What the sanitizers print when an allocation fails (the child's address-space limit)...
bool isAllocationFailureReport(std::string_view report) {
  return containsAny(report, {"out of memory", "allocation-size-too-big",
                              "requested allocation size", "failed to allocate"});
}
// ...and when they find a bug (then the child exits, or aborts with abort_on_error=1).
bool isSanitizerReport(std::string_view report) {
  return containsAny(report,
                     {"ERROR: AddressSanitizer", "ERROR: LeakSanitizer",
                      "ERROR: UndefinedBehaviorSanitizer", "runtime error:", "ERROR: libFuzzer"});
}

// Whose bug a report is: assimp is not instrumented, but ASan's interceptors (memcpy,
// strlen...) catch some of its memory errors; the first stack frame in assimp or in our
// code (namespace hsr) decides. Those inside assimp are its bugs, contained in the child like
// its crashes (found by fuzz_gltf: a skin's inverse bind matrices copied 192 bytes past a
// 240-byte buffer). UBSan's reports (our code only) and any report without such a frame are
// ours.
bool isReportInsideAssimp(std::string_view report) {
  for (std::size_t at = report.find("\n    #"); at != std::string_view::npos;
       at = report.find("\n    #", at + 1)) {
    const std::string_view frame = report.substr(at + 1, report.find('\n', at + 1) - at - 1);
    if (frame.find("libassimp") != std::string_view::npos) return true;
    if (frame.find("hsr::") != std::string_view::npos) return false;
  }
  return false;
}

// The kind of a sanitizer report ("heap-buffer-overflow"), for the one-line refusal.
std::string reportKind(std::string_view report) {
  const std::size_t at = report.find("ERROR: AddressSanitizer: ");
  if (at == std::string_view::npos) return "a memory error";
  const std::string_view rest = report.substr(at + 25);
  return std::string(rest.substr(0, std::min(rest.find_first_of(" \n"), std::size_t{48})));
}
#endif

// The import's memory, in the child: at most `budget` more bytes of address space (and, under
// ASan, of live heap) than it held when it started. The budget starts from the model's size and
// grows with every file the model references; past it, the over-budget answer goes to the
// parent. Where this process's own hard limit (ulimit -v, prlimit) is lower, that limit binds,
// and the answer says so.
struct ChildMemory {
  std::string file;
  std::uint64_t base = 0;     // address space at the start, 0 if unknown
  std::uint64_t counted = 0;  // bytes of the model and its references
  std::uint64_t budget = 0;
  std::uint64_t model_bytes = 0;
  bool fixed = false;  // ImportLimits::memory_bytes was given
  rlim_t outer = RLIM_INFINITY;
  std::string line;    // the one line for running out...
  std::string answer;  // ...as the child's answer: 'E' + line
  void apply() {
    const bool outer_binds = base > 0 && outer != RLIM_INFINITY && base + budget > outer;
    line = outer_binds ? overOuterLimit(file, outer, budget)
                       : overBudget(file, budget, counted, counted != model_bytes);
    answer = "E" + line;
    if (base > 0) {
      const rlimit limit{outer_binds ? outer : base + budget, outer};
      ::setrlimit(RLIMIT_AS, &limit);
    }
  }
} g_child_memory;

#if HSR_ASAN
std::uint64_t g_heap_base = 0;
#endif

void limitChildMemory(const std::string& file, std::uint64_t model_bytes, std::uint64_t budget,
                      bool fixed, int answer_fd, void (*before_exit)()) {
  ChildMemory& m = g_child_memory;
  m.file = file;
  m.base = addressSpaceBytes();
  m.counted = m.model_bytes = model_bytes;
  m.budget = budget;
  m.fixed = fixed;
  rlimit outer{};
  if (::getrlimit(RLIMIT_AS, &outer) == 0) m.outer = outer.rlim_max;
  m.apply();
#if HSR_ASAN
  g_heap_base = __sanitizer_get_current_allocated_bytes();
  g_heap_watch = {g_heap_base + budget, answer_fd, &m.answer, before_exit};
  __sanitizer_install_malloc_and_free_hooks(heapWatchHook, heapWatchFreeHook);
#else
  (void)answer_fd;
  (void)before_exit;
#endif
}

// ConfinedIOSystem's report of a referenced file: the budget counts it (unless it was given).
void growChildMemory(std::uint64_t bytes) {
  ChildMemory& m = g_child_memory;
  m.counted += std::min<std::uint64_t>(bytes, kMaxFileBytes);
  if (m.fixed) return;
  m.budget = budgetFor(m.counted);
  m.apply();
#if HSR_ASAN
  g_heap_watch.limit = g_heap_base + m.budget;
#endif
}

// In the child: a crash inside assimp must end the child quietly by its signal (the parent
// reports it), not run the sanitizers' or libFuzzer's crash handlers as if the whole
// program had crashed.
void childCrashesBySignal() {
  for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(sig, SIG_DFL);
#if HSR_ASAN
  __sanitizer_set_death_callback(nullptr);
#endif
}

// What the child does before it leaves: under the fuzzer, hand its coverage to the parent.
#if HSR_FUZZING
const SharedCoverage* g_child_coverage = nullptr;
void publishChildCoverage() {
  if (g_child_coverage) g_child_coverage->publishFromChild();
}
constexpr void (*kBeforeChildExit)() = publishChildCoverage;
#else
constexpr void (*kBeforeChildExit)() = nullptr;
#endif

}  // namespace

Scene importInSandbox(const SandboxJob& job) {
  const std::string& file = job.file;
  const std::uint64_t bytes = job.bytes;
  const ImportLimits& limits = job.limits;
  const int timeout_seconds = std::max(limits.timeout_seconds, 1);
  const bool fixed = limits.memory_bytes > 0;
  const std::uint64_t budget = fixed ? limits.memory_bytes : budgetFor(bytes);
  const std::string over_budget = overBudget(file, budget, bytes, false);
#if HSR_FUZZING
  const SharedCoverage coverage;
  g_child_coverage = &coverage;
#endif
  // The answer comes through one pipe, the child's stderr through a second: what assimp or the
  // C++ runtime prints there ("terminate called after throwing...") is read, never shown raw,
  // and under the sanitizers it tells a failed allocation from a bug report.
  int fds[2], err_fds[2] = {-1, -1};
  const auto inProcess = [&] { return job.run(over_budget, nullptr, false); };
  if (::pipe(fds) != 0) return inProcess();  // no pipe: in process
  if (::pipe(err_fds) != 0) err_fds[0] = err_fds[1] = -1;
  const auto closeAll = [&] {
    for (int fd : {fds[0], fds[1], err_fds[0], err_fds[1]})
      if (fd >= 0) ::close(fd);
  };
  std::fflush(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = forkWithRuntimeLocks();
  if (pid < 0) {
    closeAll();
    return inProcess();  // no fork: in process
  }
  if (pid == 0) {
    // Child: import, answer 'S' + scene or 'E' + message, and leave without running any
    // destructor or exit handler of the parent's state. It dies with the parent (a supervisor
    // that kills hsr must not leave an import running), also if the parent died before the
    // request took effect.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(1);
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, SIG_DFL);
    ::close(fds[0]);
    if (err_fds[1] >= 0) {
      ::dup2(err_fds[1], STDERR_FILENO);
      ::close(err_fds[0]);
      ::close(err_fds[1]);
    }
    childCrashesBySignal();
    limitChildMemory(file, bytes, budget, fixed, fds[1], kBeforeChildExit);
    // The over-budget line changes as the references are counted: read where it is kept
    const std::string& over_answer = g_child_memory.answer;
    std::string answer;
    try {
      const Scene scene = job.run(g_child_memory.line, growChildMemory, true);
      answer.assign(1, 'S');
      answer += serializeScene(scene);
    } catch (const Error& e) {
      answer = std::string("E") + e.what();
    } catch (const std::bad_alloc&) {
      answer = over_answer;
    } catch (...) {
      answer = "E" + file + ": assimp could not read it: unknown error";
    }
    if (kBeforeChildExit) kBeforeChildExit();
    writeAll(fds[1], answer.data(), answer.size());
    ::_exit(0);
  }
  // Parent: read the whole answer (and the child's stderr) with a deadline, then reap the
  // child.
  ::close(fds[1]);
  if (err_fds[1] >= 0) ::close(err_fds[1]);
  std::string answer, child_stderr;
  char buf[1 << 16];
  // Reads what is waiting on fd into `to`; false at EOF. A runaway stream of diagnostics is
  // cut, not stored.
  const auto drain = [&](int fd, std::string& to) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0) return errno == EINTR;
    if (n > 0 && (&to == &answer || to.size() < (1u << 20)))
      to.append(buf, static_cast<std::size_t>(n));
    return n > 0;
  };
  bool timed_out = false;
  const auto started = std::chrono::steady_clock::now();
  auto next_progress = started + std::chrono::milliseconds(250);
  const auto deadline = started + std::chrono::seconds(timeout_seconds);
  pollfd p[2] = {{fds[0], POLLIN, 0}, {err_fds[0], POLLIN, 0}};
  const nfds_t watched = err_fds[0] >= 0 ? 2 : 1;
  // Until the answer's EOF: the child closed its end (answered, or died)
  while (p[0].fd >= 0) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          deadline - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0) {
      timed_out = true;
      break;
    }
    if (limits.progress) {
      const auto now = std::chrono::steady_clock::now();
      if (now >= next_progress) {
        limits.progress(std::chrono::duration<double>(now - started).count(), answer.size(), false);
        next_progress = now + std::chrono::milliseconds(250);
      }
    }
    if (::poll(p, watched,
               static_cast<int>(std::min<long long>(left, limits.progress ? 250 : 1000))) <= 0)
      continue;
    for (nfds_t k = 0; k < watched; ++k)
      if (p[k].fd >= 0 && (p[k].revents & (POLLIN | POLLHUP | POLLERR)) &&
          !drain(p[k].fd, k == 0 ? answer : child_stderr))
        p[k].fd = -1;
  }
  if (limits.progress)
    limits.progress(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
        answer.size(), true);
  if (timed_out) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  // The child has ended: what it still wrote to stderr is waiting in the pipe
  if (p[1].fd >= 0)
    while (drain(p[1].fd, child_stderr)) {
    }
  ::close(fds[0]);
  if (err_fds[0] >= 0) ::close(err_fds[0]);
#if HSR_FUZZING
  g_child_coverage = nullptr;
  if (WIFEXITED(status)) coverage.mergeIntoParent();
#endif
  if (timed_out)
    throw Error(file + ": the importer did not finish within " + std::to_string(timeout_seconds) +
                " s; refused");
#if HSR_ASAN
  if (answer.empty() && (WIFSIGNALED(status) || WEXITSTATUS(status) != 0)) {
    if (isAllocationFailureReport(child_stderr)) throw Error(over_budget);
    if (isSanitizerReport(child_stderr) && isReportInsideAssimp(child_stderr))
      throw Error(file + ": the importer (assimp) failed on this file (" +
                  reportKind(child_stderr) + " inside assimp); refused as malformed");
    // A sanitizer's report from the import child: a bug, never a refusal. It stops the
    // program as a failed check does, as the sanitizer would have had the import run in
    // process, with the report
    if (isSanitizerReport(child_stderr))
      checkFailed(__FILE__, __LINE__,
                  "the import child for " + file + " met a bug; its report:\n" + child_stderr);
  }
#endif
  if (WIFSIGNALED(status)) {
    if (const std::string what = uncaughtException(child_stderr); !what.empty())
      throw Error(file + ": the importer (assimp) failed on this file (" + what +
                  "); refused as malformed");
    throw Error(file + ": the importer (assimp) crashed on this file (signal " +
                std::to_string(WTERMSIG(status)) + "); refused as malformed");
  }
  // Whatever else the child printed is not shown: the answer is the one line
  if (answer.empty()) throw Error(file + ": the importer (assimp) ended without an answer");
  if (answer[0] == 'E') throw Error(answer.substr(1));
  return deserializeScene(std::string_view(answer).substr(1));
}

// What the C++ runtime printed when an exception escaped inside the importer ("terminate
// called after throwing an instance of 'T'\n  what():  message"), as "an exception it did not
// catch: T: message"; empty if it printed nothing of the kind.
std::string uncaughtException(std::string_view text) {
  constexpr std::string_view kThrown = "terminate called after throwing an instance of '";
  const std::size_t at = text.find(kThrown);
  if (at == std::string_view::npos)
    return text.find("terminate called") != std::string_view::npos ? "the C++ runtime terminated it"
                                                                   : "";
  std::string_view rest = text.substr(at + kThrown.size());
  std::string what(rest.substr(0, std::min<std::size_t>(rest.find('\''), 120)));
  if (const std::size_t w = rest.find("what():"); w != std::string_view::npos) {
    std::string_view message = rest.substr(w + 7);
    message.remove_prefix(std::min(message.find_first_not_of(' '), message.size()));
    what += ": " + firstLine(message.substr(0, std::min<std::size_t>(message.size(), 200)));
  }
  return "an exception it did not catch: " + what;
}

}  // namespace hsr::detail
