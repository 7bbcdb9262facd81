// One writer per result: a study holds an advisory lock (flock) on
// `<out>.lock` from its start to its end, so a second rover process aimed at
// the same --out (the same study started twice, or --resume / --restart of a
// study that is still running) is refused before it touches the result, its
// checkpoint or its temporary file. The lock dies with its process (a crash
// or a kill leaves no stale lock, only a file the next holder reuses); the
// holder removes the file when it is done. The one-process commands take the
// same lock on each file they write (drivers/held_outputs.hpp), so that they
// and a study never write one file at once. See docs/reliability.md.
#pragma once

#include <string>

namespace rover::io {

class OutputLock {
 public:
  static std::string path_for(const std::string& results_path) { return results_path + ".lock"; }

  // Takes the lock of `results_path`, the output of flag `flag`. Throws
  // std::runtime_error naming the result if another process holds it, or if
  // the lock file cannot be made.
  explicit OutputLock(const std::string& results_path, const std::string& flag = "--out");
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  // Whether another process holds the lock of `results_path` now (a probe:
  // nothing is kept, and no lock file is made).
  static bool held_elsewhere(const std::string& results_path);
  // "another rover process is writing <result> now ...": the refusal when it
  // is, advising another value of `flag`.
  static std::string held_message(const std::string& results_path, const std::string& flag = "--out");

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace rover::io
