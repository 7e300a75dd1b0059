/// @file fuzz_harness.hpp
/// Runs fuzz cases in child processes: a crash or a hang is reported as the failing case (with its
/// index, from which the case is regenerated) instead of killing or stalling the test.
#pragma once
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "common/status.hpp"

namespace fuzz {

struct Failure {
  std::size_t index;
  std::string what;  // "crash: signal 11", "hang", "std::length_error: ..."
};

inline double env_double(const char* name, double fallback) {
  const char* e = std::getenv(name);
  return e && *e ? std::atof(e) : fallback;
}

/// Run `one(i)` for i in [0, n). Each case may end normally or with InputError/IoError; any other
/// exception, a crash or a case that takes more than `per_case_s` is a Failure. Cases run in
/// batches in a forked child (a fresh one after each crash or hang).
inline std::vector<Failure> run_cases(std::size_t n, double per_case_s, const std::function<void(std::size_t)>& one) {
  std::vector<Failure> failures;
  std::size_t next = 0;
  while (next < n) {
    int fds[2];
    if (::pipe(fds) != 0) return {{next, "pipe failed"}};
    const pid_t pid = ::fork();
    if (pid == 0) {
      ::close(fds[0]);
      auto say = [&](const std::string& s) {
        std::size_t done = 0;
        while (done < s.size()) {
          const ssize_t w = ::write(fds[1], s.data() + done, s.size() - done);
          if (w <= 0) ::_exit(9);
          done += static_cast<std::size_t>(w);
        }
      };
      for (std::size_t i = next; i < n; ++i) {
        say("S " + std::to_string(i) + "\n");
        std::string bad;
        try {
          one(i);
        } catch (const common::InputError&) {
        } catch (const common::IoError&) {
        } catch (const std::exception& e) {
          bad = std::string("untyped exception: ") + e.what();
        } catch (...) {
          bad = "untyped exception (not std::exception)";
        }
        if (!bad.empty()) {
          for (char& c : bad)
            if (c == '\n') c = ' ';
          say("F " + std::to_string(i) + " " + bad + "\n");
        }
      }
      say("D\n");
      ::_exit(0);
    }
    ::close(fds[1]);
    std::string buf;
    std::size_t current = next;
    bool done = false, hung = false;
    auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(per_case_s);
    for (;;) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
      if (left <= 0) {
        hung = true;
        break;
      }
      pollfd p{fds[0], POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(left)) <= 0) continue;
      char tmp[4096];
      const ssize_t got = ::read(fds[0], tmp, sizeof tmp);
      if (got <= 0) break;
      buf.append(tmp, static_cast<std::size_t>(got));
      std::size_t nl;
      while ((nl = buf.find('\n')) != std::string::npos) {
        const std::string line = buf.substr(0, nl);
        buf.erase(0, nl + 1);
        if (line[0] == 'S') {
          current = std::stoul(line.substr(2));
          deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(per_case_s);
        } else if (line[0] == 'F') {
          const std::size_t sp = line.find(' ', 2);
          failures.push_back({std::stoul(line.substr(2, sp - 2)), line.substr(sp + 1)});
        } else if (line[0] == 'D') {
          done = true;
        }
      }
    }
    ::close(fds[0]);
    if (hung) ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (done) break;
    if (hung)
      failures.push_back({current, "hang (over " + std::to_string(per_case_s) + " s)"});
    else if (WIFSIGNALED(status))
      failures.push_back({current, "crash: signal " + std::to_string(WTERMSIG(status))});
    else
      failures.push_back({current, "child exited with " + std::to_string(WEXITSTATUS(status))});
    next = current + 1;
  }
  return failures;
}

}  // namespace fuzz
