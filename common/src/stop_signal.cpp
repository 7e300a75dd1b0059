/// @file stop_signal.cpp
/// Implementation of stop_signal.hpp (sigaction; the handler only stores the signal number).
#include "common/stop_signal.hpp"

#include <atomic>
#include <csignal>

namespace common {
namespace {
std::atomic<int> g_signal{0};
struct sigaction g_old_term, g_old_int;
extern "C" void on_stop_signal(int sig) { g_signal.store(sig); }
}  // namespace

StopSignals::StopSignals() {
  g_signal.store(0);
  struct sigaction sa = {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;  // an interrupted write or read resumes; the loop polls afterwards
  sigaction(SIGTERM, &sa, &g_old_term);
  sigaction(SIGINT, &sa, &g_old_int);
}

StopSignals::~StopSignals() {
  sigaction(SIGTERM, &g_old_term, nullptr);
  sigaction(SIGINT, &g_old_int, nullptr);
}

int StopSignals::pending() const { return g_signal.load(); }

}  // namespace common
