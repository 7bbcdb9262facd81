// HDF5 result files: an RAII writer that never leaves a file that looks
// complete after a failure, and a reader for resume, comparison and tests.
//
// Hdf5Writer refuses a path that is no writable regular file (a link, a
// device, a read-only file: io/output_target.hpp), writes to "<path>.partial"
// and renames it to <path> only in commit(); destroying a writer without
// commit() removes the partial file.
// Datasets are stored the way h5py and numpy expect them: 2-D data row-major
// (rows x cols), strings as variable-length UTF-8. Object modification times
// are not recorded, so the same content gives byte-identical files. Large
// numeric datasets are chunked and compressed (shuffle + deflate).
//
// Large matrices that arrive a row at a time (one curve per run of a study)
// are written with create_matrix() and write_row(): memory is one chunk cache,
// whatever the number of rows. Rows may come in any order; the bytes of the
// file depend on that order (chunks are laid out as they fill), so write them
// in index order (study/runtime/ordered_sink.hpp) for files identical on any number
// of MPI ranks.
//
// A full disk (ENOSPC, EDQUOT) or file size limit (EFBIG) makes the failing
// call throw a std::runtime_error that names the file and says so; the writer
// can then only be destroyed, which removes "<path>.partial" and does not
// crash (see prepare_hdf5_library() in hdf5_file.cpp: the HDF5 library is not
// closed at exit, as its exit handler crashes on a file whose close failed).
//
// Every failure is a std::runtime_error naming the file and the object; the
// HDF5 library's own error stack printing is switched off (H5Eset_auto) and its
// innermost message is appended to ours.
//
// Not thread-safe (serial HDF5): use one thread for HDF5 at a time.
#pragma once

#include <Eigen/Core>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rover::io {

class Hdf5Writer {
 public:
  explicit Hdf5Writer(const std::string& path);
  ~Hdf5Writer();  // without commit(): closes and removes "<path>.partial"
  Hdf5Writer(const Hdf5Writer&) = delete;
  Hdf5Writer& operator=(const Hdf5Writer&) = delete;

  // Datasets. Names are absolute or relative to the root ("/band/mean" and
  // "band/mean" are the same); missing intermediate groups are created. Writing
  // an existing dataset is an error.
  void write(const std::string& dataset, const std::vector<double>& values);  // 1-D
  void write(const std::string& dataset, const std::vector<double>& row_major_values,
             std::size_t rows, std::size_t cols);                          // 2-D
  void write(const std::string& dataset, const Eigen::MatrixXd& matrix);   // 2-D, rows x cols
  void write(const std::string& dataset, const std::vector<int>& values);  // 1-D
  void write(const std::string& dataset, const std::vector<std::string>& values);  // 1-D
  // A chunked 2-D dataset of rows x cols doubles, every element fill_value
  // (NaN for curves) until written, then written row by row in any order with
  // write_row(); memory independent of rows. Chunks hold whole rows,
  // max(1, 64 KiB / (8 cols)) of them, compressed like the other large
  // datasets (shuffle + deflate). The dataset stays open until commit().
  void create_matrix(const std::string& dataset, std::size_t rows, std::size_t cols,
                     double fill_value);
  // Writes row `row` (< rows) of a dataset made by create_matrix(); `cols`
  // must be its column count. A row may be written again (it is replaced).
  void write_row(const std::string& dataset, std::size_t row, const double* values,
                 std::size_t cols);
  // Creates an (empty) group, with its intermediate groups; no-op if it exists.
  void create_group(const std::string& group);

  // Attributes of an object: "/" (the file) or an existing group or dataset.
  // Writing an existing attribute replaces it.
  void attribute(const std::string& object, const std::string& name, double value);
  void attribute(const std::string& object, const std::string& name, long long value);
  // An unsigned 64-bit integer (a seed: 0 .. 2^64 - 1), stored as such.
  void unsigned_attribute(const std::string& object, const std::string& name, std::uint64_t value);
  void attribute(const std::string& object, const std::string& name, const std::string& value);
  void attribute(const std::string& object, const std::string& name,
                 const std::vector<double>& values);
  // Any other integer type (int, std::size_t, ...) is stored as a 64-bit integer.
  template <std::integral T>
  requires(!std::same_as<T, bool> &&
           !std::same_as<T, long long>) void attribute(const std::string& object,
                                                       const std::string& name, T value) {
    attribute(object, name, static_cast<long long>(value));
  }
  void attribute(const std::string& object, const std::string& name, const char* value) {
    attribute(object, name, std::string(value));
  }

  // Closes the file and renames "<path>.partial" to <path> (replacing an older
  // file atomically). Nothing can be written afterwards. If closing fails (a
  // full disk shows here when the data were cached), the partial file is
  // removed and a std::runtime_error thrown.
  void commit();

  const std::string& path() const { return path_; }

 private:
  void require_open(const std::string& object) const;
  // Closes the datasets of create_matrix(); returns the message of the first
  // failure (empty if none).
  std::string close_row_datasets();

  struct RowDataset {
    std::int64_t id;  // hid_t, open until commit() or destruction
    std::size_t rows, cols;
  };

  std::string path_, partial_path_;
  std::int64_t file_ = -1;  // hid_t
  std::map<std::string, RowDataset> row_datasets_;  // by normalised name ("/a/b")
};

// Whether `path` is an HDF5 file (its signature), for readers of text
// formats that would otherwise show its bytes as column names.
bool is_hdf5_file(const std::string& path);

class Hdf5Reader {
 public:
  // Throws if the file is missing, no HDF5 file, damaged, or held open for
  // writing by another program (HDF5's file locking: "<path> is locked by
  // another program that has it open for writing ...: close it there").
  explicit Hdf5Reader(const std::string& path);
  ~Hdf5Reader();
  Hdf5Reader(const Hdf5Reader&) = delete;
  Hdf5Reader& operator=(const Hdf5Reader&) = delete;

  // True if a dataset or group exists at this path ("/" always exists).
  bool exists(const std::string& object) const;
  // Dimensions of a dataset ({} for a scalar).
  std::vector<std::size_t> shape(const std::string& dataset) const;
  // Any shape, flattened row-major; integer datasets are converted.
  std::vector<double> read_doubles(const std::string& dataset) const;
  // A 2-D dataset as rows x cols (a 1-D dataset of n values gives n x 1).
  Eigen::MatrixXd read_matrix(const std::string& dataset) const;
  // Integer datasets only (floating-point data is refused, not truncated).
  std::vector<int> read_ints(const std::string& dataset) const;
  // Variable- or fixed-length string datasets, flattened row-major.
  std::vector<std::string> read_strings(const std::string& dataset) const;

  bool has_attribute(const std::string& object, const std::string& name) const;
  double attribute_double(const std::string& object, const std::string& name) const;
  long long attribute_integer(const std::string& object, const std::string& name) const;
  std::string attribute_string(const std::string& object, const std::string& name) const;
  std::vector<double> attribute_doubles(const std::string& object, const std::string& name) const;

  // Names of the members of a group, sorted.
  std::vector<std::string> list(const std::string& group = "/") const;

  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::int64_t file_ = -1;  // hid_t
};

}  // namespace rover::io
