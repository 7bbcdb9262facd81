// Checkpoints of a running study, so that `--resume` recomputes only the
// tasks that are missing.
//
// ResultCheckpoint keeps the records of completed tasks (task index -> status,
// message, values) and rewrites them all to "<results>.checkpoint" (an HDF5 file,
// written through Hdf5Writer: temp file + rename, so a crash leaves either the
// previous checkpoint or the new one) every K records or T seconds. The file
// carries a fingerprint of the study configuration; load() refuses a checkpoint
// written for another configuration.
//
// File layout (readable with h5py): /index, /status, /length (ints), /message
// (strings), /values (the records' values concatenated, record i having
// length[i] values); root attributes "fingerprint" and "format".
#pragma once

#include <chrono>
#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace rover::io {

// The outcome of one task of a study. status 0 = ok; nonzero = the run failed
// (message says why); a failed run is a result too and is not retried.
struct TaskRecord {
  int index = 0;
  int status = 0;
  std::string message;
  std::vector<double> values;
};

struct CheckpointPolicy {
  std::size_t every_records = 100;  // write after this many new records ...
  double every_seconds = 60.0;      // ... or when this long has passed since the last write
};

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

  // Reads the checkpoint file if there is one and keeps its records (later
  // writes include them). Returns them sorted by index; none if no file.
  // Throws std::runtime_error if the file was written with another fingerprint
  // or is damaged.
  std::vector<TaskRecord> load();

  // Adds (or replaces) the record of one task; writes the file when the policy
  // says so.
  void add(const TaskRecord& record);
  // Writes all records now (if any were added since the last write).
  void save();
  // Deletes the checkpoint file (call once the final results are committed).
  void remove();

  std::size_t size() const { return records_.size(); }

 private:
  std::string path_, fingerprint_;
  CheckpointPolicy policy_;
  std::map<int, TaskRecord> records_;
  std::size_t unsaved_ = 0;
  std::chrono::steady_clock::time_point last_save_;
};

// Indices in [0, task_count) that have no record in `completed`, ascending.
std::vector<int> missing_indices(int task_count, const std::vector<TaskRecord>& completed);

// A short, stable hash (16 hex digits, FNV-1a 64) of a study configuration's
// canonical text, e.g. a JSON dump.
std::string config_fingerprint(std::string_view text);

}  // namespace rover::io
