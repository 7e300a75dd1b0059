/// @file stop_signal.hpp
/// SIGTERM and SIGINT as a request to stop at the next safe point, for the long-running tools
/// (mpm-frag, ssdem-grav): while a StopSignals object lives, either signal only records its
/// number; the run loop polls pending() after each completed step, writes a checkpoint and returns
/// 128 + signal (the shell's convention for a process ended by that signal). A second signal
/// before the loop polls changes nothing (the step in progress still finishes). The previous
/// handlers come back when the object is destroyed.
#pragma once

namespace common {

class StopSignals {
 public:
  /// Install the handlers and clear any earlier request.
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  /// 0, or the number of the last signal received.
  int pending() const;
};

}  // namespace common
