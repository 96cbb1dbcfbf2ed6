// The up-front memory check of requests that cannot fit (render, rays).
#include <gtest/gtest.h>

#include <string>

#include "rayscout/core/input_error.h"
#include "rayscout/core/machine_memory.h"

namespace rayscout {
namespace {

TEST(MachineMemory, RefusesOnlyWhatExceedsTheMachine) {
  const double have = machine_memory_bytes();
  ASSERT_GT(have, 256e6) << "Linux reports its memory through sysinfo";
  EXPECT_NO_THROW(require_memory(have * 0.5, "half the machine needs"));
  EXPECT_NO_THROW(require_memory(have, "exactly the machine needs"));
  try {
    require_memory(have * 2.0, "twice the machine needs");
    FAIL() << "twice the machine's memory was accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    char gb[32];
    std::snprintf(gb, sizeof gb, "%.1f GB", have * 2e-9);
    EXPECT_NE(msg.find(std::string("twice the machine needs at least ") + gb), std::string::npos) << msg;
    EXPECT_NE(msg.find("more than this machine's"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace rayscout
