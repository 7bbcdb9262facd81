// Tests of io/csv: exact round trips, the accepted syntax (comments, spaces,
// Windows line ends, a UTF-8 byte-order mark), an error naming the file and
// the line for each kind of malformed input, the measured-curve checks of
// read_measured_curve, and checked writes (a full device is an error).
#include "io/csv.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
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
                                      "0.5,-2e-3\r\n"
                                      "\"1.25\",\" 4 \"\r\n");  // every cell quoted, as spreadsheets may save
  const CsvTable table = read_csv(path, {"torque_Nm"});
  EXPECT_EQ(table.header, (std::vector<std::string>{"time_s", "torque_Nm"}));
  EXPECT_EQ(table.column("time_s"), (std::vector<double>{0.0, 0.5, 1.25}));
  EXPECT_EQ(table.column("torque_Nm"), (std::vector<double>{1.5, -2e-3, 4.0}));
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
      {"\"\",1", ":4: column 'f': empty value"},
      {"1,\"abc\"", ":4: column 'c_q': 'abc' is not a number"},
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

TEST(Csv, TabAndSemicolonSeparatedFilesAreToldToUseCommas) {
  const std::string tabs = write_text("tabs.csv", "t\tz\n0\t0.25\n");
  EXPECT_EQ(read_error(tabs, {"t", "z"}),
            tabs + ":1: the header 't\\tz' is separated by tabs: rover reads comma-separated values only; save "
                   "the file with commas between the columns (and '.' as the decimal point)");
  const std::string semicolons = write_text("semicolons.csv", "# data\nt;z\n0;0,25\n");
  EXPECT_NE(read_error(semicolons, {"t", "z"}).find(":2: the header 't;z' is separated by semicolons ';'"),
            std::string::npos);
  // A quoted name is the user's own spelling.
  const std::string quoted = write_text("quoted.csv", "\"a;b\",z\n1,2\n");
  EXPECT_EQ(read_csv(quoted, {"a;b"}).header.front(), "a;b");
}

TEST(Csv, EmptyFilesAndMissingFilesAreRefused) {
  const std::string empty = write_text("empty.csv", "");
  EXPECT_EQ(read_error(empty), empty + ": empty file (no header line)");
  const std::string comments = write_text("comments.csv", "# nothing\n\n   \n# here\n");
  EXPECT_EQ(read_error(comments), comments + ": empty file (no header line)");
  const std::string header_only = write_text("header_only.csv", "\nf,c_q\n# no rows\n");
  EXPECT_EQ(read_error(header_only), header_only + ":2: no data rows after the header");
  const std::string absent = testing::temp_dir() + "/absent.csv";
  EXPECT_EQ(read_error(absent), absent + ": no such file");
  const std::string dir = testing::temp_dir();
  EXPECT_EQ(read_error(dir), dir + ": is a directory, not a CSV file");
}

TEST(Csv, Utf8ByteOrderMarkIsAccepted) {
  const std::string bom = "\xEF\xBB\xBF";
  const std::vector<std::string> bodies = {"t,z\n0,1\n", "t,z\r\n0,1\r\n", "\"t\",z\n0,1\n",
                                           " t , z\n0,1\n", "# comment\nt,z\n0,1\n",
                                           "\nt,z\n0,1\n"};
  for (const std::string& body : bodies) {
    const CsvTable table = read_csv(write_text("bom.csv", bom + body), {"t", "z"});
    EXPECT_EQ(table.header, (std::vector<std::string>{"t", "z"})) << body;
    EXPECT_EQ(table.column("t"), std::vector<double>{0.0});
  }
  // Only at the start of the file: elsewhere it is not a number.
  const std::string inside = write_text("bom_inside.csv", "t,z\n0," + bom + "1\n");
  EXPECT_NE(read_error(inside).find(":2: column 'z'"), std::string::npos);
}

TEST(Csv, RowsKnowTheirLinesAndMissingColumnsNameTheFile) {
  const std::string path = write_text("lines.csv", "# c\nt,z\n\n0,1\n# gap\n1,2\n");
  const CsvTable table = read_csv(path);
  EXPECT_EQ(table.line_numbers, (std::vector<std::size_t>{4, 6}));
  EXPECT_EQ(table.where(1), path + ":6");
  try {
    table.column("slip");
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": no column 'slip' (columns: t, z)");
  }
}

// The message of the ConfigError that read_measured_curve throws.
std::string curve_error(const std::string& path) {
  try {
    read_measured_curve(path);
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << " was read without error";
  return "";
}

TEST(MeasuredCurve, GoodCurveIsReadWithItsValues) {
  const std::string path = write_text("good.csv", "# SYNTHETIC\nt,z,extra\n0,0.2,9\n0.002,0.199,9\n0.004,-0.1,9\n");
  const MeasuredCurve curve = read_measured_curve(path);
  EXPECT_EQ(curve.t_s, (std::vector<double>{0.0, 0.002, 0.004}));
  EXPECT_EQ(curve.z_m, (std::vector<double>{0.2, 0.199, -0.1}));
  // The shipped synthetic drop passes.
  EXPECT_GT(read_measured_curve(testing::source_path("configs/data/drop_horizontal_synthetic.csv")).t_s.size(), 100u);
}

TEST(MeasuredCurve, TimesThatDoNotIncreaseAreNamedByTheirLine) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 8; ++trial) {
    const int rows = 5 + static_cast<int>(rng() % 20);
    const int bad_row = 1 + static_cast<int>(rng() % static_cast<unsigned>(rows - 1));
    const bool equal = trial % 2 == 0;  // repeated time, or one going back
    std::string text = "t,z\n";
    for (int i = 0; i < rows; ++i) {
      const double t = i == bad_row ? (equal ? 0.01 * (i - 1) : 0.01 * (i - 1) - 0.005) : 0.01 * i;
      text += std::to_string(t) + ",0.2\n";
    }
    const std::string path = write_text("times.csv", text);
    const std::string message = curve_error(path);
    // Row i is on line i + 2 (after the header).
    EXPECT_NE(message.find(path + ":" + std::to_string(bad_row + 2) + ": column 't'"), std::string::npos)
        << message;
    EXPECT_NE(message.find("(line " + std::to_string(bad_row + 1) + ")"), std::string::npos) << message;
    EXPECT_NE(message.find("increase strictly"), std::string::npos) << message;
  }
}

TEST(MeasuredCurve, TooFewRowsHugeHeightsAndMissingColumnsAreRefused) {
  for (const std::string rows : {"0,0.2\n", "0,0.2\n1,0.1\n"}) {
    const std::string path = write_text("short.csv", "t,z\n" + rows);
    EXPECT_NE(curve_error(path).find("a curve needs at least 3"), std::string::npos);
  }
  for (const std::string z : {"1000", "-1000", "1e5", "196.6e3"}) {
    const std::string path = write_text("huge.csv", "t,z\n0,0.2\n# mm?\n1," + z + "\n2,0.2\n");
    const std::string message = curve_error(path);
    EXPECT_NE(message.find(path + ":4: column 'z': "), std::string::npos) << message;
    EXPECT_NE(message.find("|z| < 1000"), std::string::npos) << message;
  }
  EXPECT_NE(curve_error(write_text("time.csv", "time,z\n0,1\n1,1\n2,1\n")).find("missing column 't'"),
            std::string::npos);
  EXPECT_NE(curve_error(write_text("nan.csv", "t,z\n0,1\n1,nan\n2,1\n")).find(":3: column 'z'"),
            std::string::npos);
}

TEST(Csv, WriteToAFullDeviceFailsAndLeavesTheDevice) {
  ASSERT_TRUE(fs::is_character_file("/dev/full"));
  try {
    write_csv("/dev/full", {"t", "z"}, {std::vector<double>(10000, 0.5), std::vector<double>(10000, 0.25)});
    ADD_FAILURE() << "no error writing to /dev/full";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/full: cannot write"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
  EXPECT_FALSE(fs::exists("/dev/full.partial"));
  // A device that takes the data is written in place.
  EXPECT_NO_THROW(write_csv("/dev/null", {"t"}, {{1.0}}));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  // A directory is refused by name.
  const std::string dir = testing::temp_dir();
  EXPECT_THROW(write_csv(dir, {"t"}, {{1.0}}), std::runtime_error);
  EXPECT_TRUE(fs::is_directory(dir));
}

// A stop request during the write leaves the earlier file as it was and no
// temporary; without one the file is written.
TEST(Csv, AStopDuringTheWriteLeavesTheEarlierFile) {
  const std::string path = testing::temp_dir() + "/stopped.csv";
  std::ofstream(path) << "a\n7\n";
  const std::vector<double> many(3 * kStopCheckRows, 0.5);
  std::atomic<bool> stop{true};
  EXPECT_FALSE(write_csv(path, {"a"}, {many}, "", &stop));
  std::ifstream in(path);
  const std::string kept((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(kept, "a\n7\n");
  EXPECT_FALSE(fs::exists(path + ".partial"));
  stop = false;
  EXPECT_TRUE(write_csv(path, {"a"}, {many}, "", &stop));
  EXPECT_EQ(read_csv(path).rows(), many.size());
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

// The channel a curve's header declares, as write_csv writes rover
// synthesize's header: read back; a curve from elsewhere declares none.
TEST(DeclaredChannel, ReadsWhatTheHeaderDeclares) {
  const std::string dir = rover::testing::temp_dir();
  write_csv(dir + "/right.csv", {"t", "z"}, {{0.0, 0.1, 0.2}, {0.3, 0.2, 0.25}},
            "SYNTHETIC measured drop curve.\nColumns: t [s], z [m] = B_r_z, the world z of the right bogie pin B_r.");
  EXPECT_EQ(declared_channel(dir + "/right.csv"), "B_r_z");
  write_csv(dir + "/plain.csv", {"t", "z"}, {{0.0, 0.1, 0.2}, {0.3, 0.2, 0.25}}, "a drop on the test rig");
  EXPECT_EQ(declared_channel(dir + "/plain.csv"), "");
  write_csv(dir + "/described.csv", {"t", "z"}, {{0.0, 0.1, 0.2}, {0.3, 0.2, 0.25}},
            "Columns: t [s], z [m] = world z of the left bogie pin B_l.");
  EXPECT_EQ(declared_channel(dir + "/described.csv"), "");
  EXPECT_EQ(declared_channel(dir + "/absent.csv"), "");
  // A byte-order mark before the header (a "CSV UTF-8" save) hides nothing.
  std::ifstream right(dir + "/right.csv", std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(right)), std::istreambuf_iterator<char>());
  std::ofstream(dir + "/marked.csv", std::ios::binary) << "\xEF\xBB\xBF" << text;
  EXPECT_EQ(declared_channel(dir + "/marked.csv"), "B_r_z");
}

}  // namespace
}  // namespace rover::io
