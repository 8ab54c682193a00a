// Running the `hsr` binary the build made (HSR_CLI_PATH) from a test: its exit code, stderr and
// stdout, and the check that a refusal is one line "hsr: ..." with exit code 2.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <sys/wait.h>

#include "test_util.hpp"

namespace hsr::testing {

struct CliRun {
  int code;
  std::string err;
  std::string out;
};

// `args` as a shell would split them; `cwd`, when given, the directory it runs in. At most 60 s.
inline CliRun runCli(const std::string& args, const std::filesystem::path& cwd = {}) {
  const ScratchDir scratch("hsr_cli_stderr");
  const std::filesystem::path err = scratch / "stderr.txt";
  const std::string cmd = (cwd.empty() ? "" : "cd '" + cwd.string() + "' && ") + "timeout 60 " +
                          std::string(HSR_CLI_PATH) + " " + args + " 2>" + err.string();
  CliRun r;
  FILE* p = popen(cmd.c_str(), "r");
  std::array<char, 4096> buf;
  while (p && fgets(buf.data(), buf.size(), p)) r.out += buf.data();
  const int status = p ? pclose(p) : -1;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  std::ifstream in(err);
  r.err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return r;
}

inline int lineCount(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

// The run is refused the way every bad input is: exit 2, one line on stderr starting "hsr: ",
// naming `must_mention` when given.
inline void expectCleanError(const std::string& args, const std::string& must_mention = "",
                             const std::filesystem::path& cwd = {}) {
  const CliRun r = runCli(args, cwd);
  EXPECT_EQ(r.code, 2) << args << "\nstderr: " << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << args << "\nstderr: " << r.err;
  EXPECT_EQ(r.err.rfind("hsr: ", 0), 0u) << r.err;
  if (!must_mention.empty()) {
    EXPECT_NE(r.err.find(must_mention), std::string::npos) << args << "\nstderr: " << r.err;
  }
}

}  // namespace hsr::testing
