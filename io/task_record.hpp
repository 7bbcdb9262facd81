// The outcome of one task of a study, as it travels between MPI ranks
// (study/runtime/task_farm) and into checkpoints (io/checkpoint): a plain record with
// no dependency, so the task farm does not need the checkpoint's header.
#pragma once

#include <string>
#include <vector>

namespace rover::io {

// status 0 = ok; nonzero = the run failed (message says why); a failed run is
// a result too and is not retried. `values` is the study's payload
// (study/runtime/run_record.hpp encodes and decodes it).
struct TaskRecord {
  int index = 0;
  int status = 0;
  std::string message;
  std::vector<double> values;
};

}  // namespace rover::io
