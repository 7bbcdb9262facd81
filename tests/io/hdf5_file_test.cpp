// Tests of io/hdf5_file: round trips of every type through a file, row-wise
// matrices (rows in any order, unwritten rows the fill value, unwritten chunks
// not stored), the partial-file protocol (nothing that looks complete before
// commit), error messages that name the file and the object, and a full disk
// (a clear error and a clean exit, in a child process with a file size limit).
#include "io/hdf5_file.hpp"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <random>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <thread>

#include "test_support.hpp"

namespace rover::io {
namespace {

namespace fs = std::filesystem;

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Expects `call` to throw a std::runtime_error whose message contains every one of `parts`.
template <typename Call>
void expect_error_naming(Call call, const std::vector<std::string>& parts) {
  try {
    call();
    ADD_FAILURE() << "no exception thrown";
  } catch (const std::runtime_error& e) {
    for (const std::string& part : parts)
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
          << "message '" << e.what() << "' does not name '" << part << "'";
  }
}

// A file another program holds open for writing keeps HDF5's exclusive
// lock on it (flock, as h5py's "r+" or HDFView take it): reading it is
// refused as locked, not as damaged; once the lock is gone, or beside another
// reader's shared lock, it is read.
TEST(Hdf5File, FileLockedByAWriterIsReportedAsLocked) {
  const std::string path = testing::temp_dir() + "/held.h5";
  {
    Hdf5Writer writer(path);
    writer.write("/t", std::vector<double>{0.0, 1.0});
    writer.commit();
  }
  const int writer_fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  ASSERT_GE(writer_fd, 0);
  ASSERT_EQ(::flock(writer_fd, LOCK_EX | LOCK_NB), 0);
  expect_error_naming([&] { const Hdf5Reader reader(path); },
                      {path, "is locked by another program", "open for writing", "close it there"});
  try {
    const Hdf5Reader reader(path);
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).find("damaged"), std::string::npos) << e.what();
  }
  ASSERT_EQ(::flock(writer_fd, LOCK_SH), 0);  // now another reader's lock
  EXPECT_EQ(Hdf5Reader(path).read_doubles("/t"), (std::vector<double>{0.0, 1.0}));
  ::close(writer_fd);
  EXPECT_EQ(Hdf5Reader(path).read_doubles("/t"), (std::vector<double>{0.0, 1.0}));
}

TEST(Hdf5File, RoundTripOfEveryType) {
  const std::string path = testing::temp_dir() + "/all.h5";
  const std::vector<double> doubles = {
      0.1, -0.0, 1.0 / 3.0, 1e-300, 5e-324, -1e300, std::numeric_limits<double>::infinity()};
  const std::vector<double> grid = {1, 2, 3, 4, 5, 6};  // 2 x 3, row-major
  Eigen::MatrixXd matrix(3, 4);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) matrix(i, j) = 10.0 * i + j + 0.25;
  const std::vector<int> ints = {0, -1, 7, std::numeric_limits<int>::min(),
                                 std::numeric_limits<int>::max()};
  const std::vector<std::string> strings = {"ok", "", "wheel 3: slip > 0.9, aborted",
                                            "\xcf\x86 (phi)"};
  const long long big = (1LL << 53) + 1;  // not representable as a double
  {
    Hdf5Writer writer(path);
    writer.write("/band/mean", doubles);
    writer.write("grid", grid, 2, 3);
    writer.write("/band/matrix", matrix);
    writer.write("/status", ints);
    writer.write("/deep/er/messages", strings);
    writer.attribute("/", "version", std::string("0.1.0"));
    writer.attribute("/", "seed", big);
    writer.attribute("/", "runs", std::size_t{1000});
    writer.attribute("/band/mean", "level", 0.95);
    writer.attribute("/band", "edges", std::vector<double>{-1.5, 0.0, 2.5});
    writer.attribute("/band", "label", "c_q");
    writer.attribute("/band", "label", "f");  // replaces
    writer.commit();
  }
  const Hdf5Reader reader(path);
  const std::vector<double> back = reader.read_doubles("/band/mean");
  ASSERT_EQ(back.size(), doubles.size());
  for (std::size_t i = 0; i < doubles.size(); ++i) {
    EXPECT_EQ(back[i], doubles[i]) << i;
    EXPECT_EQ(std::signbit(back[i]), std::signbit(doubles[i])) << i;
  }
  EXPECT_EQ(reader.shape("grid"), (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(reader.read_doubles("/grid"), grid);
  // Matrices are stored rows x cols, row-major (as h5py/numpy read them).
  EXPECT_EQ(reader.shape("/band/matrix"), (std::vector<std::size_t>{3, 4}));
  const std::vector<double> flat = reader.read_doubles("/band/matrix");
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_EQ(flat[static_cast<std::size_t>(4 * i + j)], matrix(i, j));
  EXPECT_EQ(reader.read_matrix("/band/matrix"), matrix);
  EXPECT_EQ(reader.read_matrix("/grid")(1, 0), 4.0);
  EXPECT_EQ(reader.read_ints("/status"), ints);
  EXPECT_EQ(reader.read_doubles("/status")[3], static_cast<double>(ints[3]));
  EXPECT_EQ(reader.read_strings("/deep/er/messages"), strings);

  EXPECT_EQ(reader.attribute_string("/", "version"), "0.1.0");
  EXPECT_EQ(reader.attribute_integer("/", "seed"), big);
  EXPECT_EQ(reader.attribute_integer("/", "runs"), 1000);
  EXPECT_EQ(reader.attribute_double("/band/mean", "level"), 0.95);
  EXPECT_EQ(reader.attribute_doubles("/band", "edges"), (std::vector<double>{-1.5, 0.0, 2.5}));
  EXPECT_EQ(reader.attribute_string("/band", "label"), "f");
  EXPECT_TRUE(reader.has_attribute("/band/mean", "level"));
  EXPECT_FALSE(reader.has_attribute("/band/mean", "levels"));
  EXPECT_FALSE(reader.has_attribute("/nowhere", "level"));

  EXPECT_EQ(reader.list(), (std::vector<std::string>{"band", "deep", "grid", "status"}));
  EXPECT_EQ(reader.list("/band"), (std::vector<std::string>{"matrix", "mean"}));
  EXPECT_TRUE(reader.exists("/band"));
  EXPECT_TRUE(reader.exists("band/mean"));
  EXPECT_FALSE(reader.exists("/band/median"));
  EXPECT_FALSE(reader.exists("/grid/below_a_dataset"));
}

TEST(Hdf5File, EmptyDatasetsAndAttributesRoundTrip) {
  const std::string path = testing::temp_dir() + "/empty.h5";
  {
    Hdf5Writer writer(path);
    writer.write("/d", std::vector<double>{});
    writer.write("/i", std::vector<int>{});
    writer.write("/s", std::vector<std::string>{});
    writer.write("/m", Eigen::MatrixXd(0, 3));
    writer.create_group("/empty/group");
    writer.attribute("/d", "none", std::vector<double>{});
    writer.commit();
  }
  const Hdf5Reader reader(path);
  EXPECT_TRUE(reader.read_doubles("/d").empty());
  EXPECT_TRUE(reader.read_ints("/i").empty());
  EXPECT_TRUE(reader.read_strings("/s").empty());
  EXPECT_EQ(reader.shape("/m"), (std::vector<std::size_t>{0, 3}));
  EXPECT_EQ(reader.read_matrix("/m").cols(), 3);
  EXPECT_TRUE(reader.list("/empty/group").empty());
  EXPECT_TRUE(reader.attribute_doubles("/d", "none").empty());
}

TEST(Hdf5File, LargeDatasetsAreCompressedAndExact) {
  const std::string path = testing::temp_dir() + "/large.h5";
  // A smooth 400 x 300 field (compressible) with an irrational-ish pattern.
  Eigen::MatrixXd field(400, 300);
  for (int i = 0; i < field.rows(); ++i)
    for (int j = 0; j < field.cols(); ++j) field(i, j) = std::sin(0.01 * i) * std::cos(0.02 * j);
  {
    Hdf5Writer writer(path);
    writer.write("/field", field);
    writer.commit();
  }
  EXPECT_EQ(Hdf5Reader(path).read_matrix("/field"), field);
  EXPECT_LT(fs::file_size(path), static_cast<std::uintmax_t>(field.size()) * sizeof(double));
}

TEST(Hdf5File, NothingLooksCompleteBeforeCommit) {
  const std::string path = testing::temp_dir() + "/result.h5";
  {
    Hdf5Writer writer(path);
    writer.write("/x", std::vector<double>{1.0, 2.0});
    EXPECT_FALSE(fs::exists(path));
    EXPECT_TRUE(fs::exists(path + ".partial"));
  }  // destroyed without commit, as after an exception
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));

  Hdf5Writer writer(path);
  writer.write("/x", std::vector<double>{3.0});
  writer.commit();
  EXPECT_TRUE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));
  EXPECT_THROW(writer.write("/y", std::vector<double>{1.0}), std::runtime_error);
}

TEST(Hdf5File, OlderFileIsReplacedOnlyAtCommit) {
  const std::string path = testing::temp_dir() + "/result.h5";
  {
    Hdf5Writer old_run(path);
    old_run.write("/x", std::vector<double>{1.0});
    old_run.commit();
  }
  {
    Hdf5Writer failed_run(path);
    failed_run.write("/x", std::vector<double>{2.0});
    EXPECT_EQ(Hdf5Reader(path).read_doubles("/x"), std::vector<double>{1.0});
  }
  EXPECT_EQ(Hdf5Reader(path).read_doubles("/x"), std::vector<double>{1.0});
  Hdf5Writer new_run(path);
  new_run.write("/x", std::vector<double>{3.0});
  new_run.commit();
  EXPECT_EQ(Hdf5Reader(path).read_doubles("/x"), std::vector<double>{3.0});
}

TEST(Hdf5File, SameContentGivesIdenticalBytes) {
  const std::string dir = testing::temp_dir();
  for (const char* name : {"/a.h5", "/b.h5"}) {
    Hdf5Writer writer(dir + name);
    writer.write("/g/x", std::vector<double>{1.0, 2.0});
    writer.write("/g/s", std::vector<std::string>{"one", "two"});
    writer.attribute("/", "note", "same");
    writer.commit();
    if (name[1] == 'a') std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  }
  EXPECT_EQ(file_bytes(dir + "/a.h5"), file_bytes(dir + "/b.h5"));
}

TEST(Hdf5File, ErrorsNameTheFileAndTheObject) {
  const std::string path = testing::temp_dir() + "/errors.h5";
  {
    Hdf5Writer writer(path);
    writer.write("/band/mean", std::vector<double>{1.0, 2.0});
    writer.write("/count", std::vector<double>{1.5});
    expect_error_naming([&] { writer.write("/band/mean", std::vector<double>{3.0}); },
                        {path, "/band/mean", "already"});
    expect_error_naming([&] { writer.write("/count/x", std::vector<double>{3.0}); },
                        {path, "/count", "not a group"});
    expect_error_naming(
        [&] {
          writer.write("/m", std::vector<double>{1, 2, 3}, 2, 2);
        },
        {path, "/m", "2 x 2"});
    expect_error_naming([&] { writer.attribute("/nowhere", "a", 1.0); }, {path, "/nowhere", "a"});
    writer.commit();
  }
  const Hdf5Reader reader(path);
  expect_error_naming([&] { reader.read_doubles("/band/median"); },
                      {path, "/band/median", "no such dataset"});
  expect_error_naming([&] { reader.shape("/nothing"); }, {path, "/nothing"});
  expect_error_naming([&] { reader.read_ints("/count"); }, {path, "/count", "floating-point"});
  // A group where a dataset is expected: an intact file of another layout, not a damaged one.
  expect_error_naming([&] { reader.read_doubles("/band"); }, {path, "/band", "is a group, not a dataset"});
  try {
    reader.read_strings("/band");
  } catch (const std::exception& e) {
    EXPECT_EQ(std::string(e.what()).find("damaged"), std::string::npos) << e.what();
  }
  expect_error_naming([&] { reader.read_strings("/count"); }, {path, "/count", "strings"});
  expect_error_naming([&] { reader.attribute_double("/band/mean", "level"); },
                      {path, "/band/mean", "level"});
  expect_error_naming([&] { reader.list("/band/mean"); }, {path, "/band/mean"});

  const std::string missing = testing::temp_dir() + "/missing.h5";
  expect_error_naming([&] { Hdf5Reader{missing}; }, {missing, "no such file"});
  const std::string text = testing::temp_dir() + "/text.h5";
  std::ofstream(text) << "not hdf5\n";
  expect_error_naming([&] { Hdf5Reader{text}; }, {text, "not an HDF5 file"});
  expect_error_naming([&] { Hdf5Writer{"/nonexistent-dir/x.h5"}; }, {"/nonexistent-dir/x.h5"});
}

TEST(Hdf5File, RowWiseMatrixInAnyOrderWithUnwrittenRowsFilled) {
  const std::string path = testing::temp_dir() + "/rows.h5";
  const std::size_t rows = 300, cols = 1001;  // 8 rows per 64 KiB chunk
  Eigen::MatrixXd curves(rows, cols);
  for (std::size_t i = 0; i < rows; ++i)
    for (std::size_t j = 0; j < cols; ++j) curves(i, j) = 0.28 + 1e-3 * std::sin(0.01 * static_cast<double>(i * j));
  std::vector<std::size_t> order(rows);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937_64(4));
  {
    Hdf5Writer writer(path);
    writer.create_matrix("/curves/B_l_z", rows, cols, std::nan(""));
    writer.create_matrix("empty", 0, 3, 0.0);
    for (const std::size_t i : order) {
      if (i % 7 == 3) continue;  // failed runs: never written
      const Eigen::RowVectorXd row = curves.row(static_cast<Eigen::Index>(i));
      writer.write_row("curves/B_l_z", i, row.data(), cols);
    }
    writer.commit();
  }
  const Hdf5Reader reader(path);
  EXPECT_EQ(reader.shape("/curves/B_l_z"), (std::vector<std::size_t>{rows, cols}));
  EXPECT_EQ(reader.shape("/empty"), (std::vector<std::size_t>{0, 3}));
  const Eigen::MatrixXd back = reader.read_matrix("/curves/B_l_z");
  for (std::size_t i = 0; i < rows; ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    if (i % 7 == 3)
      EXPECT_TRUE(back.row(r).array().isNaN().all()) << i;
    else
      EXPECT_EQ(back.row(r), curves.row(r)) << i;
  }
  EXPECT_LT(fs::file_size(path), static_cast<std::uintmax_t>(rows * cols * sizeof(double)));
}

TEST(Hdf5File, UnwrittenRowsCostNoSpace) {
  // 10^5 x 1001 doubles are 800 MB; three written rows must not make a large file.
  const std::string path = testing::temp_dir() + "/sparse.h5";
  const std::vector<double> row(1001, 0.25);
  {
    Hdf5Writer writer(path);
    writer.create_matrix("/curves", 100000, row.size(), std::nan(""));
    for (const std::size_t i : {0, 50000, 99999}) writer.write_row("/curves", i, row.data(), row.size());
    writer.commit();
  }
  EXPECT_LT(fs::file_size(path), 1u << 20);
  EXPECT_EQ(Hdf5Reader(path).shape("/curves"), (std::vector<std::size_t>{100000, 1001}));
}

TEST(Hdf5File, RowsInTheSameOrderGiveIdenticalBytes) {
  const std::string dir = testing::temp_dir();
  const std::size_t rows = 40, cols = 500;
  auto write = [&](const std::string& name, bool reversed) {
    Hdf5Writer writer(dir + name);
    writer.create_matrix("/m", rows, cols, 0.0);
    for (std::size_t k = 0; k < rows; ++k) {
      const std::size_t i = reversed ? rows - 1 - k : k;
      std::vector<double> row(cols);
      for (std::size_t j = 0; j < cols; ++j) row[j] = std::cos(0.3 * static_cast<double>(i) + 0.01 * static_cast<double>(j));
      writer.write_row("/m", i, row.data(), cols);
    }
    writer.attribute("/m", "note", "same");
    writer.commit();
  };
  write("/a.h5", false);
  write("/b.h5", false);
  write("/c.h5", true);
  EXPECT_EQ(file_bytes(dir + "/a.h5"), file_bytes(dir + "/b.h5"));
  EXPECT_EQ(Hdf5Reader(dir + "/a.h5").read_matrix("/m"), Hdf5Reader(dir + "/c.h5").read_matrix("/m"));
}

TEST(Hdf5File, RowWriteErrorsNameTheFileAndTheDataset) {
  const std::string path = testing::temp_dir() + "/row_errors.h5";
  Hdf5Writer writer(path);
  writer.create_matrix("/m", 4, 3, 0.0);
  writer.write("/plain", std::vector<double>{1.0});
  const double row[3] = {1, 2, 3};
  expect_error_naming([&] { writer.write_row("/m", 4, row, 3); }, {path, "/m", "row 4", "4 x 3"});
  expect_error_naming([&] { writer.write_row("/m", 0, row, 2); }, {path, "/m", "4 x 3"});
  expect_error_naming([&] { writer.write_row("/plain", 0, row, 3); }, {path, "/plain", "create_matrix"});
  expect_error_naming([&] { writer.create_matrix("/m", 1, 1, 0.0); }, {path, "/m", "already"});
  writer.commit();
  EXPECT_THROW(writer.write_row("/m", 0, row, 3), std::runtime_error);
}

// In a forked child limited to a few hundred KB per file (a full disk without
// root): writing a large incompressible dataset must throw a clear error, and
// destroying the writer and exiting (through the normal exit handlers) must
// not crash. Exit codes: 0 as expected, 1 nothing thrown, 2 unclear message.
int full_disk_child(const std::string& path, bool row_wise) {
  const rlimit limit{300 * 1024, 300 * 1024};
  setrlimit(RLIMIT_FSIZE, &limit);
  std::signal(SIGXFSZ, SIG_IGN);
  std::mt19937_64 engine(1);
  std::normal_distribution<double> normal;
  const std::size_t rows = 2000, cols = 1000;  // 16 MB of random doubles
  std::vector<double> values(rows * cols);
  for (double& v : values) v = normal(engine);
  try {
    Hdf5Writer writer(path);
    if (row_wise) {
      writer.create_matrix("/curves", rows, cols, std::nan(""));
      for (std::size_t i = 0; i < rows; ++i) writer.write_row("/curves", i, &values[i * cols], cols);
    } else {
      writer.write("/curves", values, rows, cols);
    }
    writer.commit();
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    std::fprintf(stderr, "full disk: %s\n", message.c_str());
    const bool clear = message.find(path) != std::string::npos &&
                       message.find("disk is full") != std::string::npos;
    return clear ? 0 : 2;
  }
  return 1;
}

TEST(Hdf5File, FullDiskIsAClearErrorAndACleanExit) {
  for (const bool row_wise : {false, true}) {
    const std::string path = testing::temp_dir() + (row_wise ? "/rows.h5" : "/whole.h5");
    std::fflush(nullptr);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) std::exit(full_disk_child(path, row_wise));  // runs the exit handlers
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status)) << "row_wise " << row_wise << ": the child died of signal "
                                   << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    EXPECT_EQ(WEXITSTATUS(status), 0) << "row_wise " << row_wise;
    EXPECT_FALSE(fs::exists(path));
    EXPECT_FALSE(fs::exists(path + ".partial"));
  }
}

}  // namespace
}  // namespace rover::io
