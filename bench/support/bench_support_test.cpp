// bench_support.h: interleaved_medians' call order, which every driver's timing relies on, and
// parse_column, the form of core_bench --column and dacrt_bench --variants, and check_argument,
// which names such an argument in the errors of its checks.
#include <string>
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

void expect_column(const ColumnSpec& c, const std::string& label, const std::string& accel,
                   const std::vector<std::string>& options) {
  EXPECT_EQ(c.label, label);
  EXPECT_EQ(c.accel, accel);
  EXPECT_EQ(c.options, options);
}

TEST(ParseColumn, LabelAccelOptions) {
  expect_column(parse_column("--column", "p1:bvh:presplit=0.1"), "p1", "bvh", {"presplit=0.1"});
  expect_column(parse_column("--column", "e:embree:robust=off,packet=16"), "e", "embree", {"robust=off", "packet=16"});
  expect_column(parse_column("--column", "b:bvh"), "b", "bvh", {});
  expect_column(parse_column("--column", "b:bvh:"), "b", "bvh", {});
}

TEST(ParseColumn, AccelMayBeLeftOutOnlyWithADefault) {
  expect_column(parse_column("--variants", "cs:cost=sampled,skip=on", "dacrt-rs"), "cs", "dacrt-rs",
                {"cost=sampled", "skip=on"});
  expect_column(parse_column("--variants", "plain", "dacrt-rs"), "plain", "dacrt-rs", {});
  expect_column(parse_column("--variants", "a:dacrt:cost=sampled", "dacrt-rs"), "a", "dacrt", {"cost=sampled"});
  EXPECT_THROW(parse_column("--column", "p1:presplit=0.1"), InputError);
  EXPECT_THROW(parse_column("--column", "p1"), InputError);
  EXPECT_THROW(parse_column("--column", ":bvh"), InputError);
}

TEST(ParseColumn, OlderVariantFormIsAnErrorNamingTheForm) {
  try {
    parse_column("--variants", "cs=cost:sampled;skip:on", "dacrt-rs");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--variants 'cs=cost:sampled;skip:on': expected label[:accel][:key=value,...]");
  }
}

TEST(CheckArgument, AnErrorNamesTheArgumentItCameFrom) {
  bool called = false;
  check_argument("--column", "b:bvh", [&] { called = true; });
  EXPECT_TRUE(called);
  try {
    check_argument("--column", "bvh-x:bvh:colapse=sah", [] { throw InputError("accelerator 'bvh' has no option(s): colapse"); });
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--column 'bvh-x:bvh:colapse=sah': accelerator 'bvh' has no option(s): colapse");
  }
}

}  // namespace
}  // namespace rayscout::bench
