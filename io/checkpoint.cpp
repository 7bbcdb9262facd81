// See checkpoint.hpp.
#include "io/checkpoint.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>
#include <system_error>
#include <utility>
#include <vector>

#include <boost/crc.hpp>

#include "io/output_target.hpp"

namespace rover::io {
namespace {

constexpr char kMagic[8] = {'R', 'O', 'V', 'E', 'R', 'C', 'K', 'P'};
constexpr std::uint32_t kVersion = 2;
constexpr char kHdf5Signature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
constexpr std::size_t kRecordFixedBytes = 16;  // index, status, M, V

void put_u32(std::string& out, std::uint32_t v) {
  for (int shift = 0; shift < 32; shift += 8) out.push_back(static_cast<char>((v >> shift) & 0xff));
}
void put_u64(std::string& out, std::uint64_t v) {
  for (int shift = 0; shift < 64; shift += 8) out.push_back(static_cast<char>((v >> shift) & 0xff));
}
std::uint32_t get_u32(const char* in) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(in[i]);
  return v;
}
std::uint64_t get_u64(const char* in) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(in[i]);
  return v;
}

std::uint32_t crc32(const char* data, std::size_t size) {
  boost::crc_32_type crc;
  crc.process_bytes(data, size);
  return crc.checksum();
}

std::string encode_header(const std::string& fingerprint) {
  std::string out(kMagic, sizeof kMagic);
  put_u32(out, kVersion);
  put_u32(out, static_cast<std::uint32_t>(fingerprint.size()));
  out += fingerprint;
  put_u32(out, crc32(out.data(), out.size()));
  return out;
}

// Appends the encoded record to `out`.
void encode_record(const TaskRecord& record, const std::string& path, std::string& out) {
  const std::size_t payload =
      kRecordFixedBytes + record.message.size() + sizeof(double) * record.values.size();
  if (payload > std::numeric_limits<std::uint32_t>::max())
    throw std::runtime_error(path + ": task " + std::to_string(record.index) +
                             ": record too long for a checkpoint");
  const std::size_t start = out.size();
  put_u32(out, static_cast<std::uint32_t>(payload));
  put_u32(out, static_cast<std::uint32_t>(record.index));
  put_u32(out, static_cast<std::uint32_t>(record.status));
  put_u32(out, static_cast<std::uint32_t>(record.message.size()));
  out += record.message;
  put_u32(out, static_cast<std::uint32_t>(record.values.size()));
  for (const double v : record.values) put_u64(out, std::bit_cast<std::uint64_t>(v));
  put_u32(out, crc32(out.data() + start, out.size() - start));
}

// Decodes a record whose length field and payload are in `bytes` (the CRC
// already checked); false if its fields do not add up to the payload length.
bool decode_record(const std::string& bytes, TaskRecord& record) {
  const char* p = bytes.data() + 4;
  const std::size_t payload = bytes.size() - 4;
  record.index = static_cast<int>(get_u32(p));
  record.status = static_cast<int>(get_u32(p + 4));
  const std::size_t message = get_u32(p + 8);
  if (record.index < 0 || kRecordFixedBytes + message > payload) return false;
  record.message.assign(p + 12, message);
  const std::size_t count = get_u32(p + 12 + message);
  if (kRecordFixedBytes + message + sizeof(double) * count != payload) return false;
  record.values.resize(count);
  for (std::size_t i = 0; i < count; ++i)
    record.values[i] = std::bit_cast<double>(get_u64(p + 16 + message + 8 * i));
  return true;
}

[[noreturn]] void fail_io(const std::string& path, const std::string& what, int error) {
  std::string message = path + ": " + what + ": " + std::strerror(error);
  if (error == ENOSPC || error == EFBIG || error == EDQUOT)
    message += " (the disk is full or the file size limit is reached; the records already "
               "written are kept)";
  throw std::runtime_error(message);
}

// Writes all of `data` at `offset` of the open file `fd`.
void write_all(int fd, const std::string& data, std::uint64_t offset, const std::string& path) {
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::pwrite(fd, data.data() + done, data.size() - done,
                               static_cast<off_t>(offset + done));
    if (n < 0) {
      if (errno == EINTR) continue;
      fail_io(path, "cannot write the checkpoint", errno);
    }
    done += static_cast<std::size_t>(n);
  }
}

// Owns a POSIX file descriptor.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }
  // Closes now and reports the error of close(2) (NFS reports write errors there).
  int close() { return ::close(std::exchange(fd_, -1)) == 0 ? 0 : errno; }

 private:
  int fd_;
};

}  // namespace

bool ResultCheckpoint::is_checkpoint_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[sizeof kMagic] = {};
  in.read(magic, sizeof magic);
  return in.gcount() == sizeof magic && std::equal(magic, magic + sizeof magic, kMagic);
}

bool ResultCheckpoint::is_foreign_file(const std::string& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::symlink_status(path, error);
  return std::filesystem::is_regular_file(status) && std::filesystem::hard_link_count(path, error) == 1 &&
         !is_checkpoint_file(path);
}

ResultCheckpoint::ResultCheckpoint(const std::string& results_path, std::string fingerprint,
                                   CheckpointPolicy policy)
    : path_(path_for(results_path)),
      fingerprint_(std::move(fingerprint)),
      policy_(policy),
      last_save_(std::chrono::steady_clock::now()) {}

bool ResultCheckpoint::contains(int index) const {
  return index >= 0 && static_cast<std::size_t>(index) < done_.size() &&
         done_[static_cast<std::size_t>(index)];
}

void ResultCheckpoint::mark_done(int index) {
  const auto i = static_cast<std::size_t>(index);
  if (i >= done_.size()) done_.resize(std::max(i + 1, 2 * done_.size()), false);
  if (!done_[i]) {
    done_[i] = true;
    ++size_;
  }
}

std::vector<TaskRecord> ResultCheckpoint::load() {
  save();
  std::ifstream in(path_, std::ios::binary);
  if (!in) {
    std::error_code error;
    if (std::filesystem::exists(path_, error))
      throw std::runtime_error(path_ + ": cannot open the checkpoint");
    return {};
  }
  const auto refuse = [&](const std::string& why) {
    throw std::runtime_error(path_ + ": " + why +
                             "; it is kept: continue it with the configuration that made it, or discard it with "
                             "--restart instead of --resume");
  };
  // A file that does not begin as a checkpoint is never offered for removal.
  const auto refuse_foreign = [&](const std::string& why) {
    throw std::runtime_error(path_ + ": " + why + "; rover never removes such a file: give another --out");
  };

  char magic[sizeof kMagic] = {};
  in.read(magic, sizeof magic);
  if (in.gcount() == sizeof magic && std::equal(magic, magic + 8, kHdf5Signature))
    refuse_foreign("an HDF5 file (a checkpoint of an earlier version of this program, which cannot be resumed, "
                   "or another file)");
  if (in.gcount() != sizeof magic || !std::equal(magic, magic + 8, kMagic))
    refuse_foreign("not a rover checkpoint (it does not start with \"ROVERCKP\")");
  char fixed[8];
  if (!in.read(fixed, sizeof fixed)) refuse("damaged checkpoint header");
  const std::uint32_t version = get_u32(fixed);
  if (version != kVersion)
    refuse("checkpoint format version " + std::to_string(version) + ", this program reads " +
           std::to_string(kVersion));
  const std::uint32_t fingerprint_length = get_u32(fixed + 4);
  if (fingerprint_length > 4096) refuse("damaged checkpoint header");
  std::string fingerprint(fingerprint_length, '\0');
  char crc[4];
  if (!in.read(fingerprint.data(), fingerprint_length) || !in.read(crc, sizeof crc))
    refuse("damaged checkpoint header");
  if (encode_header(fingerprint) !=
      std::string(magic, 8) + std::string(fixed, 8) + fingerprint + std::string(crc, 4))
    refuse("damaged checkpoint header (checksum mismatch)");
  if (!keys_match(fingerprint, fingerprint_))
    refuse("checkpoint of a different study configuration: " + key_mismatch(fingerprint, fingerprint_));

  // Records up to the first one that is incomplete or fails its checksum:
  // appends only ever add at the end, so that one is a torn tail.
  std::uint64_t offset = 16 + fingerprint_length + 4;
  std::error_code error;
  const std::uint64_t file_size = std::filesystem::file_size(path_, error);
  if (error) throw std::runtime_error(path_ + ": cannot read the size: " + error.message());
  std::map<int, TaskRecord> records;
  std::string bytes;
  while (offset < file_size) {
    if (file_size - offset < 8) break;
    bytes.resize(4);
    if (!in.read(bytes.data(), 4)) break;
    const std::uint32_t payload = get_u32(bytes.data());
    if (payload < kRecordFixedBytes || payload > file_size - offset - 8) break;
    bytes.resize(4 + static_cast<std::size_t>(payload));
    if (!in.read(bytes.data() + 4, payload) || !in.read(crc, sizeof crc)) break;
    if (get_u32(crc) != crc32(bytes.data(), bytes.size())) break;
    TaskRecord record;
    if (!decode_record(bytes, record)) break;
    records[record.index] = std::move(record);
    offset += 8 + payload;
  }
  torn_tail_bytes_ = file_size - offset;
  appending_ = true;
  append_offset_ = offset;

  std::vector<TaskRecord> out;
  out.reserve(records.size());
  for (auto& [index, record] : records) {
    mark_done(index);
    out.push_back(std::move(record));
  }
  return out;
}

void ResultCheckpoint::add(const TaskRecord& record) {
  if (record.index < 0)
    throw std::invalid_argument(path_ + ": task index " + std::to_string(record.index) +
                                " is negative");
  encode_record(record, path_, unsaved_bytes_);
  ++unsaved_records_;
  mark_done(record.index);
  const std::chrono::duration<double> since = std::chrono::steady_clock::now() - last_save_;
  if (unsaved_records_ >= policy_.every_records || since.count() >= policy_.every_seconds)
    save();
}

void ResultCheckpoint::create_file() {
  require_output(path_, OutputFormat::kSeekable);  // never renamed over a link or a read-only file
  const std::string partial = path_ + ".partial";
  const std::string header = encode_header(fingerprint_);
  create_temporary(partial, path_);
  {
    Descriptor fd(::open(partial.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
    if (fd.get() < 0) fail_io(partial, "cannot create the checkpoint", errno);
    write_all(fd.get(), header, 0, partial);
    if (const int error = fd.close()) fail_io(partial, "cannot write the checkpoint", error);
  }
  std::error_code error;
  std::filesystem::rename(partial, path_, error);
  if (error) throw std::runtime_error(path_ + ": cannot rename '" + partial + "': " + error.message());
  bytes_written_ += header.size();
  appending_ = true;
  append_offset_ = header.size();
}

void ResultCheckpoint::save() {
  if (unsaved_records_ == 0) return;
  if (!appending_) create_file();
  Descriptor fd(::open(path_.c_str(), O_WRONLY | O_CLOEXEC));
  if (fd.get() < 0) fail_io(path_, "cannot open the checkpoint to append", errno);
  struct stat status {};
  if (::fstat(fd.get(), &status) != 0) fail_io(path_, "cannot read the size", errno);
  // A torn tail (a crash or a failed write since) is cut before appending.
  if (static_cast<std::uint64_t>(status.st_size) != append_offset_ &&
      ::ftruncate(fd.get(), static_cast<off_t>(append_offset_)) != 0)
    fail_io(path_, "cannot truncate the torn tail of the checkpoint", errno);
  write_all(fd.get(), unsaved_bytes_, append_offset_, path_);
  if (const int error = fd.close()) fail_io(path_, "cannot write the checkpoint", error);
  append_offset_ += unsaved_bytes_.size();
  bytes_written_ += unsaved_bytes_.size();
  unsaved_bytes_.clear();
  unsaved_records_ = 0;
  last_save_ = std::chrono::steady_clock::now();
}

void ResultCheckpoint::remove() {
  if (is_foreign_file(path_))
    throw std::runtime_error(path_ + ": not a rover checkpoint (it does not start with \"ROVERCKP\"); rover never "
                             "removes such a file: give another --out");
  std::error_code error;
  std::filesystem::remove(path_, error);
  if (error) throw std::runtime_error(path_ + ": cannot delete the checkpoint: " + error.message());
  done_.clear();
  size_ = 0;
  unsaved_bytes_.clear();
  unsaved_records_ = 0;
  appending_ = false;
  append_offset_ = 0;
}

std::vector<int> missing_indices(int task_count, const std::vector<TaskRecord>& completed) {
  std::vector<bool> done(static_cast<std::size_t>(std::max(task_count, 0)), false);
  for (const TaskRecord& record : completed)
    if (record.index >= 0 && record.index < task_count)
      done[static_cast<std::size_t>(record.index)] = true;
  std::vector<int> missing;
  for (int i = 0; i < task_count; ++i)
    if (!done[static_cast<std::size_t>(i)]) missing.push_back(i);
  return missing;
}

std::string config_fingerprint(std::string_view text) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;  // FNV-1a 64 offset basis
  for (const char c : text) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ULL;  // FNV prime
  }
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out(16, '0');
  for (int i = 15; i >= 0; --i, hash >>= 4) out[static_cast<std::size_t>(i)] = kHex[hash & 0xf];
  return out;
}

namespace {

constexpr char kSettingSeparator = '\t';
// The source of a setting in a key: the flag, the study file, or another input file named.
constexpr const char* kFlagSource = "flag";
constexpr const char* kFileSource = "file";

// A key's digest and its settings (flag -> setting).
struct ParsedKey {
  std::string digest;
  std::vector<RunSetting> settings;
  const RunSetting* find(const std::string& flag) const {
    for (const RunSetting& s : settings)
      if (s.flag == flag) return &s;
    return nullptr;
  }
};

ParsedKey parse_key(const std::string& key) {
  ParsedKey parsed;
  std::size_t end = key.find('\n');
  parsed.digest = key.substr(0, end);
  while (end != std::string::npos) {
    const std::size_t start = end + 1;
    end = key.find('\n', start);
    const std::string line = key.substr(start, end == std::string::npos ? std::string::npos : end - start);
    const std::size_t a = line.find(kSettingSeparator), b = line.rfind(kSettingSeparator);
    if (a == std::string::npos || b == a) continue;
    const std::string source = line.substr(b + 1);
    RunSetting setting{line.substr(0, a), line.substr(a + 1, b - a - 1), source == kFlagSource};
    if (!setting.from_flag && source != kFileSource) setting.origin = source;
    parsed.settings.push_back(setting);
  }
  return parsed;
}

// "--samples 300"; "samples 16 (from the study file, no --samples)"; "the
// scenario's integrator (no --integrator)"; a setting no flag gives: "study
// montecarlo 'mc'".
std::string describe_setting(const RunSetting& s) {
  if (s.from_flag || !s.flag.starts_with("--")) return s.flag + " " + s.value;
  if (s.origin == RunSetting{}.origin)
    return s.flag.substr(2) + " " + s.value + " (from " + s.origin + ", no " + s.flag + ")";
  return s.origin + "'s " + s.value + " (no " + s.flag + ")";
}

}  // namespace

std::string add_run_setting(const std::string& key, const RunSetting& setting) {
  const bool study_file = setting.origin == RunSetting{}.origin;
  return key + "\n" + setting.flag + kSettingSeparator + setting.value + kSettingSeparator +
         (setting.from_flag ? kFlagSource : study_file ? kFileSource : setting.origin);
}

std::string extend_key_digest(const std::string& key, const std::string& text) {
  const std::size_t end = key.find('\n');
  const std::string settings = end == std::string::npos ? std::string() : key.substr(end);
  return config_fingerprint(key.substr(0, end) + "\n" + text) + settings;
}

std::string key_summary(const std::string& key) {
  return key.find('\n') == std::string::npos ? key : config_fingerprint(key);
}

bool keys_match(const std::string& stored, const std::string& current) {
  const ParsedKey a = parse_key(stored), b = parse_key(current);
  if (a.digest != b.digest || a.settings.size() != b.settings.size()) return false;
  for (const RunSetting& s : b.settings) {
    const RunSetting* t = a.find(s.flag);
    if (t == nullptr || t->value != s.value) return false;
  }
  return true;
}

std::string key_mismatch(const std::string& stored, const std::string& current) {
  const ParsedKey then = parse_key(stored), now = parse_key(current);
  if (then.settings.empty() && !now.settings.empty() && then.digest != now.digest)
    return "it was written by an earlier version of rover (which recorded no settings of its runs) or for other "
           "input files";
  std::string differences;
  for (const RunSetting& s : now.settings) {
    const RunSetting* t = then.find(s.flag);
    if (t == nullptr || t->value == s.value) continue;
    if (!differences.empty()) differences += "; ";
    differences += describe_setting(s) + " here, but the checkpoint's runs were made with " + describe_setting(*t);
  }
  if (then.digest != now.digest) {
    if (!differences.empty()) differences += "; and ";
    differences += "the study file or a file it names (scenario, rover, terrain, data, design, reference) differs "
                   "from the one its runs were made with, in some byte (a description or a space counts)";
  }
  return differences.empty() ? "its runs were made with other settings" : differences;
}

}  // namespace rover::io
