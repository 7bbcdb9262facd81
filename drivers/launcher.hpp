// The processes a launcher (mpirun, srun) started with this one, as the
// environment names them, and the refusal of a one-process command among
// several (docs/cluster.md): every process would write the same outputs.
#pragma once

#include <string>

namespace rover::cli {

// The number of processes the launcher started with this one (mpirun or
// srun set it for each process: Open MPI, MPICH, PMIx), or 1 when run alone.
// SLURM_NTASKS is not asked: a batch script running rover directly has it too.
int launcher_size();

// This process's rank under mpirun (Open MPI, PMIx and MPICH name it in the
// environment), or 0 when run alone. A rank variable without a job size above
// 1 beside it (one set by hand, say) is no job: the messages stay printed.
int launcher_rank();

// "runs on one process, but mpirun started 2 (every one would do the same
// work and print or write the same): run it without mpirun".
std::string one_process_refusal(int size);

}  // namespace rover::cli
