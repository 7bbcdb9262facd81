// RAII MPI session: initialises MPI (also when the program was started without
// mpirun, as a singleton) and finalises it. One per process, in main().
#pragma once

namespace rover::study {

class MpiSession {
 public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  int rank_ = 0, size_ = 1;
  bool owns_ = false;
};

}  // namespace rover::study
