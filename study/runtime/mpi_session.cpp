#include "study/runtime/mpi_session.hpp"

#include <cstdlib>

#include <mpi.h>

namespace rover::study {
namespace {

// A run's record (its QoIs and one 1,001-sample channel, about 8 kB) is above
// Open MPI's shared-memory eager limit (4 kB): it would go in a rendezvous,
// a handshake with rank 0's communication thread (which polls every
// millisecond) before the data move. 32 kB sends such records in one message
// (a 2-rank drop study: 0.97x the wall time, on top of the workers' MPI_Isend).
// The default only: a user's own setting (OMPI_MCA_... in the environment, or
// mpirun --mca) wins; other MPI libraries ignore the name.
void prefer_eager_shared_memory_sends() {
  setenv("OMPI_MCA_btl_vader_eager_limit", "32768", /*overwrite=*/0);
}

}  // namespace

MpiSession::MpiSession(int* argc, char*** argv) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) {
    prefer_eager_shared_memory_sends();
    int provided = 0;
    // Rank 0 runs a communication thread beside its compute thread; only one
    // thread calls MPI at a time.
    MPI_Init_thread(argc, argv, MPI_THREAD_SERIALIZED, &provided);
    owns_ = true;
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
  if (owns_) {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Finalize();
  }
}

}  // namespace rover::study
