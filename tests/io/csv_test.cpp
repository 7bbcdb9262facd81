// Tests of io/csv: exact round trips, the accepted syntax (comments, spaces,
// Windows line ends), and an error naming the file and the line for each kind
// of malformed input.
#include "io/csv.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "io/json_reader.hpp"
#include "test_support.hpp"

namespace rover::io {
namespace {

namespace fs = std::filesystem;

std::string write_text(const std::string& name, const std::string& text) {
  const std::string path = testing::temp_dir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// The message of the ConfigError that read_csv throws (fails the test if none).
std::string read_error(const std::string& path, const std::vector<std::string>& required = {}) {
  try {
    read_csv(path, required);
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << " was read without error";
  return "";
}

TEST(Csv, RoundTripIsExact) {
  const std::string path = testing::temp_dir() + "/table.csv";
  const std::vector<double> f = {0.1, 1.0 / 3.0, -1e-300, 5e-324, 1e300, -0.0, 42.0};
  std::vector<double> c_q;
  for (const double x : f) c_q.push_back(std::nextafter(x, 1.0));
  write_csv(path, {"f", "c_q"}, {f, c_q}, "response surface\nrover 0.1.0");
  EXPECT_FALSE(fs::exists(path + ".partial"));

  const CsvTable table = read_csv(path, {"c_q", "f"});
  EXPECT_EQ(table.header, (std::vector<std::string>{"f", "c_q"}));
  ASSERT_EQ(table.rows(), f.size());
  EXPECT_EQ(table.column("f"), f);
  EXPECT_EQ(table.column("c_q"), c_q);
  EXPECT_TRUE(std::signbit(table.column("f")[5]));
  EXPECT_THROW(table.column("slip"), std::runtime_error);
}

TEST(Csv, AcceptsCommentsSpacesAndWindowsLineEnds) {
  const std::string path = write_text("loose.csv",
                                      "# measured on the test bench\r\n"
                                      "\r\n"
                                      " time_s , \"torque_Nm\" \r\n"
                                      "0, +1.5   # first sample\r\n"
                                      "   # a comment between rows\r\n"
                                      "0.5,-2e-3\r\n");
  const CsvTable table = read_csv(path, {"torque_Nm"});
  EXPECT_EQ(table.header, (std::vector<std::string>{"time_s", "torque_Nm"}));
  EXPECT_EQ(table.column("time_s"), (std::vector<double>{0.0, 0.5}));
  EXPECT_EQ(table.column("torque_Nm"), (std::vector<double>{1.5, -2e-3}));
}

TEST(Csv, EachMalformedLineIsNamedWithItsNumber) {
  const std::string header = "# comment\nf,c_q\n1,2\n";  // data from line 4 on
  struct Case {
    std::string last_line, expected;
  };
  const std::vector<Case> cases = {
      {"1,2,3", ":4: expected 2 values, got 3"},
      {"1", ":4: expected 2 values, got 1"},
      {"1,2,", ":4: expected 2 values, got 3"},
      {"1,abc", ":4: column 'c_q': 'abc' is not a number"},
      {"1.5x,2", ":4: column 'f': '1.5x' is not a number"},
      {"1,NaN", ":4: column 'c_q': 'NaN' is not a finite number"},
      {"nan,1", ":4: column 'f': 'nan' is not a finite number"},
      {"-inf,1", ":4: column 'f': '-inf' is not a finite number"},
      {"1e999,1", ":4: column 'f': '1e999' is out of range"},
      {",1", ":4: column 'f': empty value"},
  };
  for (const Case& c : cases) {
    const std::string path = write_text("bad.csv", header + c.last_line + "\n1,2\n");
    EXPECT_EQ(read_error(path), path + c.expected) << c.last_line;
  }
}

TEST(Csv, HeaderProblemsAreNamed) {
  const std::string missing = write_text("missing.csv", "# c_q sweep\nf,T\n1,2\n");
  EXPECT_EQ(read_error(missing, {"f", "c_q"}),
            missing + ":2: missing column 'c_q' (columns: f, T)");
  const std::string duplicate = write_text("duplicate.csv", "f,f\n1,2\n");
  EXPECT_EQ(read_error(duplicate), duplicate + ":1: duplicate column 'f'");
  const std::string unnamed = write_text("unnamed.csv", "f,,c_q\n1,2,3\n");
  EXPECT_EQ(read_error(unnamed), unnamed + ":1: empty column name in the header");
}

TEST(Csv, EmptyFilesAndMissingFilesAreRefused) {
  const std::string empty = write_text("empty.csv", "");
  EXPECT_EQ(read_error(empty), empty + ": empty file (no header line)");
  const std::string comments = write_text("comments.csv", "# nothing\n\n   \n# here\n");
  EXPECT_EQ(read_error(comments), comments + ": empty file (no header line)");
  const std::string header_only = write_text("header_only.csv", "\nf,c_q\n# no rows\n");
  EXPECT_EQ(read_error(header_only), header_only + ":2: no data rows after the header");
  const std::string absent = testing::temp_dir() + "/absent.csv";
  EXPECT_EQ(read_error(absent), absent + ": cannot open file");
}

TEST(Csv, WriteRefusesInconsistentColumnsAndLeavesNothing) {
  const std::string path = testing::temp_dir() + "/out.csv";
  EXPECT_THROW(write_csv(path, {"a", "b"}, {{1.0, 2.0}, {1.0}}), std::invalid_argument);
  EXPECT_THROW(write_csv(path, {"a"}, {{1.0}, {2.0}}), std::invalid_argument);
  EXPECT_THROW(write_csv(path, {"a,b"}, {{1.0}}), std::invalid_argument);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));
  EXPECT_THROW(write_csv(testing::temp_dir() + "/no/such/dir/out.csv", {"a"}, {{1.0}}),
               std::runtime_error);
}

}  // namespace
}  // namespace rover::io
