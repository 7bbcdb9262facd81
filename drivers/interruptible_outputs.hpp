// The files a one-process command (simulate, synthesize, terrain, friction,
// surrogate --predict) writes, under a study::InterruptGuard: a signal
// (Ctrl-C, SIGTERM, SIGHUP, a closed output pipe) while they are written stops
// the command between files, or inside a file at the writer's next check
// (io::write_csv's and write_trajectory_hdf5's `stop`). The file then being
// written is not written (its temporary is removed and an earlier file at its
// path is left as it was), no lock stays, and the command ends with status 130
// and a message that names the files written and those not written
// (docs/reliability.md, "Interrupts").
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "study/runtime/study_runner.hpp"

namespace rover::cli {

class InterruptibleOutputs {
 public:
  // `planned`: every file the command is to write, in order (empty paths are
  // skipped). Installs the guard: construct it before the work and the locks
  // (drivers/held_outputs.hpp), so that it outlives them.
  explicit InterruptibleOutputs(const std::vector<std::string>& planned);

  // The flag the writers read.
  const std::atomic<bool>* stop() const { return &study::InterruptGuard::flag(); }
  bool signalled() const { return study::InterruptGuard::flag().load(); }

  // `path` is written in full; then stop_if_signalled().
  void written(const std::string& path);
  // `path` will not be written (a plot that failed): it is left out of the
  // message.
  void dropped(const std::string& path);
  // Throws study::StudyInterrupted if a signal came: "interrupted (SIGTERM);
  // wrote a.h5; not written: a.csv, a.png (an earlier file at such a path is
  // left as it was)", or "... nothing written".
  void stop_if_signalled() const;
  // For work that gave up after a signal: "writing a.csv", "predicting".
  [[noreturn]] void interrupted_while(const std::string& activity) const;

 private:
  [[noreturn]] void interrupted(const std::string& during) const;

  study::InterruptGuard guard_;
  std::vector<std::string> planned_, written_;
};

}  // namespace rover::cli
