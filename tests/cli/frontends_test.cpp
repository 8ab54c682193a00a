// The three front-ends accept and refuse the same values: the command line's half. Every case of
// tests/frontend/cases.json is typed as flags (--cull back, --size 40x30, --no-depth-test) and
// run through the `hsr` binary; a case accepted renders, a refused one is one line naming what
// the case says, with each {name} spelled as the command line spells it. The Python module
// (tests/python/test_frontends.py) and the web page's module (web/test/node_test.mjs) run the
// same cases.

#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/cli_run.hpp"
#include "hsr/frontend.hpp"
#include "test_util.hpp"

namespace {

using nlohmann::json;

json cases() {
  std::ifstream in(std::string(HSR_SOURCE_DIR) + "/tests/frontend/cases.json");
  return json::parse(in)["cases"];
}

// "{clear_depth} must be" -> "--clear-depth must be"
std::string spelledFor(std::string says, hsr::FrontEnd fe) {
  static const std::regex name(R"(\{([a-z_]+)\})");
  std::string out;
  std::sregex_iterator it(says.begin(), says.end(), name), end;
  std::size_t at = 0;
  for (; it != end; ++it) {
    out += says.substr(at, it->position() - at) + hsr::spelled((*it)[1].str(), fe);
    at = it->position() + it->length();
  }
  return out + says.substr(at);
}

// The case's options as flags; empty when a value has no command-line form (a flag with a value
// other than the one its flag sets).
std::string flagsOf(const json& options, bool* expressible) {
  std::string flags;
  *expressible = true;
  for (const auto& [name, value] : options.items()) {
    const std::string flag = hsr::spelled(name, hsr::FrontEnd::kCli);
    const hsr::OptionSpec* spec = hsr::findOptionSpec(name);
    if (spec && spec->kind == hsr::OptionKind::kFlag) {
      if (!value.is_boolean() || value.get<bool>() == (spec->default_text == "true"))
        *expressible = false;
      flags += " " + flag;
      continue;
    }
    std::string text;
    if (value.is_array()) {
      for (std::size_t i = 0; i < value.size(); ++i)
        text += (i ? (name == "size" ? "x" : ",") : "") + value[i].dump();
    } else {
      text = value.is_string() ? value.get<std::string>() : value.dump();
    }
    flags += " " + flag + " '" + text + "'";
  }
  return flags;
}

TEST(FrontEnds, TheCommandLineAcceptsAndRefusesAsTheCasesSay) {
  const hsr::testing::ScratchDir scratch("hsr_frontends_cli");
  const std::string png = (scratch.path() / "x.png").string();
  int ran = 0;
  for (const json& c : cases()) {
    if (c.contains("only")) {
      bool here = false;
      for (const json& f : c["only"]) here = here || f == "cli";
      if (!here) continue;
    }
    bool expressible = true;
    const std::string flags = flagsOf(c["options"], &expressible);
    ASSERT_TRUE(expressible) << "a case the command line cannot type needs \"only\": " << c.dump();
    const std::string size = c["options"].contains("size") ? "" : " --size 64x48";
    const std::string args = "render demo" + size + flags + " -q -o " + png;
    ++ran;
    if (!c.contains("says")) {
      const hsr::testing::CliRun r = hsr::testing::runCli(args);
      EXPECT_EQ(r.code, 0) << args << "\nstderr: " << r.err;
    } else {
      hsr::testing::expectCleanError(args,
                                     spelledFor(c["says"].get<std::string>(), hsr::FrontEnd::kCli));
    }
  }
  EXPECT_GT(ran, 50);
}

}  // namespace
