// bench_support.h's interleaved_medians: the call order every driver's timing relies on.
#include <vector>

#include <gtest/gtest.h>

#include "bench_support.h"

namespace rayscout::bench {
namespace {

TEST(InterleavedMedians, WarmUpEachColumnThenRoundsInColumnOrder) {
  std::vector<size_t> calls;
  std::vector<double> next = {100, 200, 1, 5, 3, 6, 2, 4};  // warm-ups 100, 200 are dropped
  const std::vector<double> m = interleaved_medians(2, {.count = 3}, [&](size_t k) {
    calls.push_back(k);
    return next[calls.size() - 1];
  });
  EXPECT_EQ(calls, (std::vector<size_t>{0, 1, 0, 1, 0, 1, 0, 1}));
  EXPECT_EQ(m, (std::vector<double>{2, 5}));  // medians of {1, 3, 2} and {5, 6, 4}
}

TEST(InterleavedMedians, NoWarmUp) {
  std::vector<size_t> calls;
  const std::vector<double> m = interleaved_medians(3, {.count = 2, .warm_up = false}, [&](size_t k) {
    calls.push_back(k);
    return double(10 * k + calls.size());
  });
  EXPECT_EQ(calls, (std::vector<size_t>{0, 1, 2, 0, 1, 2}));
  EXPECT_EQ(m, (std::vector<double>{2.5, 13.5, 24.5}));  // {1, 4}, {12, 15}, {23, 26}
}

TEST(InterleavedMedians, AlternateReversesOddRounds) {
  std::vector<size_t> calls;
  (void)interleaved_medians(3, {.count = 3, .alternate = true}, [&](size_t k) {
    calls.push_back(k);
    return 0.0;
  });
  EXPECT_EQ(calls, (std::vector<size_t>{0, 1, 2, /* rounds: */ 0, 1, 2, 2, 1, 0, 0, 1, 2}));
}

}  // namespace
}  // namespace rayscout::bench
