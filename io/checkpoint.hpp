// Checkpoints of a running study, so that `--resume` recomputes only the
// tasks that are missing.
//
// ResultCheckpoint appends the record of each completed task (task index,
// status, message, values) to "<results>.checkpoint" and never rewrites old
// records: the cost of a write is the size of the new records, whatever the
// number already saved. Records are buffered and written every K records or
// T seconds (CheckpointPolicy) and by save(). The object keeps only the set of
// task indices done and the records not yet written, not the records
// themselves; load() reads them back once, for a resume.
//
// Crashes: the file is created with its header through "<file>.partial" and a
// rename, so it always starts with a complete header. A crash in the middle
// of an append leaves a torn last record, which load() recognises by its
// length or checksum and drops (torn_tail_bytes()); the next append truncates
// it away and continues after the last good record. Appends are write(2)
// calls without fsync: what was written survives a crash of the process; a
// power failure can lose the last records, which again shows as a torn tail.
//
// Why a plain binary file and not HDF5 with extendable datasets: an HDF5 file
// modified in place is not crash-safe (HDF5 1.10 without SWMR can leave its
// metadata unreadable after a crash during a write), so the whole checkpoint
// would be at risk at every append; a sequence of self-delimiting, checksummed
// records loses at most the record being written, and appending is one write.
//
// File format (all integers little-endian, doubles IEEE-754 binary64 stored
// as their little-endian bit patterns; CRC-32 is the zlib/PNG polynomial,
// boost::crc_32_type):
//   header:  8 bytes  "ROVERCKP"
//            u32      format version (2)
//            u32      L, the fingerprint's length in bytes
//            L bytes  fingerprint: the key of the study's runs (run_key text:
//                     the digest of its inputs, then its RunSetting lines)
//            u32      CRC-32 of all the header bytes before it
//   record:  u32      P, the payload's length in bytes (16 + M + 8 V)
//            payload: i32 task index (>= 0), i32 status,
//                     u32 M, M bytes message (UTF-8),
//                     u32 V, V doubles (the values)
//            u32      CRC-32 of the P field and the payload
// A task may appear more than once (add() of an index already recorded): the
// last record counts.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/task_record.hpp"

namespace rover::io {

struct CheckpointPolicy {
  std::size_t every_records = 100;  // write after this many new records ...
  double every_seconds = 60.0;      // ... or when this long has passed since the last write
};

// Not synchronised: use one object from one thread.
class ResultCheckpoint {
 public:
  // `results_path` is the study's final result file; the checkpoint lives
  // beside it. `fingerprint` identifies the study configuration
  // (see config_fingerprint()).
  ResultCheckpoint(const std::string& results_path, std::string fingerprint,
                   CheckpointPolicy policy = {});

  static std::string path_for(const std::string& results_path) {
    return results_path + ".checkpoint";
  }
  const std::string& path() const { return path_; }
  // Whether the file at `path` begins as a checkpoint (its 8-byte signature).
  static bool is_checkpoint_file(const std::string& path);
  // Whether `path` is a regular file of one name that does not begin as a
  // checkpoint: someone's data, which remove() and --restart never delete.
  static bool is_foreign_file(const std::string& path);

  // Reads the checkpoint file if there is one: returns its records sorted by
  // index (the last record of an index counts), none if there is no file,
  // and makes later writes append to it (after the last good record). A torn
  // last record is dropped (see torn_tail_bytes()). Records added before and
  // not yet written are written first. Throws std::runtime_error, naming the
  // file, if it was written for another fingerprint, is of another format or
  // version, or has a damaged header. Without load(), the first write starts
  // a new file (replacing an old one).
  std::vector<TaskRecord> load();

  // Adds the record of one task (index >= 0, else std::invalid_argument); a
  // record of an index already done replaces it. Writes when the policy says
  // so; a failed write (e.g. a full disk) throws std::runtime_error naming the
  // file and keeps the unwritten records for the next attempt.
  void add(const TaskRecord& record);
  // Writes the records added since the last write, if any.
  void save();
  // Deletes the checkpoint file (call once the final results are committed)
  // and forgets everything: indices done and records not yet written.
  void remove();

  // Number of distinct task indices recorded (loaded or added).
  std::size_t size() const { return size_; }
  // True if task `index` has a record.
  bool contains(int index) const;
  // Bytes this object has written to files (headers and records), and the
  // bytes of a torn tail that the last load() dropped.
  std::uint64_t bytes_written() const { return bytes_written_; }
  std::uint64_t torn_tail_bytes() const { return torn_tail_bytes_; }

 private:
  void mark_done(int index);
  void create_file();

  std::string path_, fingerprint_;
  CheckpointPolicy policy_;
  std::vector<bool> done_;          // by task index
  std::size_t size_ = 0;            // count of true entries in done_
  std::string unsaved_bytes_;       // encoded records not yet written
  std::size_t unsaved_records_ = 0;
  bool appending_ = false;          // the file exists and ends (logically) at append_offset_
  std::uint64_t append_offset_ = 0;
  std::uint64_t bytes_written_ = 0, torn_tail_bytes_ = 0;
  std::chrono::steady_clock::time_point last_save_;
};

// Indices in [0, task_count) that have no record in `completed`, ascending.
std::vector<int> missing_indices(int task_count, const std::vector<TaskRecord>& completed);

// A short, stable hash (16 hex digits, FNV-1a 64) of a study configuration's
// canonical text, e.g. a JSON dump.
std::string config_fingerprint(std::string_view text);

// A setting in force that changes a study's runs (a sample count, a seed, an
// integrator): the flag that overrides it, its value, and whether that flag
// gave it (else the input file `origin` did). A checkpoint records the
// settings of its runs, so that a --resume under other values names the flag
// that differs.
struct RunSetting {
  std::string flag;   // "--samples"
  std::string value;  // "300"
  bool from_flag = false;
  std::string origin = "the study file";  // "the scenario": where a value not from the flag came from
};

// The key of a study's runs, which a checkpoint is written under: the digest
// of its inputs' text (config_fingerprint), then one line per setting. Keys
// match when their digests and their settings' values do (where a value came
// from does not count).
std::string add_run_setting(const std::string& key, const RunSetting& setting);
// The key with its digest replaced by the digest of (digest, text): for
// inputs added to the key; the settings stay.
std::string extend_key_digest(const std::string& key, const std::string& text);
// One 16-hex-digit hash of the whole key, for the provenance of a result.
std::string key_summary(const std::string& key);
// Whether runs made under the key `stored` are runs of the key `current`.
bool keys_match(const std::string& stored, const std::string& current);
// Why they are not: the settings that differ ("--samples 320 here, but the
// checkpoint's runs were made with --samples 300"), else the input files.
std::string key_mismatch(const std::string& stored, const std::string& current);

}  // namespace rover::io
