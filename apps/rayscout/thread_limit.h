// --threads of `render` and `trace`: one TBB limit for the whole process, and the thread
// count it really gives (TBB's default arena never runs more threads than it sees cores).
#pragma once

#include <algorithm>
#include <memory>

#include <fmt/core.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

namespace rayscout::cli {

struct ThreadLimit {
  /// requested: --threads (0 = all cores). Warns when more than the cores are asked for.
  explicit ThreadLimit(int requested) {
    const int cores = tbb::info::default_concurrency();
    if (requested > cores)
      fmt::print(stderr, "rayscout: warning: --threads {} on {} cores: running {} threads\n", requested, cores, cores);
    threads = requested > 0 ? std::min(requested, cores) : cores;
    // Limits every TBB parallel region of this process, Embree's build included.
    control = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(threads));
  }
  int threads = 1;
  std::unique_ptr<tbb::global_control> control;
};

}  // namespace rayscout::cli
