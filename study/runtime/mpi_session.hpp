// RAII MPI session: initialises MPI (also when the program was started without
// mpirun, as a singleton) and finalises it. One per process, in main().
// Throws std::invalid_argument, before MPI starts, when a variable of the
// environment that rover sets itself (OMPI_MCA_btl_vader_eager_limit) holds
// a value Open MPI could not read: MPI_Init would abort with its own text.
//
// Leaving: every rank meets the others before MPI_Finalize (meet_on_exit). A
// rank that refused its inputs waits for them a few seconds only: a refusal
// that only some ranks reach (a file that differs between nodes, an MPMD
// launch) would otherwise leave the others waiting for its runs forever; the
// refusing rank then ends the whole job (end_job).
#pragma once

#include <chrono>

#include <mpi.h>

namespace rover::study {

class MpiSession {
 public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

  // How long a refusing rank waits for the others on its way out.
  static constexpr std::chrono::seconds kRefusalGrace{10};

  // Waits until every rank has reached its exit: without limit for a rank
  // that did not refuse (it may wait for rank 0 to write the result), at
  // most kRefusalGrace for one that did. False when the others did not come.
  bool meet_on_exit(bool refused);
  // Ends this rank at once with `exit_status`, without MPI_Finalize (which
  // would wait for the others): mpirun then ends the other ranks, as after
  // any rank's non-zero exit, with its own short notice and not MPI_Abort's.
  [[noreturn]] void end_job(int exit_status);

 private:
  int rank_ = 0, size_ = 1;
  bool owns_ = false;
  MPI_Comm exit_comm_ = MPI_COMM_NULL;  // the exit meeting's own, apart from the study's collectives
};

}  // namespace rover::study
