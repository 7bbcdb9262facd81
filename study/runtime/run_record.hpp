// The record of one run of a study: its status, the quantities of interest and
// the output curves. Records travel between MPI ranks and into checkpoints as
// io::TaskRecord (a flat vector of doubles); encode_record() and decode_record()
// are the only places that know that layout.
#pragma once

#include <string>
#include <vector>

#include "io/task_record.hpp"

namespace rover::study {

// Status of a run: 0 ok; 1 .. 9 the integrator's (SimulationStatus); and the
// study's own. A failed or rejected run is a result too: it is recorded, not
// retried, and never used as if it had values.
namespace run_status {
inline constexpr int kOk = 0;
inline constexpr int kRejectedInput = 10;  // a sample outside a parameter's valid range
inline constexpr int kError = 11;          // an exception while setting up or evaluating
}  // namespace run_status
const char* run_status_name(int status);

struct RecordLayout {
  int qoi_count = 0;
  int channel_count = 0;
  int time_samples = 0;
  std::size_t value_count() const {
    return 2 + static_cast<std::size_t>(qoi_count) +
           static_cast<std::size_t>(channel_count) * static_cast<std::size_t>(time_samples);
  }
};

struct RunRecord {
  int status = run_status::kOk;
  std::string message;  // why it failed; of a run that did not, a note the study reports (or empty)
  double wall_time_s = 0.0;      // of the simulation itself (the paper's t_c), set-up excluded
  double rhs_evaluations = 0.0;
  std::vector<double> qoi;     // qoi_count values (NaN unless ok)
  std::vector<double> curves;  // channel_count x time_samples, row-major (NaN unless ok)
  bool ok() const { return status == run_status::kOk; }
  const double* curve(int channel, int time_samples) const {
    return curves.data() + static_cast<std::size_t>(channel) * static_cast<std::size_t>(time_samples);
  }
};

// A record with every value NaN and the given status.
RunRecord failed_record(const RecordLayout& layout, int status, std::string message);

io::TaskRecord encode_record(int index, const RunRecord& record);
// A record of another length (a checkpoint written for another layout) becomes
// a kError record saying so.
RunRecord decode_record(const RecordLayout& layout, io::TaskRecord task);

}  // namespace rover::study
