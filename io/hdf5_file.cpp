// See hdf5_file.hpp.
#include "io/hdf5_file.hpp"

#include <hdf5.h>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>
#include <type_traits>
#include <utility>

#include "io/json_reader.hpp"
#include "io/output_target.hpp"

namespace rover::io {
namespace {

static_assert(std::is_same_v<hid_t, std::int64_t>, "hid_t is stored as std::int64_t");

// Numeric datasets with at least this many elements are chunked and compressed.
constexpr hsize_t kCompressMinElements = 1 << 16;
// Chunks hold at most this many elements (1 MiB of doubles: HDF5's default chunk cache).
constexpr hsize_t kChunkElements = 1 << 17;
constexpr unsigned kDeflateLevel = 4;

// Owns one HDF5 identifier and closes it with the matching H5?close.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(Handle&& other) noexcept
      : id_(std::exchange(other.id_, H5I_INVALID_HID)), close_(other.close_) {}
  Handle& operator=(Handle&&) = delete;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  hid_t get() const { return id_; }

 private:
  hid_t id_ = H5I_INVALID_HID;
  herr_t (*close_)(hid_t) = nullptr;
};

// Called before any other HDF5 call of a reader or writer. Error printing is
// switched off (errors become exceptions). And the library is told not to
// close itself at exit: after a failed write (a full disk) H5Fclose fails and
// leaves the file's identifier pointing at freed memory, which the library's
// own exit handler would close again and crash on. Files are always closed by
// their owners, so nothing is left for that handler to do. (H5dont_atexit only
// acts before the library's first initialisation; later calls are no-ops.)
void prepare_hdf5_library() {
  H5dont_atexit();
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

// What HDF5's error stack says about the last failure (the stack is cleared):
// its innermost message, and the errno of a failed system call if one is
// reported ("errno = 28, ..." in the file driver's message), else 0.
struct Hdf5ErrorDetail {
  std::string innermost;
  int system_error = 0;
};

Hdf5ErrorDetail hdf5_error_detail() {
  Hdf5ErrorDetail detail;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned n, const H5E_error2_t* error, void* out) -> herr_t {
        auto& d = *static_cast<Hdf5ErrorDetail*>(out);
        if (!error->desc) return 0;
        const std::string desc = error->desc;
        if (n == 0) d.innermost = desc;
        if (const std::size_t at = desc.find("errno = "); at != std::string::npos && !d.system_error)
          d.system_error = std::atoi(desc.c_str() + at + 8);
        return 0;
      },
      &detail);
  H5Eclear2(H5E_DEFAULT);
  return detail;
}

// An input HDF5 file that HDF5 cannot open or read: said in rover's words.
std::string damaged_input(const std::string& file) {
  return file + " is not a readable HDF5 file (damaged or incomplete: cut short while written or copied?)";
}

// An input HDF5 file that H5Fopen refused: a file cut short says how much of
// it is there ("truncated file: eof = 3000, ..., stored_eof = 459784").
std::string unopenable_input(const std::string& file, const Hdf5ErrorDetail& detail) {
  const std::string& text = detail.innermost;
  const std::size_t eof = text.find("eof = "), stored = text.find("stored_eof = ");
  if (text.find("truncated file") == std::string::npos || eof == std::string::npos || stored == std::string::npos)
    return damaged_input(file);
  const std::string have = text.substr(eof + 6, text.find_first_not_of("0123456789", eof + 6) - eof - 6);
  const std::string want = text.substr(stored + 13, text.find_first_not_of("0123456789", stored + 13) - stored - 13);
  return file + " is not a complete HDF5 file: it ends after " + have + " of its " + want +
         " bytes (cut short while written or copied?)";
}

// Whether another program holds `path` open for writing through HDF5, whose
// file locking (HDF5 1.10 and later, also h5py and HDFView) keeps an
// exclusive flock(2) on a file open for writing: a shared lock cannot be had.
bool locked_for_writing(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool locked = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && (errno == EWOULDBLOCK || errno == EAGAIN);
  ::close(fd);  // and the lock with it, if taken
  return locked;
}

std::string locked_input(const std::string& file) {
  return file + " is locked by another program that has it open for writing (HDF5 file locking): close it there "
                "(or let that program finish), then run again";
}

// Whose file an HDF5 call failed on: one rover writes, or an input it reads.
enum class Access { kWrite, kRead };

// "<file>: <what>: <problem>", with the cause from HDF5's error stack. For a
// file rover writes, a full disk is said in plain words, else HDF5's
// innermost message is added; for an input, a failed call means the file is
// damaged or incomplete, said in rover's words (HDF5's own text is no help).
std::string error_message(const std::string& file, const std::string& what,
                          const std::string& problem, Access access = Access::kWrite) {
  std::string message = file + ": " + what + ": " + problem;
  const Hdf5ErrorDetail detail = hdf5_error_detail();
  if (access == Access::kRead)
    return detail.innermost.empty() && detail.system_error == 0 ? message : message + ": " + damaged_input(file);
  const int e = detail.system_error;
  if (e == ENOSPC || e == EFBIG || e == EDQUOT)
    message += ": " + std::string(std::strerror(e)) +
               " (the disk is full or the file size limit is reached)";
  else if (!detail.innermost.empty())
    message += " (HDF5: " + detail.innermost + ")";
  return message;
}

[[noreturn]] void fail(const std::string& file, const std::string& what,
                       const std::string& problem, Access access = Access::kWrite) {
  throw std::runtime_error(error_message(file, what, problem, access));
}

std::string dataset_label(const std::string& name) { return "dataset '" + name + "'"; }
std::string attribute_label(const std::string& object, const std::string& name) {
  return "attribute '" + name + "' of '" + object + "'";
}

// Throws (naming file and object) if an HDF5 call returned a negative value.
template <typename T>
T check(T result, const std::string& file, const std::string& what, const std::string& problem,
        Access access = Access::kWrite) {
  if (result < 0) fail(file, what, problem, access);
  return result;
}

Handle checked_handle(hid_t id, herr_t (*close)(hid_t), const std::string& file,
                      const std::string& what, const std::string& problem, Access access = Access::kWrite) {
  return Handle(check(id, file, what, problem, access), close);
}

// "/a//b/c/" -> {"a", "b", "c"}
std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (start <= path.size()) {
    const std::size_t end = std::min(path.find('/', start), path.size());
    if (end > start) parts.push_back(path.substr(start, end - start));
    start = end + 1;
  }
  return parts;
}

std::string join_path(const std::vector<std::string>& parts, std::size_t count) {
  std::string path;
  for (std::size_t i = 0; i < count; ++i) path += "/" + parts[i];
  return path.empty() ? "/" : path;
}

// True if every component of `path` exists (intermediate ones being groups).
bool object_exists(hid_t file, const std::string& path) {
  const std::vector<std::string> parts = split_path(path);
  for (std::size_t i = 1; i <= parts.size(); ++i) {
    const std::string prefix = join_path(parts, i);
    if (H5Lexists(file, prefix.c_str(), H5P_DEFAULT) <= 0) {
      H5Eclear2(H5E_DEFAULT);
      return false;
    }
    if (i < parts.size()) {
      const Handle object(H5Oopen(file, prefix.c_str(), H5P_DEFAULT), H5Oclose);
      if (object.get() < 0 || H5Iget_type(object.get()) != H5I_GROUP) {
        H5Eclear2(H5E_DEFAULT);
        return false;
      }
    }
  }
  return true;
}

// Object creation properties shared by groups and datasets: no time stamps,
// so that identical content gives identical bytes.
void no_time_stamps(hid_t plist, const std::string& file, const std::string& what) {
  check(H5Pset_obj_track_times(plist, false), file, what, "cannot set creation properties");
}

// Creates the groups along `path` that are missing (all of them when
// `include_last`, else all but the last component).
void create_groups(hid_t file, const std::string& file_name, const std::string& path,
                   bool include_last) {
  const std::vector<std::string> parts = split_path(path);
  const std::size_t groups = include_last ? parts.size() : (parts.empty() ? 0 : parts.size() - 1);
  for (std::size_t i = 1; i <= groups; ++i) {
    const std::string prefix = join_path(parts, i);
    const std::string what = "group '" + prefix + "'";
    if (check(H5Lexists(file, prefix.c_str(), H5P_DEFAULT), file_name, what, "cannot look up") >
        0) {
      const Handle object = checked_handle(H5Oopen(file, prefix.c_str(), H5P_DEFAULT), H5Oclose,
                                           file_name, what, "cannot open");
      if (H5Iget_type(object.get()) != H5I_GROUP)
        fail(file_name, what, "exists and is not a group (needed for '" + path + "')");
      continue;
    }
    const Handle gcpl = checked_handle(H5Pcreate(H5P_GROUP_CREATE), H5Pclose, file_name, what,
                                       "cannot create property list");
    no_time_stamps(gcpl.get(), file_name, what);
    checked_handle(H5Gcreate2(file, prefix.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), H5Gclose,
                   file_name, what, "cannot create group");
  }
}

// Creates dataset `name` of `file_type` and `dims` and writes `data` (in
// `memory_type`) to it.
void write_dataset(hid_t file, const std::string& file_name, const std::string& name,
                   hid_t memory_type, hid_t file_type, const std::vector<hsize_t>& dims,
                   const void* data, bool compressible) {
  const std::string what = dataset_label(name);
  if (split_path(name).empty()) fail(file_name, what, "empty dataset name");
  create_groups(file, file_name, name, /*include_last=*/false);
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0) fail(file_name, what, "already written");
  H5Eclear2(H5E_DEFAULT);

  hsize_t elements = 1;
  for (const hsize_t d : dims) elements *= d;
  const Handle space =
      checked_handle(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                     H5Sclose, file_name, what, "cannot create dataspace");
  const Handle dcpl = checked_handle(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, file_name, what,
                                     "cannot create property list");
  no_time_stamps(dcpl.get(), file_name, what);
  if (compressible && elements >= kCompressMinElements && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
    // Chunks of whole rows (or row pieces), at most kChunkElements each.
    std::vector<hsize_t> chunk(dims);
    const hsize_t last = std::min<hsize_t>(chunk.back(), kChunkElements);
    chunk.back() = last;
    hsize_t room = kChunkElements / last;
    for (std::size_t i = chunk.size() - 1; i-- > 0;) {
      chunk[i] = std::max<hsize_t>(1, std::min(chunk[i], room));
      room = std::max<hsize_t>(1, room / chunk[i]);
    }
    check(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()), file_name, what,
          "cannot set chunking");
    check(H5Pset_shuffle(dcpl.get()), file_name, what, "cannot set shuffle filter");
    check(H5Pset_deflate(dcpl.get(), kDeflateLevel), file_name, what, "cannot set deflate filter");
  }
  const Handle dataset = checked_handle(
      H5Dcreate2(file, name.c_str(), file_type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
      H5Dclose, file_name, what, "cannot create dataset");
  if (elements > 0)
    check(H5Dwrite(dataset.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), file_name,
          what, "cannot write");
}

Handle variable_string_type(const std::string& file, const std::string& what) {
  Handle type = checked_handle(H5Tcopy(H5T_C_S1), H5Tclose, file, what, "cannot create type");
  check(H5Tset_size(type.get(), H5T_VARIABLE), file, what, "cannot create string type");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), file, what, "cannot create string type");
  return type;
}

Handle open_object(hid_t file, const std::string& file_name, const std::string& object,
                   const std::string& what, Access access) {
  if (!object_exists(file, object)) fail(file_name, what, "no such object '" + object + "'");
  return checked_handle(H5Oopen(file, object.c_str(), H5P_DEFAULT), H5Oclose, file_name, what,
                        "cannot open '" + object + "'", access);
}

// Creates attribute `name` on `object` (replacing an existing one) and writes it.
void write_attribute(hid_t file, const std::string& file_name, const std::string& object,
                     const std::string& name, hid_t memory_type, hid_t file_type, hid_t space,
                     const void* data) {
  const std::string what = attribute_label(object, name);
  const Handle target = open_object(file, file_name, object, what, Access::kWrite);
  if (check(H5Aexists(target.get(), name.c_str()), file_name, what, "cannot look up") > 0)
    check(H5Adelete(target.get(), name.c_str()), file_name, what, "cannot replace");
  const Handle attribute = checked_handle(
      H5Acreate2(target.get(), name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
      file_name, what, "cannot create");
  if (H5Sget_select_npoints(space) > 0)
    check(H5Awrite(attribute.get(), memory_type, data), file_name, what, "cannot write");
}

// Number of elements of a dataspace.
std::size_t element_count(hid_t space, const std::string& file, const std::string& what) {
  return static_cast<std::size_t>(
      check(H5Sget_simple_extent_npoints(space), file, what, "cannot read the dataspace", Access::kRead));
}

// Reads a whole string dataset or attribute of `type` with `count` elements.
// `read(memory_type, buffer)` performs the H5Dread / H5Aread.
template <typename Read>
std::vector<std::string> read_string_data(hid_t type, std::size_t count, const std::string& file,
                                          const std::string& what, Read read) {
  if (H5Tget_class(type) != H5T_STRING) fail(file, what, "does not hold strings", Access::kRead);
  std::vector<std::string> out;
  out.reserve(count);
  if (count == 0) return out;
  const htri_t variable = check(H5Tis_variable_str(type), file, what, "cannot inspect the type", Access::kRead);
  if (variable > 0) {
    const Handle memory_type = variable_string_type(file, what);
    std::vector<char*> buffer(count, nullptr);
    check(read(memory_type.get(), buffer.data()), file, what, "cannot read", Access::kRead);
    for (char* s : buffer) {
      out.emplace_back(s ? s : "");
      if (s) H5free_memory(s);
    }
    return out;
  }
  const std::size_t size = H5Tget_size(type);
  const H5T_str_t padding = H5Tget_strpad(type);
  std::vector<char> buffer(count * size);
  const Handle memory_type =
      checked_handle(H5Tcopy(type), H5Tclose, file, what, "cannot copy type", Access::kRead);
  check(read(memory_type.get(), buffer.data()), file, what, "cannot read", Access::kRead);
  for (std::size_t i = 0; i < count; ++i) {
    std::string s(buffer.data() + i * size, size);
    const char pad = padding == H5T_STR_SPACEPAD ? ' ' : '\0';
    const std::size_t end = s.find_last_not_of(pad);
    s.erase(end == std::string::npos ? 0 : end + 1);
    if (pad == '\0') s.erase(std::min(s.find('\0'), s.size()));
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace

// ------------------------------------------------------------------ Hdf5Writer

Hdf5Writer::Hdf5Writer(const std::string& path) : path_(path), partial_path_(path + ".partial") {
  require_output(path_, OutputFormat::kSeekable);
  prepare_hdf5_library();
  const Handle fcpl = checked_handle(H5Pcreate(H5P_FILE_CREATE), H5Pclose, path_, "file",
                                     "cannot create property list");
  no_time_stamps(fcpl.get(), path_, "file");
  create_temporary(partial_path_, path_);
  file_ = H5Fcreate(partial_path_.c_str(), H5F_ACC_TRUNC, fcpl.get(), H5P_DEFAULT);
  if (file_ < 0) fail(path_, "file", "cannot create '" + partial_path_ + "'");
}

Hdf5Writer::~Hdf5Writer() {
  if (file_ < 0) return;  // committed, or commit() failed and cleaned up
  close_row_datasets();
  // After a failed write this close fails too; the file is gone either way.
  H5Fclose(file_);
  H5Eclear2(H5E_DEFAULT);
  std::error_code ignored;
  std::filesystem::remove(partial_path_, ignored);
}

std::string Hdf5Writer::close_row_datasets() {
  std::string first_error;
  for (const auto& [name, dataset] : row_datasets_)
    if (H5Dclose(dataset.id) < 0) {
      const std::string message = error_message(path_, dataset_label(name), "cannot close");
      if (first_error.empty()) first_error = message;
    }
  row_datasets_.clear();
  return first_error;
}

void Hdf5Writer::require_open(const std::string& what) const {
  if (file_ < 0) throw std::runtime_error(path_ + ": " + what + ": file already committed");
}

void Hdf5Writer::write(const std::string& dataset, const std::vector<double>& values) {
  require_open(dataset_label(dataset));
  write_dataset(file_, path_, dataset, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, {values.size()},
                values.data(), true);
}

void Hdf5Writer::write(const std::string& dataset, const std::vector<double>& row_major_values,
                       std::size_t rows, std::size_t cols) {
  require_open(dataset_label(dataset));
  if (row_major_values.size() != rows * cols)
    throw std::runtime_error(path_ + ": " + dataset_label(dataset) + ": " +
                             std::to_string(row_major_values.size()) + " values for a " +
                             std::to_string(rows) + " x " + std::to_string(cols) + " dataset");
  write_dataset(file_, path_, dataset, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, {rows, cols},
                row_major_values.data(), true);
}

void Hdf5Writer::write(const std::string& dataset, const Eigen::MatrixXd& matrix) {
  require_open(dataset_label(dataset));
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> row_major = matrix;
  write_dataset(file_, path_, dataset, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE,
                {static_cast<hsize_t>(matrix.rows()), static_cast<hsize_t>(matrix.cols())},
                row_major.data(), true);
}

void Hdf5Writer::write(const std::string& dataset, const std::vector<int>& values) {
  require_open(dataset_label(dataset));
  write_dataset(file_, path_, dataset, H5T_NATIVE_INT, H5T_STD_I32LE, {values.size()},
                values.data(), true);
}

void Hdf5Writer::write(const std::string& dataset, const std::vector<std::string>& values) {
  const std::string what = dataset_label(dataset);
  require_open(what);
  std::vector<const char*> pointers;
  pointers.reserve(values.size());
  for (const std::string& s : values) pointers.push_back(s.c_str());
  const Handle type = variable_string_type(path_, what);
  write_dataset(file_, path_, dataset, type.get(), type.get(), {values.size()}, pointers.data(),
                false);
}

void Hdf5Writer::create_group(const std::string& group) {
  require_open("group '" + group + "'");
  create_groups(file_, path_, group, /*include_last=*/true);
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name, double value) {
  const std::string what = attribute_label(object, name);
  require_open(what);
  const Handle space = checked_handle(H5Screate(H5S_SCALAR), H5Sclose, path_, what, "dataspace");
  write_attribute(file_, path_, object, name, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, space.get(),
                  &value);
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name, long long value) {
  const std::string what = attribute_label(object, name);
  require_open(what);
  const Handle space = checked_handle(H5Screate(H5S_SCALAR), H5Sclose, path_, what, "dataspace");
  write_attribute(file_, path_, object, name, H5T_NATIVE_LLONG, H5T_STD_I64LE, space.get(), &value);
}

void Hdf5Writer::unsigned_attribute(const std::string& object, const std::string& name, std::uint64_t value) {
  const std::string what = attribute_label(object, name);
  require_open(what);
  const Handle space = checked_handle(H5Screate(H5S_SCALAR), H5Sclose, path_, what, "dataspace");
  write_attribute(file_, path_, object, name, H5T_NATIVE_UINT64, H5T_STD_U64LE, space.get(), &value);
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name,
                           const std::string& value) {
  const std::string what = attribute_label(object, name);
  require_open(what);
  const Handle space = checked_handle(H5Screate(H5S_SCALAR), H5Sclose, path_, what, "dataspace");
  const Handle type = variable_string_type(path_, what);
  const char* text = value.c_str();
  write_attribute(file_, path_, object, name, type.get(), type.get(), space.get(), &text);
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name,
                           const std::vector<double>& values) {
  const std::string what = attribute_label(object, name);
  require_open(what);
  const hsize_t n = values.size();
  // An empty attribute has a null dataspace (a zero-length simple one is not allowed).
  const Handle space = checked_handle(n ? H5Screate_simple(1, &n, nullptr) : H5Screate(H5S_NULL),
                                      H5Sclose, path_, what, "dataspace");
  write_attribute(file_, path_, object, name, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, space.get(),
                  values.data());
}

void Hdf5Writer::create_matrix(const std::string& dataset, std::size_t rows, std::size_t cols,
                               double fill_value) {
  const std::string what = dataset_label(dataset);
  require_open(what);
  const std::string name = join_path(split_path(dataset), split_path(dataset).size());
  if (split_path(dataset).empty()) fail(path_, what, "empty dataset name");
  create_groups(file_, path_, name, /*include_last=*/false);
  if (H5Lexists(file_, name.c_str(), H5P_DEFAULT) > 0) fail(path_, what, "already written");
  H5Eclear2(H5E_DEFAULT);

  const hsize_t dims[2] = {rows, cols};
  const Handle space = checked_handle(H5Screate_simple(2, dims, nullptr), H5Sclose, path_, what,
                                      "cannot create dataspace");
  const Handle dcpl = checked_handle(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, path_, what,
                                     "cannot create property list");
  no_time_stamps(dcpl.get(), path_, what);
  check(H5Pset_fill_value(dcpl.get(), H5T_NATIVE_DOUBLE, &fill_value), path_, what,
        "cannot set the fill value");
  if (rows > 0 && cols > 0) {
    // Whole rows, about 64 KiB per chunk; unwritten chunks are not stored.
    constexpr hsize_t kRowChunkBytes = 64 * 1024;
    const hsize_t chunk[2] = {
        std::min<hsize_t>(rows, std::max<hsize_t>(1, kRowChunkBytes / (sizeof(double) * cols))),
        cols};
    check(H5Pset_chunk(dcpl.get(), 2, chunk), path_, what, "cannot set chunking");
    if (H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
      check(H5Pset_shuffle(dcpl.get()), path_, what, "cannot set shuffle filter");
      check(H5Pset_deflate(dcpl.get(), kDeflateLevel), path_, what, "cannot set deflate filter");
    }
  }
  const hid_t id =
      H5Dcreate2(file_, name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, dcpl.get(),
                 H5P_DEFAULT);
  check(id, path_, what, "cannot create dataset");
  row_datasets_.emplace(name, RowDataset{id, rows, cols});
}

void Hdf5Writer::write_row(const std::string& dataset, std::size_t row, const double* values,
                           std::size_t cols) {
  const std::string what = dataset_label(dataset);
  require_open(what);
  const auto it = row_datasets_.find(join_path(split_path(dataset), split_path(dataset).size()));
  if (it == row_datasets_.end()) fail(path_, what, "not made by create_matrix()");
  const RowDataset& target = it->second;
  if (row >= target.rows || cols != target.cols)
    throw std::runtime_error(path_ + ": " + what + ": row " + std::to_string(row) + " of " +
                             std::to_string(cols) + " values for a " +
                             std::to_string(target.rows) + " x " + std::to_string(target.cols) +
                             " dataset");
  if (cols == 0) return;
  const hsize_t start[2] = {row, 0}, count[2] = {1, cols};
  const Handle file_space = checked_handle(H5Dget_space(target.id), H5Sclose, path_, what,
                                           "cannot read the dataspace");
  check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr),
        path_, what, "cannot select the row");
  const Handle memory_space = checked_handle(H5Screate_simple(2, count, nullptr), H5Sclose, path_,
                                             what, "cannot create dataspace");
  check(H5Dwrite(target.id, H5T_NATIVE_DOUBLE, memory_space.get(), file_space.get(), H5P_DEFAULT,
                 values),
        path_, what, "cannot write row " + std::to_string(row));
}

void Hdf5Writer::commit() {
  require_open("commit");
  std::string error = close_row_datasets();
  const hid_t file = std::exchange(file_, H5I_INVALID_HID);
  if (H5Fclose(file) < 0 && error.empty())
    error = error_message(path_, "file", "cannot close '" + partial_path_ + "'");
  std::error_code ignored;
  if (!error.empty()) {
    std::filesystem::remove(partial_path_, ignored);
    throw std::runtime_error(error);
  }
  std::error_code rename_error;
  std::filesystem::rename(partial_path_, path_, rename_error);
  if (rename_error) {
    std::filesystem::remove(partial_path_, ignored);
    throw std::runtime_error(path_ + ": cannot rename '" + partial_path_ +
                             "': " + rename_error.message());
  }
}

// ------------------------------------------------------------------ Hdf5Reader

bool is_hdf5_file(const std::string& path) {
  prepare_hdf5_library();
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return false;
  const bool hdf5 = H5Fis_hdf5(path.c_str()) > 0;
  H5Eclear2(H5E_DEFAULT);
  return hdf5;
}

Hdf5Reader::Hdf5Reader(const std::string& path) : path_(path) {
  prepare_hdf5_library();
  if (const std::string problem = input_path_problem(path_, "an HDF5 file"); !problem.empty())
    throw std::runtime_error(path_ + ": " + problem);
  if (const htri_t hdf5 = H5Fis_hdf5(path_.c_str()); hdf5 <= 0) {
    H5Eclear2(H5E_DEFAULT);
    if (hdf5 < 0 && locked_for_writing(path_)) throw std::runtime_error(locked_input(path_));
    throw std::runtime_error(path_ + ": not an HDF5 file");
  }
  file_ = H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file_ < 0) {
    const Hdf5ErrorDetail detail = hdf5_error_detail();
    if (detail.system_error == EWOULDBLOCK || detail.system_error == EAGAIN || locked_for_writing(path_))
      throw std::runtime_error(locked_input(path_));
    throw std::runtime_error(unopenable_input(path_, detail));
  }
}

Hdf5Reader::~Hdf5Reader() {
  if (file_ >= 0) H5Fclose(file_);
}

bool Hdf5Reader::exists(const std::string& object) const { return object_exists(file_, object); }

namespace {

// Whether `name` (which exists) is a group: an intact file of another layout
// than the reader expects, not a damaged one.
bool is_group(hid_t file, const std::string& name) {
  const hid_t group = H5Gopen2(file, name.c_str(), H5P_DEFAULT);
  if (group < 0) {
    H5Eclear2(H5E_DEFAULT);
    return false;
  }
  H5Gclose(group);
  return true;
}

Handle open_dataset(hid_t file, const std::string& file_name, const std::string& name) {
  const std::string what = dataset_label(name);
  if (!object_exists(file, name)) fail(file_name, what, "no such dataset", Access::kRead);
  if (is_group(file, name))
    fail(file_name, what, "is a group, not a dataset (a file of another layout than this one reads?)",
         Access::kRead);
  return checked_handle(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose, file_name, what,
                        "cannot open (not a dataset?)", Access::kRead);
}

// Reads a whole numeric dataset converted to `memory_type`.
template <typename T>
std::vector<T> read_numbers(hid_t file, const std::string& file_name, const std::string& name,
                            hid_t memory_type, bool allow_float) {
  const std::string what = dataset_label(name);
  const Handle dataset = open_dataset(file, file_name, name);
  const Handle type =
      checked_handle(H5Dget_type(dataset.get()), H5Tclose, file_name, what, "cannot read the type", Access::kRead);
  const H5T_class_t type_class = H5Tget_class(type.get());
  if (type_class != H5T_INTEGER && !(allow_float && type_class == H5T_FLOAT))
    fail(file_name, what,
         allow_float ? "does not hold numbers"
                     : (type_class == H5T_FLOAT ? "holds floating-point values, not integers"
                                                : "does not hold integers"), Access::kRead);
  const Handle space = checked_handle(H5Dget_space(dataset.get()), H5Sclose, file_name, what,
                                      "cannot read the dataspace", Access::kRead);
  std::vector<T> values(element_count(space.get(), file_name, what));
  if (!values.empty())
    check(H5Dread(dataset.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
          file_name, what, "cannot read", Access::kRead);
  return values;
}

Handle open_attribute(hid_t file, const std::string& file_name, const std::string& object,
                      const std::string& name) {
  const std::string what = attribute_label(object, name);
  const Handle target = open_object(file, file_name, object, what, Access::kRead);
  if (check(H5Aexists(target.get(), name.c_str()), file_name, what, "cannot look up", Access::kRead) <= 0)
    fail(file_name, what, "no such attribute", Access::kRead);
  return checked_handle(H5Aopen(target.get(), name.c_str(), H5P_DEFAULT), H5Aclose, file_name, what,
                        "cannot open", Access::kRead);
}

template <typename T>
std::vector<T> read_attribute_numbers(hid_t file, const std::string& file_name,
                                      const std::string& object, const std::string& name,
                                      hid_t memory_type) {
  const std::string what = attribute_label(object, name);
  const Handle attribute = open_attribute(file, file_name, object, name);
  const Handle type = checked_handle(H5Aget_type(attribute.get()), H5Tclose, file_name, what,
                                     "cannot read the type", Access::kRead);
  const H5T_class_t type_class = H5Tget_class(type.get());
  if (type_class != H5T_INTEGER && type_class != H5T_FLOAT) fail(file_name, what, "is not numeric", Access::kRead);
  const Handle space = checked_handle(H5Aget_space(attribute.get()), H5Sclose, file_name, what,
                                      "cannot read the dataspace", Access::kRead);
  std::vector<T> values(element_count(space.get(), file_name, what));
  if (!values.empty())
    check(H5Aread(attribute.get(), memory_type, values.data()), file_name, what, "cannot read", Access::kRead);
  return values;
}

template <typename T>
T single(const std::vector<T>& values, const std::string& file_name, const std::string& what) {
  if (values.size() != 1)
    throw std::runtime_error(file_name + ": " + what + ": expected one value, got " +
                             std::to_string(values.size()));
  return values.front();
}

}  // namespace

std::vector<std::size_t> Hdf5Reader::shape(const std::string& dataset) const {
  const std::string what = dataset_label(dataset);
  const Handle handle = open_dataset(file_, path_, dataset);
  const Handle space = checked_handle(H5Dget_space(handle.get()), H5Sclose, path_, what,
                                      "cannot read the dataspace", Access::kRead);
  const int rank = check(H5Sget_simple_extent_ndims(space.get()), path_, what, "cannot read rank", Access::kRead);
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  check(H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr), path_, what,
        "cannot read dimensions", Access::kRead);
  return {dims.begin(), dims.end()};
}

std::vector<double> Hdf5Reader::read_doubles(const std::string& dataset) const {
  return read_numbers<double>(file_, path_, dataset, H5T_NATIVE_DOUBLE, true);
}

Eigen::MatrixXd Hdf5Reader::read_matrix(const std::string& dataset) const {
  const std::vector<std::size_t> dims = shape(dataset);
  if (dims.empty() || dims.size() > 2)
    throw std::runtime_error(path_ + ": " + dataset_label(dataset) + ": expected a 1-D or 2-D " +
                             "dataset, got " + std::to_string(dims.size()) + " dimensions");
  const std::vector<double> values = read_doubles(dataset);
  const auto rows = static_cast<Eigen::Index>(dims[0]);
  const auto cols = static_cast<Eigen::Index>(dims.size() == 2 ? dims[1] : 1);
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      values.data(), rows, cols);
}

std::vector<int> Hdf5Reader::read_ints(const std::string& dataset) const {
  return read_numbers<int>(file_, path_, dataset, H5T_NATIVE_INT, false);
}

std::vector<std::string> Hdf5Reader::read_strings(const std::string& dataset) const {
  const std::string what = dataset_label(dataset);
  const Handle handle = open_dataset(file_, path_, dataset);
  const Handle type =
      checked_handle(H5Dget_type(handle.get()), H5Tclose, path_, what, "cannot read the type", Access::kRead);
  const Handle space = checked_handle(H5Dget_space(handle.get()), H5Sclose, path_, what,
                                      "cannot read the dataspace", Access::kRead);
  return read_string_data(type.get(), element_count(space.get(), path_, what), path_, what,
                          [&](hid_t memory_type, void* buffer) {
                            return H5Dread(handle.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                                           buffer);
                          });
}

bool Hdf5Reader::has_attribute(const std::string& object, const std::string& name) const {
  if (!object_exists(file_, object)) return false;
  const Handle target(H5Oopen(file_, object.c_str(), H5P_DEFAULT), H5Oclose);
  const bool found = target.get() >= 0 && H5Aexists(target.get(), name.c_str()) > 0;
  H5Eclear2(H5E_DEFAULT);
  return found;
}

double Hdf5Reader::attribute_double(const std::string& object, const std::string& name) const {
  return single(read_attribute_numbers<double>(file_, path_, object, name, H5T_NATIVE_DOUBLE),
                path_, attribute_label(object, name));
}

long long Hdf5Reader::attribute_integer(const std::string& object, const std::string& name) const {
  return single(read_attribute_numbers<long long>(file_, path_, object, name, H5T_NATIVE_LLONG),
                path_, attribute_label(object, name));
}

std::vector<double> Hdf5Reader::attribute_doubles(const std::string& object,
                                                  const std::string& name) const {
  return read_attribute_numbers<double>(file_, path_, object, name, H5T_NATIVE_DOUBLE);
}

std::string Hdf5Reader::attribute_string(const std::string& object, const std::string& name) const {
  const std::string what = attribute_label(object, name);
  const Handle attribute = open_attribute(file_, path_, object, name);
  const Handle type =
      checked_handle(H5Aget_type(attribute.get()), H5Tclose, path_, what, "cannot read the type", Access::kRead);
  const Handle space = checked_handle(H5Aget_space(attribute.get()), H5Sclose, path_, what,
                                      "cannot read the dataspace", Access::kRead);
  return single(read_string_data(type.get(), element_count(space.get(), path_, what), path_, what,
                                 [&](hid_t memory_type, void* buffer) {
                                   return H5Aread(attribute.get(), memory_type, buffer);
                                 }),
                path_, what);
}

std::vector<std::string> Hdf5Reader::list(const std::string& group) const {
  const std::string what = "group '" + group + "'";
  if (!object_exists(file_, group)) fail(path_, what, "no such group", Access::kRead);
  const Handle handle = checked_handle(H5Gopen2(file_, group.c_str(), H5P_DEFAULT), H5Gclose, path_,
                                       what, "cannot open (not a group?)", Access::kRead);
  H5G_info_t info{};
  check(H5Gget_info(handle.get(), &info), path_, what, "cannot read group info", Access::kRead);
  std::vector<std::string> names;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t length = check(H5Lget_name_by_idx(handle.get(), ".", H5_INDEX_NAME, H5_ITER_INC,
                                                    i, nullptr, 0, H5P_DEFAULT),
                                 path_, what, "cannot read member names", Access::kRead);
    std::string name(static_cast<std::size_t>(length) + 1, '\0');
    check(H5Lget_name_by_idx(handle.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(),
                             name.size(), H5P_DEFAULT),
          path_, what, "cannot read member names", Access::kRead);
    name.resize(static_cast<std::size_t>(length));
    names.push_back(std::move(name));
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace rover::io
