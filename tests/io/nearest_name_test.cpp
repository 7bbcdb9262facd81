// The nearest known name to a mistyped one (io/nearest_name.hpp).
#include "io/nearest_name.hpp"

#include <gtest/gtest.h>

namespace rover::io {
namespace {

TEST(EditDistance, CountsEachEditOnceAndAnAdjacentSwapAsOne) {
  EXPECT_EQ(edit_distance("simulate", "simulate"), 0u);
  EXPECT_EQ(edit_distance("simulat", "simulate"), 1u);       // deletion
  EXPECT_EQ(edit_distance("distribuiton", "distribution"), 1u);  // transposition
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);         // the classic example
  EXPECT_EQ(edit_distance("", "abc"), 3u);
}

TEST(NearestName, SuggestsACloseSpelling) {
  const std::vector<std::string> flags = {"--scenario", "--out", "--csv", "--crab-deg"};
  EXPECT_EQ(nearest_name("--scenaro", flags), "--scenario");
  EXPECT_EQ(nearest_name("--otu", flags), "--out");
}

TEST(NearestName, SuggestsTheOnlyNameThatSharesTheFirstWord) {
  const std::vector<std::string> flags = {"--scenario", "--out", "--crab-deg", "--speed-mps"};
  EXPECT_EQ(nearest_name("--crab-angle", flags), "--crab-deg");
  EXPECT_EQ(nearest_name("--speed-kmh", flags), "--speed-mps");
  const std::vector<std::string> keys = {"noise_sd", "rate_hz", "scenario"};
  EXPECT_EQ(nearest_name("noise_level", keys), "noise_sd");
}

TEST(NearestName, SuggestsNothingWhenTheFirstWordIsSharedByManyOrIsShort) {
  const std::vector<std::string> flags = {"--crab-deg", "--crab-rate", "--no-plot", "--no-progress"};
  EXPECT_EQ(nearest_name("--crab-angle", flags), "");
  EXPECT_EQ(nearest_name("--no-pictures-at-all", flags), "");
  EXPECT_EQ(nearest_name("--temperature", flags), "");  // one word, far from every name
}

}  // namespace
}  // namespace rover::io
