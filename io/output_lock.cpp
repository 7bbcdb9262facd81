// See output_lock.hpp.
#include "io/output_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace rover::io {
namespace {

// A lock file is never followed through a link, and holds no data.
// Never blocking: a FIFO at the lock's name must not hold the study.
constexpr int kOpenFlags = O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK;
constexpr mode_t kLockMode = 0644;

// Whether `fd` is still the file at `path` (another holder may have removed
// and re-made it between our open and our lock).
bool still_named(int fd, const std::string& path) {
  struct stat opened {}, named {};
  return fstat(fd, &opened) == 0 && lstat(path.c_str(), &named) == 0 && opened.st_dev == named.st_dev &&
         opened.st_ino == named.st_ino;
}

// A lock file of rover is empty and has one name: anything else is a file of
// the user's that happens to stand there, never removed.
bool is_lock_file(int fd) {
  struct stat st {};
  return fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size == 0 && st.st_nlink == 1;
}

}  // namespace

OutputLock::OutputLock(const std::string& results_path, const std::string& flag) : path_(path_for(results_path)) {
  for (;;) {
    fd_ = ::open(path_.c_str(), kOpenFlags, kLockMode);
    if (fd_ < 0 && errno == ELOOP)
      throw std::runtime_error(path_ + " is a symbolic link, which no lock file of rover is: move it, or give "
                               "another " + flag);
    if (fd_ < 0)
      throw std::runtime_error("cannot make the lock file " + path_ + " beside the result: " + std::strerror(errno));
    struct stat opened {};
    if (fstat(fd_, &opened) == 0 && opened.st_nlink == 0) {
      ::close(fd_);  // its holder is removing it: make a new one
      continue;
    }
    if (!is_lock_file(fd_)) {
      ::close(fd_);
      fd_ = -1;
      throw std::runtime_error(path_ + " is in the way of the result's lock: it is no empty regular file with one "
                               "name, which a lock file of rover always is; move it, or give another " + flag);
    }
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd_);
      fd_ = -1;
      throw std::runtime_error(OutputLock::held_message(results_path, flag));
    }
    if (still_named(fd_, path_)) return;
    ::close(fd_);  // the previous holder removed it: lock the new one
  }
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  if (is_lock_file(fd_)) ::unlink(path_.c_str());  // while still held: the next process makes a new file
  ::close(fd_);
}

std::string OutputLock::held_message(const std::string& results_path, const std::string& flag) {
  return "another rover process is writing " + results_path + " now (it holds " + path_for(results_path) +
         "): wait for it to finish, or give another " + flag;
}

bool OutputLock::held_elsewhere(const std::string& results_path) {
  const int fd = ::open(path_for(results_path).c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
  if (fd < 0) return false;
  const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);
  return held;
}

}  // namespace rover::io
