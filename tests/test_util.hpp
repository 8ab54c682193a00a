#pragma once
// Small helpers shared by the tests: deterministic random numbers, scene builders and scratch
// directories.

#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "hsr/camera.hpp"
#include "hsr/render.hpp"
#include "core/random.hpp"
#include "hsr/scene.hpp"

namespace hsr::testing {

using Rng = hsr::detail::SplitMix64;

// Channel c (0 = R, 1 = G, 2 = B) of pixel k of a frame's packed RGBA colour.
inline int channel(const Frame& f, std::size_t k, int c) { return (f.color[k] >> (8 * c)) & 0xFF; }

// A fresh, empty directory of its own under the system's temporary directory (TAG_XXXXXX,
// made unique by mkdtemp, so tests running in parallel never share one), removed with all it
// holds when the object goes out of scope: a test run leaves nothing behind in /tmp.
class ScratchDir {
 public:
  explicit ScratchDir(std::string_view tag = "hsr_test") {
    std::string name = (std::filesystem::temp_directory_path() / tag).string() + "_XXXXXX";
    if (::mkdtemp(name.data()) == nullptr)
      throw std::system_error(errno, std::generic_category(), "mkdtemp " + name);
    path_ = name;
  }
  ~ScratchDir() {
    namespace fs = std::filesystem;
    // A test may have taken away its own permissions on a folder inside: give them back
    // (to folders only, never through a link) so that everything can be removed. A destructor
    // must not throw: what cannot go stays.
    std::error_code ec;
    fs::permissions(path_, fs::perms::owner_all, fs::perm_options::add, ec);
    for (fs::recursive_directory_iterator it(path_, ec), end; !ec && it != end; it.increment(ec)) {
      std::error_code ignored;
      if (it->symlink_status(ignored).type() == fs::file_type::directory)
        fs::permissions(it->path(), fs::perms::owner_all, fs::perm_options::add, ignored);
    }
    fs::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::filesystem::path& p) const { return path_ / p; }

 private:
  std::filesystem::path path_;
};

// HSR_TEST_INTENSITY: 1 in CI (default), 3 for long local runs (10x the cases), 5 for 100x.
inline int testIntensity() {
  const char* v = std::getenv("HSR_TEST_INTENSITY");
  const int i = v ? std::atoi(v) : 1;
  return i < 1 ? 1 : (i > 9 ? 9 : i);
}

// Multiplier for a test's case counts: 1 at intensity 1 (CI), about 3 at 2, 10 at 3, 100 at 5.
inline int countScale() {
  return static_cast<int>(std::lround(std::pow(10.0, (testIntensity() - 1) / 2.0)));
}

// The sanitizer leg's size tier (docs/testing.md, "Running the tests"). The sanitizers look for
// memory errors and undefined behaviour on every path a property takes, not for more cases, and
// run hsr's code 4 to 20 times slower: there a property of many alike cases runs 1/`share` of
// them (at least one); Release runs them all. Every property still runs in both legs.
inline int legCases(int cases, int share) {
#ifdef HSR_SANITIZER_BUILD
  return cases / share > 1 ? cases / share : 1;
#else
  (void)share;
  return cases;
#endif
}

// Tests of one suite that ran so far, and how many of them passed: for the "[ figures ]"
// lines that the README's Reliability table quotes.
struct SuiteTally {
  int run = 0;
  int passed = 0;
};
inline SuiteTally tallySuite(std::string_view suite_name) {
  const ::testing::UnitTest& u = *::testing::UnitTest::GetInstance();
  SuiteTally tally;
  for (int i = 0; i < u.total_test_suite_count(); ++i) {
    const ::testing::TestSuite& suite = *u.GetTestSuite(i);
    if (std::string_view(suite.name()) != suite_name) continue;
    for (int j = 0; j < suite.total_test_count(); ++j) {
      const ::testing::TestInfo& t = *suite.GetTestInfo(j);
      if (!t.should_run()) continue;
      ++tally.run;
      tally.passed += t.result()->Passed() ? 1 : 0;
    }
  }
  return tally;
}

// Runs `print` once, after every test of the program has run (a gtest environment's
// teardown): where a file prints the figures of its whole suite.
template <class Print>
::testing::Environment* printFiguresAtEnd(Print print) {
  struct AtEnd : ::testing::Environment {
    explicit AtEnd(Print p) : print(std::move(p)) {}
    void TearDown() override {
      print();
      std::fflush(stdout);
    }
    Print print;
  };
  return ::testing::AddGlobalTestEnvironment(new AtEnd(std::move(print)));
}

// A w x h perspective camera at the origin looking down -z (near 0.5, far 20): a scene around
// it is clipped at the near plane.
inline Camera cameraAtOrigin(int w, int h) {
  Camera c;
  c.eye = {0, 0, 0};
  c.target = {0, 0, -1};
  c.near = 0.5f;
  c.far = 20.0f;
  c.width = w;
  c.height = h;
  return c;
}

// An orthographic camera on which world x,y in [0,w]x[0,h] map to window pixels (y up),
// looking down -z from z = 10 with near 1 and far 20 (window depth = (10 - z - 1) / 19 ... ).
inline Camera pixelCamera(int w, int h) {
  Camera c;
  c.width = w;
  c.height = h;
  c.ortho = true;
  c.ortho_half_height = h * 0.5f;
  c.eye = {w * 0.5f, h * 0.5f, 10.0f};
  c.target = {w * 0.5f, h * 0.5f, 0.0f};
  c.up = {0.0f, 1.0f, 0.0f};
  c.near = 1.0f;
  c.far = 20.0f;
  return c;
}

// The registry's algorithm names. Tests of properties every algorithm must keep are
// value-parameterised over it (class Suite : public EveryAlgorithm, TEST_P, and
// HSR_INSTANTIATE_FOR_EVERY_ALGORITHM(Suite)): adding a line to the registry table adds the
// new algorithm to every such test, named Suite.Test/ALGORITHM.

// The algorithms a property applies to: those with every capability in `caps` (all of them
// when caps is 0). The others are listed once at the end of the run, with what they lack
// ("[ not applicable ] Suite: painter lacks exact-coverage"), so that a property never
// silently skips an algorithm.
struct NotApplicable {
  std::string suite, algorithm, lacks;
};
inline std::vector<NotApplicable>& notApplicable() {
  static std::vector<NotApplicable> list;
  return list;
}
// A demonstration row (painter-naive: wrong on purpose) is held to none of these properties;
// its own tests measure its failure.
//
// The sanitizer leg's tier for the textbook pairs (hsr/algorithms.hpp): a textbook entry draws
// its fast sibling's frame bit for bit, which tests/cross/textbook_test.cpp checks in every leg,
// the sanitizers' included, on every kind of scene the suites use. So under the sanitizers
// (which look for memory errors and undefined behaviour, not for more cases) the property
// suites run the fast sibling, whose tiles, bands and threads are where such errors hide, and
// the textbook entry joins only the random-bit-pattern suite (Garbage); Release runs every
// suite on both.
inline const char* sanitizerLegLeavesOut([[maybe_unused]] const AlgorithmInfo& a,
                                         [[maybe_unused]] std::string_view suite) {
#ifdef HSR_SANITIZER_BUILD
  if (a.textbook && suite != "Garbage")
    return "(the sanitizer leg: pinned to its fast sibling by TextbookPair, which runs here; "
           "Release runs this suite on it)";
#endif
  return nullptr;
}

inline std::vector<const AlgorithmInfo*> algorithmsWith(std::string_view suite,
                                                        std::uint32_t caps) {
  std::vector<const AlgorithmInfo*> out;
  for (const AlgorithmInfo& a : algorithms()) {
    const char* left_out = sanitizerLegLeavesOut(a, suite);
    if ((a.capabilities & caps) == caps && !a.demonstration && !left_out) {
      out.push_back(&a);
      continue;
    }
    bool known = false;
    for (const NotApplicable& n : notApplicable())
      known = known || (n.suite == suite && n.algorithm == a.name);
    if (!known)
      notApplicable().push_back({std::string(suite), std::string(a.name),
                                 a.demonstration ? std::string("(a demonstration)")
                                 : left_out      ? std::string(left_out)
                                                 : capabilityList(caps & ~a.capabilities)});
  }
  return out;
}
inline std::vector<std::string> algorithmNamesWith(std::string_view suite, std::uint32_t caps) {
  std::vector<std::string> names;
  for (const AlgorithmInfo* a : algorithmsWith(suite, caps)) names.emplace_back(a->name);
  return names;
}
// Every algorithm a property of all of them applies to (the demonstrations left out).
inline std::vector<std::string> algorithmNames() {
  return algorithmNamesWith("every algorithm", 0);
}

// The property suites judge what is drawn at pixel centres (coverage by colour and overdraw,
// ids, depth). An antialiasing algorithm is judged there with its one sample at the centre;
// its ids and depth, which hold at any sample count, and its sub-pixel coverage have suites of
// their own (tests/visibility/abuffer_test.cpp).
inline void sampleAtCentres(RenderOptions& o) {
  o.samples = findAlgorithm(o.algorithm).has(kAntialiasing) ? 1 : 0;
}

// Default render state with the algorithm under test.
inline RenderOptions optionsFor(const std::string& algorithm) {
  RenderOptions o;
  o.algorithm = algorithm;
  sampleAtCentres(o);
  return o;
}

class EveryAlgorithm : public ::testing::TestWithParam<std::string> {
 protected:
  RenderOptions options() const { return optionsFor(GetParam()); }
};

// A test name for an algorithm name: gtest allows only letters, digits and '_'.
inline std::string testNameOf(const ::testing::TestParamInfo<std::string>& info) {
  std::string s = info.param;
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

}  // namespace hsr::testing

#define HSR_INSTANTIATE_FOR_EVERY_ALGORITHM(Suite)                                             \
  INSTANTIATE_TEST_SUITE_P(, Suite,                                                            \
                           ::testing::ValuesIn(::hsr::testing::algorithmNamesWith(#Suite, 0)), \
                           ::hsr::testing::testNameOf)

// Suite instantiated for the algorithms with every capability in `caps` (hsr/algorithms.hpp).
#define HSR_INSTANTIATE_FOR_ALGORITHMS_WITH(Suite, caps)                                \
  INSTANTIATE_TEST_SUITE_P(                                                             \
      , Suite, ::testing::ValuesIn(::hsr::testing::algorithmNamesWith(#Suite, (caps))), \
      ::hsr::testing::testNameOf);                                                      \
  GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(Suite)
