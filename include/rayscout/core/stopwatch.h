// Milliseconds on the steady clock and on the CPU-time clocks: the helpers every module's
// and benchmark's timings use.
#pragma once

#include <chrono>
#include <ctime>
#include <utility>

namespace rayscout {

using SteadyClock = std::chrono::steady_clock;

/// Milliseconds from start until now.
inline double ms_since(SteadyClock::time_point start) {
  return std::chrono::duration<double, std::milli>(SteadyClock::now() - start).count();
}

/// Steady-clock milliseconds since an arbitrary epoch (only differences mean anything).
inline double wall_ms() {
  return std::chrono::duration<double, std::milli>(SteadyClock::now().time_since_epoch()).count();
}

/// CPU time of the whole process in ms (all threads): on a shared machine it measures the
/// work without the waits for a core.
inline double process_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

/// CPU time of the calling thread in ms.
inline double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

/// Runs fn() and returns how long it took, in milliseconds.
template <class Fn>
double time_ms(Fn&& fn) {
  const auto start = SteadyClock::now();
  std::forward<Fn>(fn)();
  return ms_since(start);
}

}  // namespace rayscout
