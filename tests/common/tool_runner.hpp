/// @file tool_runner.hpp
/// Running the suite's executables from tests as a user would: capture exit code and output, or
/// start one in the background (to kill it mid-run) and wait for a condition.
#pragma once
#include <sys/types.h>

#include <functional>
#include <string>
#include <vector>

namespace testutil {

struct ToolResult {
  int rc = -1;      ///< exit status (-1: killed by a signal; 137 when the time limit killed it)
  std::string out;  ///< stdout and stderr together
};

/// Run `exe args` through the shell with one OpenMP thread; `timeout_s` > 0 kills it (SIGKILL)
/// after that many seconds (a FIFO input must not block a test).
ToolResult run_tool(const std::string& exe, const std::string& args, int timeout_s = 0);

/// Start `exe --quiet --scene scene --set s... extra...` in the background (one OpenMP thread,
/// output discarded); it is killed if the test process dies.
pid_t spawn_tool(const std::string& exe, const std::string& scene, const std::vector<std::string>& sets,
                 const std::vector<std::string>& extra = {});

/// Poll `ready()` every 5 ms for up to 60 s; whether it became true.
bool wait_for(const std::function<bool()>& ready);

}  // namespace testutil
