// Tests of io/hdf5_file: round trips of every type through a file, the
// partial-file protocol (nothing that looks complete before commit), and error
// messages that name the file and the object.
#include "io/hdf5_file.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
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

}  // namespace
}  // namespace rover::io
