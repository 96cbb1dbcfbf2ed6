// What the benchmark drivers share: medians of repetitions, checks of name lists, error exits.
#pragma once

#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "rayscout/core/input_error.h"
#include "rayscout/core/median.h"

namespace rayscout::bench {

// Median of the repetitions' times; never empty: every driver's repetition options are
// checked to be at least 1.
using rayscout::median;

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
