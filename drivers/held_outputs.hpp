// One writer per file for the one-process commands (simulate, synthesize,
// terrain, friction, surrogate --predict): each takes, for every file it is
// about to write, the lock a study holds on its result (io/output_lock.hpp),
// so that a command and a running study, or two commands, never write one
// file at once. Links and special files (a pipe, a terminal, /dev/stdout)
// are written through and take no lock. See docs/reliability.md.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "io/output_lock.hpp"

namespace rover::cli {

class HeldOutputs {
 public:
  // Makes the folders of `path` and takes its lock until this object dies;
  // nothing for an empty path, a link or a special file. Retires the exit on
  // a signal of study::exit_on_interrupt_until_guarded(): the command writes. Throws CommandLineError
  // naming `flag` if another process writes `path` now.
  void hold(const std::string& flag, const std::string& path);

 private:
  std::vector<std::unique_ptr<io::OutputLock>> locks_;
};

}  // namespace rover::cli
