// See checkpoint.hpp.
#include "io/checkpoint.hpp"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "io/hdf5_file.hpp"

namespace rover::io {
namespace {

constexpr const char* kFormat = "rover-checkpoint-1";

}  // namespace

ResultCheckpoint::ResultCheckpoint(const std::string& results_path, std::string fingerprint,
                                   CheckpointPolicy policy)
    : path_(path_for(results_path)),
      fingerprint_(std::move(fingerprint)),
      policy_(policy),
      last_save_(std::chrono::steady_clock::now()) {}

std::vector<TaskRecord> ResultCheckpoint::load() {
  std::error_code error;
  if (!std::filesystem::exists(path_, error)) return {};
  const Hdf5Reader file(path_);
  if (!file.has_attribute("/", "format") || file.attribute_string("/", "format") != kFormat)
    throw std::runtime_error(path_ + ": not a rover checkpoint (no attribute format = '" +
                             std::string(kFormat) + "')");
  const std::string fingerprint = file.attribute_string("/", "fingerprint");
  if (fingerprint != fingerprint_)
    throw std::runtime_error(path_ + ": checkpoint of a different study configuration " +
                             "(fingerprint " + fingerprint + ", this study " + fingerprint_ +
                             "); delete it or run without --resume");

  const std::vector<int> index = file.read_ints("/index");
  const std::vector<int> status = file.read_ints("/status");
  const std::vector<int> length = file.read_ints("/length");
  const std::vector<std::string> message = file.read_strings("/message");
  const std::vector<double> values = file.read_doubles("/values");
  const std::size_t n = index.size();
  if (status.size() != n || length.size() != n || message.size() != n)
    throw std::runtime_error(path_ + ": damaged checkpoint: index, status, length and message " +
                             "have different sizes");
  std::size_t offset = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (length[i] < 0 || offset + static_cast<std::size_t>(length[i]) > values.size())
      throw std::runtime_error(path_ + ": damaged checkpoint: record lengths exceed /values");
    const auto begin = values.begin() + static_cast<std::ptrdiff_t>(offset);
    offset += static_cast<std::size_t>(length[i]);
    records_[index[i]] = TaskRecord{index[i],
                                    status[i],
                                    message[i],
                                    {begin, values.begin() + static_cast<std::ptrdiff_t>(offset)}};
  }
  if (offset != values.size())
    throw std::runtime_error(path_ + ": damaged checkpoint: /values longer than the records");

  unsaved_ = 0;
  std::vector<TaskRecord> out;
  out.reserve(records_.size());
  for (const auto& [i, record] : records_) out.push_back(record);
  return out;
}

void ResultCheckpoint::add(const TaskRecord& record) {
  records_[record.index] = record;
  ++unsaved_;
  const std::chrono::duration<double> since = std::chrono::steady_clock::now() - last_save_;
  if (unsaved_ >= policy_.every_records || since.count() >= policy_.every_seconds) save();
}

void ResultCheckpoint::save() {
  if (unsaved_ == 0) return;
  std::vector<int> index, status, length;
  std::vector<std::string> message;
  std::vector<double> values;
  for (const auto& [i, record] : records_) {
    if (record.values.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
      throw std::runtime_error(path_ + ": task " + std::to_string(i) + ": record too long");
    index.push_back(i);
    status.push_back(record.status);
    length.push_back(static_cast<int>(record.values.size()));
    message.push_back(record.message);
    values.insert(values.end(), record.values.begin(), record.values.end());
  }
  Hdf5Writer file(path_);
  file.write("/index", index);
  file.write("/status", status);
  file.write("/length", length);
  file.write("/message", message);
  file.write("/values", values);
  file.attribute("/", "format", std::string(kFormat));
  file.attribute("/", "fingerprint", fingerprint_);
  file.commit();
  unsaved_ = 0;
  last_save_ = std::chrono::steady_clock::now();
}

void ResultCheckpoint::remove() {
  std::error_code error;
  std::filesystem::remove(path_, error);
  if (error) throw std::runtime_error(path_ + ": cannot delete the checkpoint: " + error.message());
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

}  // namespace rover::io
