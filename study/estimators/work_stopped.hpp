// A request to stop long work early (docs/reliability.md, interrupts): a
// signal raises a flag (study::InterruptGuard::flag()) that the long loops
// read: a bootstrap at every resample, a simulation at every step. Work so
// stopped throws WorkStopped: it is neither a result nor a failure, and is
// done again from the start (a study's --resume recomputes it).
#pragma once

#include <atomic>
#include <stdexcept>
#include <string>

namespace rover::study {

class WorkStopped : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws WorkStopped ("<what>: stopped on request") once `stop` (if given) is set.
inline void stop_if_requested(const std::atomic<bool>* stop, const char* what) {
  if (stop != nullptr && stop->load(std::memory_order_relaxed))
    throw WorkStopped(std::string(what) + ": stopped on request");
}

}  // namespace rover::study
