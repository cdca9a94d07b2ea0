#pragma once
// Runs the real hapticbox binary (HB_CLI_PATH) with no display, capturing exit code, stdout
// and stderr: the CLI suites test the command line end to end.
#include <array>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/wait.h>

namespace hb::test {

struct CommandResult {
  int code = -1;
  std::string out, err;
};

/// `args` is appended to the binary's path as is (quote paths with spaces); stderr goes
/// through a file in `scratch_dir`. `env`: "NAME=value ..." set for this run (e.g. HB_MEASURE).
inline CommandResult run_cli(const std::string& args, const std::string& scratch_dir, const std::string& env = "") {
  const std::string err_path = scratch_dir + "/stderr.txt";
  // No display: the command line must never need one.
  // A box cache of its own per call (bake, sweep and report cache by default): no test reads
  // the user's cache or another call's entry unless it names one with --cache DIR.
  static int call = 0;
  const std::string cache = scratch_dir + "/xdg-cache-" + std::to_string(++call);
  const std::string cmd =
      "env -u DISPLAY XDG_CACHE_HOME=" + cache + " " + env + " " + std::string(HB_CLI_PATH) + " " + args + " 2>" + err_path;
  CommandResult r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream e(err_path);
  r.err.assign(std::istreambuf_iterator<char>(e), {});
  return r;
}

} // namespace hb::test
