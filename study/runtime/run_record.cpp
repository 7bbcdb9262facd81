// See run_record.hpp.
#include "study/runtime/run_record.hpp"

#include <cmath>

#include "core/integrators.hpp"

namespace rover::study {

const char* run_status_name(int status) {
  switch (status) {
    case run_status::kOk: return "ok";
    case run_status::kRejectedInput: return "rejected input";
    case run_status::kError: return "error";
    default: return "integration failed";
  }
}

RunRecord failed_record(const RecordLayout& layout, int status, std::string message) {
  RunRecord r;
  r.status = status;
  r.message = std::move(message);
  r.qoi.assign(static_cast<std::size_t>(layout.qoi_count), std::nan(""));
  r.curves.assign(static_cast<std::size_t>(layout.channel_count) *
                      static_cast<std::size_t>(layout.time_samples),
                  std::nan(""));
  return r;
}

io::TaskRecord encode_record(int index, const RunRecord& record) {
  io::TaskRecord task{index, record.status, record.message, {}};
  task.values.reserve(2 + record.qoi.size() + record.curves.size());
  task.values.push_back(record.wall_time_s);
  task.values.push_back(record.rhs_evaluations);
  task.values.insert(task.values.end(), record.qoi.begin(), record.qoi.end());
  task.values.insert(task.values.end(), record.curves.begin(), record.curves.end());
  return task;
}

RunRecord decode_record(const RecordLayout& layout, io::TaskRecord task) {
  if (task.values.size() != layout.value_count()) {
    // A task that threw inside the farm carries no values: keep its status and message.
    if (task.values.empty() && task.status != run_status::kOk)
      return failed_record(layout, task.status, std::move(task.message));
    return failed_record(layout, run_status::kError,
                         "record holds " + std::to_string(task.values.size()) + " values, expected " +
                             std::to_string(layout.value_count()));
  }
  RunRecord r;
  r.status = task.status;
  r.message = std::move(task.message);
  r.wall_time_s = task.values[0];
  r.rhs_evaluations = task.values[1];
  const auto q0 = task.values.begin() + 2;
  const auto c0 = q0 + layout.qoi_count;
  r.qoi.assign(q0, c0);
  r.curves.assign(c0, task.values.end());
  return r;
}

}  // namespace rover::study
