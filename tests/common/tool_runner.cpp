/// @file tool_runner.cpp
/// Implementation of tool_runner.hpp.
#include "tool_runner.hpp"

#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

namespace testutil {

ToolResult run_tool(const std::string& exe, const std::string& args, int timeout_s) {
  static int counter = 0;  // ctest runs tests in parallel processes: the pid keeps logs apart
  const auto log = std::filesystem::temp_directory_path() /
                   ("tool_run_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + ".log");
  const std::string limit = timeout_s > 0 ? "timeout -s KILL " + std::to_string(timeout_s) + " " : "";
  const std::string cmd = "OMP_NUM_THREADS=1 " + limit + exe + " " + args + " > " + log.string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  ToolResult r;
  r.rc = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  std::ifstream f(log);
  r.out.assign(std::istreambuf_iterator<char>(f), {});
  std::filesystem::remove(log);
  return r;
}

pid_t spawn_tool(const std::string& exe, const std::string& scene, const std::vector<std::string>& sets,
                 const std::vector<std::string>& extra) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    ::setenv("OMP_NUM_THREADS", "1", 1);
    if (!std::freopen("/dev/null", "w", stdout) || !std::freopen("/dev/null", "w", stderr)) ::_exit(98);
    std::vector<std::string> args = {exe, "--quiet", "--scene", scene};
    for (const auto& s : sets) {
      args.push_back("--set");
      args.push_back(s);
    }
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(99);
  }
  return pid;
}

bool wait_for(const std::function<bool()>& ready) {
  for (int i = 0; i < 12000; ++i) {
    if (ready()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

}  // namespace testutil
