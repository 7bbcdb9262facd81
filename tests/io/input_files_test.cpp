// The inputs a command must not overwrite (io/input_files.hpp): the fallback
// that takes every existing file a JSON config names, transitively.
#include "io/input_files.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace rover::io {
namespace {

namespace fs = std::filesystem;

class InputFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("input_files_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path path = dir_ / name;
    std::ofstream(path) << text;
    return path.string();
  }
  fs::path dir_;
};

TEST_F(InputFilesTest, ConfigNamesFilesTransitivelyRelativeToEachConfig) {
  const std::string data = write("data.csv", "t,z\n0,0.2\n");
  write("scenario.json", R"({"rover": "rover.json"})");
  const std::string rover = write("rover.json", "{}");
  const std::string study =
      write("study.json", R"({"scenario": "scenario.json", "data": [{"file": "data.csv"}], "name": "x"})");
  InputFiles inputs;
  inputs.add_config(study, "--study");
  ASSERT_NE(inputs.same_file_as(data), nullptr);
  EXPECT_EQ(inputs.same_file_as(data)->named_by, "'data[0].file' in " + study);
  ASSERT_NE(inputs.same_file_as(rover), nullptr);
  EXPECT_NE(inputs.same_file_as(rover)->named_by.find("scenario.json"), std::string::npos);
  EXPECT_EQ(inputs.same_file_as(write("other.h5", "")), nullptr);
}

TEST_F(InputFilesTest, DescriptionIsTextEvenWhenItSpellsAFileName) {
  const std::string result = write("result.h5", "");
  const std::string data = write("data.csv", "t,z\n0,0.2\n");
  const std::string study = write("study.json",
                                  R"({"description": "result.h5", "data": {"file": "data.csv",
                                      "description": "data.csv"}})");
  InputFiles inputs;
  inputs.add_config(study, "--study");
  EXPECT_EQ(inputs.same_file_as(result), nullptr);
  ASSERT_NE(inputs.same_file_as(data), nullptr);
  EXPECT_EQ(inputs.same_file_as(data)->named_by, "'data.file' in " + study);
}

}  // namespace
}  // namespace rover::io
