// scenes_dir: which folder, and that messages name it plainly.
#include "rayscout/core/scenes_dir.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

namespace rayscout {
namespace {

// Sets (or, with nullopt, unsets) an environment variable for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, std::optional<std::string> value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value) setenv(name, value->c_str(), 1);
    else unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_) setenv(name_, old_->c_str(), 1);
    else unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

bool has_dot_dot(const std::filesystem::path& p) {
  for (const auto& part : p)
    if (part == "..") return true;
  return false;
}

TEST(ScenesDir, EnvironmentWinsOverTheDefaults) {
  const ScopedEnv scenes("RAYSCOUT_SCENES", "/data/scenes");
  const ScopedEnv ctest_default("RAYSCOUT_DEFAULT_SCENES", "/elsewhere");
  EXPECT_EQ(scenes_dir(), "/data/scenes");
  EXPECT_EQ(scenes_dir_origin(), "RAYSCOUT_SCENES=/data/scenes");
}

// The build's default is ../shared/scenes beside the source tree, said without the "..": a skip
// message read "/src/rayscout/../shared/scenes".
TEST(ScenesDir, BuildDefaultIsANormalPath) {
  const ScopedEnv scenes("RAYSCOUT_SCENES", std::nullopt);
  const ScopedEnv ctest_default("RAYSCOUT_DEFAULT_SCENES", std::nullopt);
  const std::filesystem::path dir = scenes_dir();
  EXPECT_FALSE(has_dot_dot(dir)) << dir;
  EXPECT_TRUE(dir.is_absolute()) << dir;
  EXPECT_EQ(dir.filename(), "scenes") << dir;
  EXPECT_EQ(dir.parent_path().filename(), "shared") << dir;
  EXPECT_EQ(scenes_dir_origin(), "RAYSCOUT_SCENES is not set, default " + dir.string());
}

}  // namespace
}  // namespace rayscout
