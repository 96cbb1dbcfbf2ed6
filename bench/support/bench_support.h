// What the benchmark drivers share: clocks, ray sets and their tracing, interleaved medians of
// repetitions, labelled accelerator columns, checks of name lists, the machine line, skipping
// scenes that are missing, error exits.
#pragma once

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <fmt/core.h>

#include "rayscout/core/accelerator.h"
#include "rayscout/core/input_error.h"
#include "rayscout/core/median.h"
#include "rayscout/core/scenes_dir.h"
#include "rayscout/core/stopwatch.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout::bench {

// Median of the repetitions' times; never empty: every driver's repetition options are
// checked to be at least 1.
using rayscout::median;

/// The clock a driver times with. On a shared machine the CPU time of a one-thread run
/// measures the work without the waits for a core; with more threads only wall time means
/// anything (TBB's workers are other threads, and CPU time sums them).
enum class Clock { Wall, ProcessCpu, ThreadCpu };

inline double now_ms(Clock clock) {
  switch (clock) {
    case Clock::ProcessCpu: return process_cpu_ms();
    case Clock::ThreadCpu: return thread_cpu_ms();
    case Clock::Wall: break;
  }
  return wall_ms();
}

inline const char* clock_name(Clock clock) {
  switch (clock) {
    case Clock::ProcessCpu: return "process CPU time";
    case Clock::ThreadCpu: return "thread CPU time";
    case Clock::Wall: break;
  }
  return "wall clock";
}

/// How interleaved_medians runs its rounds.
struct Rounds {
  int count = 1;           ///< timed rounds (every driver checks its repetition option is >= 1)
  bool warm_up = true;     ///< one untimed call of each column before the rounds
  bool alternate = false;  ///< odd rounds call the columns in reverse order, so none always follows the same one
};

/// Median over rounds.count rounds of measure(k), for each column k < n. A round calls every
/// column once (interleaved), so that a change of load on a shared machine moves every column
/// alike instead of the ratio between them. measure returns a time or anything else to take
/// the median of (core_bench's builds return their own build_ms).
template <class Measure>
std::vector<double> interleaved_medians(size_t n, const Rounds& rounds, Measure&& measure) {
  if (rounds.warm_up)
    for (size_t k = 0; k < n; ++k) (void)measure(k);
  std::vector<std::vector<double>> values(n);
  for (int r = 0; r < rounds.count; ++r)
    for (size_t i = 0; i < n; ++i) {
      const size_t k = rounds.alternate && r % 2 ? n - 1 - i : i;
      values[k].push_back(measure(k));
    }
  std::vector<double> medians;
  for (const auto& v : values) medians.push_back(median(v));
  return medians;
}

/// One traced batch of a workload and the query it is traced with.
struct RaySet {
  std::string kind;        ///< "primary", "shadow", "ao", "diffuse", "mirror", "path", ...
  int bounce = 0;          ///< 0 = from the camera or the primary hits; k = after k bounces
  bool occlusion = false;  ///< any-hit batch (shadow, ao)
  RayBatch rays;

  /// "shadow", or "shadow@1" for a later bounce's batch.
  std::string label() const { return kind + (bounce ? "@" + std::to_string(bounce) : ""); }
};

/// Traces rays once with `a`: occluded() for an any-hit batch, else intersect(); the results
/// are dropped, the work is counted into stats if given.
inline void trace(const Accelerator& a, const RayBatch& rays, bool occlusion, TraceStats* stats = nullptr) {
  if (occlusion) {
    std::vector<uint8_t> occluded;
    a.occluded(rays, occluded, stats);
  } else {
    HitBatch hits;
    a.intersect(rays, hits, stats);
  }
}

inline void trace(const Accelerator& a, const RaySet& set, TraceStats* stats = nullptr) {
  trace(a, set.rays, set.occlusion, stats);
}

/// Milliseconds one trace of set takes on clock. The output buffers live on between calls and
/// are sized before the clock starts, as a renderer keeps its own: a fresh HitBatch of 1M rays
/// is 16 MB of page faults, which would be charged to whichever accelerator is being timed.
inline double trace_ms(Clock clock, const Accelerator& a, const RaySet& set) {
  thread_local HitBatch hits;
  thread_local std::vector<uint8_t> occluded;
  const size_t n = set.rays.size();
  if (set.occlusion) occluded.assign(n, 0);
  else hits.reset(n);
  const double t0 = now_ms(clock);
  if (set.occlusion) a.occluded(set.rays, occluded);
  else a.intersect(set.rays, hits);
  return now_ms(clock) - t0;
}

/// Throws InputError naming `option` and the first of `given` that is not in `known`, so a
/// misspelt workload or view is an error instead of an empty table.
inline void check_names(const std::string& option, const std::vector<std::string>& given,
                        const std::vector<std::string>& known) {
  for (const std::string& g : given)
    if (std::find(known.begin(), known.end(), g) == known.end()) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      throw InputError(option + ": unknown '" + g + "' (known: " + list + ")");
    }
}

/// A labelled accelerator and its options: a column of core_bench (--column) or dacrt_bench
/// (--variants).
struct ColumnSpec {
  std::string label, accel;
  std::vector<std::string> options;  ///< "key=value", as rayscout's --accel-opt takes them
};

/// Parses "label:accel[:key=value,key=value,...]"; with a default_accel, "label[:key=value,...]"
/// too (a field holding '=' is options, never an accelerator name). Throws InputError naming
/// option and the expected form; the keys are checked by check_accelerator, not here.
inline ColumnSpec parse_column(const std::string& option, const std::string& spec, const std::string& default_accel = "") {
  const std::string form = default_accel.empty() ? "label:accel[:key=value,...]" : "label[:accel][:key=value,...]";
  const size_t a = spec.find(':');
  ColumnSpec c{spec.substr(0, a), default_accel, {}};
  std::string rest = a == std::string::npos ? "" : spec.substr(a + 1);
  if (const size_t b = rest.find(':'); rest.substr(0, b).find('=') == std::string::npos) {
    if (b != std::string::npos || !rest.empty()) c.accel = rest.substr(0, b);
    rest = b == std::string::npos ? "" : rest.substr(b + 1);
  }
  // A label with '=' or ';' is the older dacrt_bench form "label=key:value;key:value".
  if (c.label.empty() || c.accel.empty() || c.label.find_first_of("=;") != std::string::npos)
    throw InputError(option + " '" + spec + "': expected " + form);
  for (size_t p = 0; p < rest.size();) {
    const size_t q = std::min(rest.find(',', p), rest.size());
    if (q > p) c.options.push_back(rest.substr(p, q - p));
    p = q + 1;
  }
  return c;
}

/// Calls check() and puts "option 'arg': " before the message of an InputError it throws, so
/// that of several --column or --variants arguments the error names the wrong one:
/// "--column 'x:bvh:colapse=sah': accelerator 'bvh' has no option(s): colapse (...)".
template <class Check>
void check_argument(const std::string& option, const std::string& arg, Check check) {
  try {
    check();
  } catch (const InputError& e) {
    throw InputError(option + " '" + arg + "': " + e.what());
  }
}

/// One line naming the machine a table was measured on, for the drivers' headers: absolute
/// times and even side-by-side ratios move between CPUs (docs/history/performance.md, session 22).
/// "AMD EPYC (family 26, model 2), 2 logical CPUs, AVX-512, g++ 12.2.0"; on a system
/// without /proc/cpuinfo, "unknown CPU, ...".
inline std::string machine_description() {
  std::string model, family, number;
  bool avx512 = false;
  std::ifstream in("/proc/cpuinfo");
  auto value = [](const std::string& line) {
    const size_t colon = line.find(':');
    return colon == std::string::npos || colon + 2 > line.size() ? std::string() : line.substr(colon + 2);
  };
  for (std::string line; std::getline(in, line) && !line.empty();) {  // the first CPU's block
    if (line.rfind("model name", 0) == 0) model = value(line);
    else if (line.rfind("cpu family", 0) == 0) family = value(line);
    else if (line.rfind("model\t", 0) == 0) number = value(line);
    else if (line.rfind("flags", 0) == 0) avx512 = line.find(" avx512f") != std::string::npos;
  }
  std::string s = model.empty() ? "unknown CPU" : model;
  if (!family.empty()) s += fmt::format(" (family {}, model {})", family, number);
  s += fmt::format(", {} logical CPUs", std::thread::hardware_concurrency());
  if (avx512) s += ", AVX-512";
#if defined(__clang__)
  s += ", clang " __clang_version__;
#elif defined(__GNUC__)
  s += ", g++ " __VERSION__;
#endif
  return s;
}

/// Prints "skipping NAME: WHY (RAYSCOUT_SCENES=...)" to stdout, beside the tables: a scene whose
/// files are missing leaves a gap in them, not an error. The loader's own message already names
/// the variable when a mesh path used it; it is not said twice.
inline void print_skip(const std::string& name, const std::string& why) {
  if (why.find("RAYSCOUT_SCENES") != std::string::npos) fmt::print("skipping {}: {}\n", name, why);
  else fmt::print("skipping {}: {} ({})\n", name, why, scenes_dir_origin());
}

/// The scene `arg` names ("cornell", or a scene or mesh file), or nullopt after a skip line when
/// loading it fails (its meshes are not under $RAYSCOUT_SCENES). A file that is not there at all
/// is a mistake on the command line: InputError naming `option`.
inline std::optional<Scene> load_or_skip(const std::string& option, const std::string& arg, const std::string& name) {
  std::error_code ec;
  if (arg != "cornell" && !std::filesystem::exists(arg, ec)) throw InputError(option + " " + arg + ": no such file");
  try {
    return resolve_scene(arg);
  } catch (const InputError& e) {
    print_skip(name, e.what());
    return std::nullopt;
  }
}

/// Runs a driver's body once its options are parsed: bad input (an unknown scene, a bad
/// --accel-opt) ends with "<name>: error: <what>" and exit 2 instead of std::terminate.
template <class Body>
int run_bench(const char* name, Body&& body) {
  try {
    return body();
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}: error: {}\n", name, e.what());
    return 2;
  }
}

}  // namespace rayscout::bench
