// Tests of io/output_lock: one holder at a time (flock locks belong to an
// open file, so a second lock of the same process is refused as another
// process's would be), a probe that keeps nothing, the lock file removed by
// its holder, and a file of the user's at the lock's name never removed.
#include "io/output_lock.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "test_support.hpp"

namespace rover::io {
namespace {

namespace fs = std::filesystem;

TEST(OutputLock, OneHolderAtATime) {
  const std::string out = testing::temp_dir() + "/result.h5";
  EXPECT_FALSE(OutputLock::held_elsewhere(out));
  {
    const OutputLock lock(out);
    EXPECT_TRUE(fs::exists(OutputLock::path_for(out)));
    EXPECT_TRUE(OutputLock::held_elsewhere(out));
    try {
      const OutputLock second(out);
      ADD_FAILURE() << "a second lock was taken";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("another rover process is writing " + out), std::string::npos) << e.what();
    }
  }
  EXPECT_FALSE(fs::exists(OutputLock::path_for(out)));
  EXPECT_FALSE(OutputLock::held_elsewhere(out));
  const OutputLock again(out);  // free once released
}

TEST(OutputLock, AFileOfTheUsersAtTheLocksNameIsKept) {
  const std::string out = testing::temp_dir() + "/result.h5";
  std::ofstream(OutputLock::path_for(out)) << "my notes\n";
  EXPECT_THROW(OutputLock lock(out), std::runtime_error);
  std::ifstream in(OutputLock::path_for(out));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "my notes");
}

TEST(OutputLock, ALeftoverLockFileOfAKilledHolderIsReused) {
  const std::string out = testing::temp_dir() + "/result.h5";
  std::ofstream(OutputLock::path_for(out)).close();  // empty, unlocked: its holder died
  EXPECT_FALSE(OutputLock::held_elsewhere(out));
  { const OutputLock lock(out); }
  EXPECT_FALSE(fs::exists(OutputLock::path_for(out)));
}

}  // namespace
}  // namespace rover::io
