// RAII MPI session: initialises MPI (also when the program was started without
// mpirun, as a singleton) and finalises it. One per process, in main().
// Throws std::invalid_argument, before MPI starts, when a variable of the
// environment that rover sets itself (OMPI_MCA_btl_vader_eager_limit) holds
// a value Open MPI could not read: MPI_Init would abort with its own text.
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
