// Wall-clock milliseconds on the steady clock: the one helper every module's timings use.
#pragma once

#include <chrono>
#include <utility>

namespace rayscout {

using SteadyClock = std::chrono::steady_clock;

/// Milliseconds from start until now.
inline double ms_since(SteadyClock::time_point start) {
  return std::chrono::duration<double, std::milli>(SteadyClock::now() - start).count();
}

/// Runs fn() and returns how long it took, in milliseconds.
template <class Fn>
double time_ms(Fn&& fn) {
  const auto start = SteadyClock::now();
  std::forward<Fn>(fn)();
  return ms_since(start);
}

}  // namespace rayscout
