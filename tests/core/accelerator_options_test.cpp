// AcceleratorOptions: typed access and the errors that name the option.
#include <gtest/gtest.h>

#include <string>

#include "rayscout/core/accelerator_options.h"

namespace rayscout {
namespace {

std::string error_of(const AcceleratorOptions& o, double lo, double hi) {
  try {
    o.get_double("fraction", 0.5, lo, hi);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Printed with six digits, 1.0000001 read "1 is not in [0, 1]".
TEST(AcceleratorOptions, OutOfRangeDoubleIsPrintedAsGiven) {
  AcceleratorOptions o;
  o.set("fraction=1.0000001");
  EXPECT_EQ(error_of(o, 0.0, 1.0), "option 'fraction': 1.0000001 is not in [0, 1]");
  o.set("fraction=5e-7");
  EXPECT_EQ(error_of(o, 1e-6, 4096.0), "option 'fraction': 5e-07 is not in [1e-06, 4096]");
}

// Each malformed value names the rule it broke: bins=1e9 said "'1e9' is not a number".
TEST(AcceleratorOptions, MalformedValuesSayWhatIsWrong) {
  auto error = [](const std::string& kv, bool integer) {
    AcceleratorOptions o;
    o.set(kv);
    try {
      if (integer) (void)o.get_int("k", 0);
      else (void)o.get_double("k", 0.0);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error("k=1e9", true), "option 'k': '1e9' is not an integer");
  EXPECT_EQ(error("k=16.5", true), "option 'k': '16.5' is not an integer");
  EXPECT_EQ(error("k=99999999999999999999", true), "option 'k': '99999999999999999999' is out of range");
  EXPECT_EQ(error("k=1e999", false), "option 'k': '1e999' is out of range");
  EXPECT_EQ(error("k=8x", true), "option 'k': '8x' is not a number");
  EXPECT_EQ(error("k=", true), "option 'k': '' is not a number");
  EXPECT_EQ(error("k=x", false), "option 'k': 'x' is not a number");
}

TEST(AcceleratorOptions, RepeatedKeyAndUnusedKeyAreErrors) {
  const std::string list[] = {"skip=on", "skip=off"};
  EXPECT_THROW(AcceleratorOptions::from_list(list), InputError);
  AcceleratorOptions o;
  o.set("skpi=on");
  EXPECT_TRUE(o.get_bool("skip", true));  // the misspelt key is not read...
  EXPECT_THROW(o.check_all_used("bvh"), InputError);  // ...and so reported
}

// The error names the keys the accelerator read, its options, so that a misspelt key needs no
// trip to the accelerator's doc (it named only the unknown key).
TEST(AcceleratorOptions, UnusedKeyErrorNamesTheKeysRead) {
  AcceleratorOptions o;
  o.set("skpi=on");
  o.get_bool("skip", true);
  o.get_int("bins", 32);
  try {
    o.check_all_used("dacrt-rs");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "accelerator 'dacrt-rs' has no option(s): skpi (its options: bins, skip)");
  }
  AcceleratorOptions none;
  none.set("x=1");
  try {
    none.check_all_used("brute");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "accelerator 'brute' has no option(s): x (it has no options)");
  }
}

// unread(): the same values, none of them asked for yet (what make_accelerator reads from).
TEST(AcceleratorOptions, UnreadKeepsTheValuesAndForgetsTheReads) {
  AcceleratorOptions o;
  o.set("bins=8");
  EXPECT_EQ(o.get_int("bins", 32), 8);
  EXPECT_NO_THROW(o.check_all_used("bvh"));
  const AcceleratorOptions fresh = o.unread();
  EXPECT_THROW(fresh.check_all_used("brute"), InputError);
  EXPECT_EQ(fresh.get_int("bins", 32), 8);
  EXPECT_NO_THROW(fresh.check_all_used("bvh"));
}

}  // namespace
}  // namespace rayscout
