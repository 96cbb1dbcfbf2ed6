// SplitMix64 against the published test vectors of the reference implementation (Vigna's
// splitmix64.c, the stream of Java's SplittableRandom): the sampler, the shafts' sample rays
// and manylight's seeds all come from it.
#include <gtest/gtest.h>

#include <cstdint>

#include "rayscout/core/random.h"

namespace rayscout {
namespace {

TEST(SplitMix64, PublishedStreams) {
  SplitMix64 zero{0};
  for (const uint64_t want : {0xe220a8397b1dcdafull, 0x6e789e6aa1b965f4ull, 0x06c45d188009454full, 0xf88bb8a8724c81ecull})
    EXPECT_EQ(zero.next(), want);
  SplitMix64 s{1234567};
  for (const uint64_t want : {6457827717110365317ull, 3203168211198807973ull, 9817491932198370423ull,
                              4593380528125082431ull, 16408922859458223821ull})
    EXPECT_EQ(s.next(), want);
}

// uniform(): the top 24 bits of the next output over 2^24 (0xe220a8 and 0x6e789e above).
TEST(SplitMix64, UniformIsTheTop24BitsOverTwoTo24) {
  SplitMix64 zero{0};
  EXPECT_EQ(zero.uniform(), float(0xe220a8) / 16777216.0f);
  EXPECT_EQ(zero.uniform(), float(0x6e789e) / 16777216.0f);
}

}  // namespace
}  // namespace rayscout
