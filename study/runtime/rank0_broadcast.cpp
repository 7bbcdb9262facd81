// See rank0_broadcast.hpp.
#include "study/runtime/rank0_broadcast.hpp"

#include <mpi.h>

namespace rover::study {

void broadcast_from_rank0(std::vector<double>& values) {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (!initialized || finalized) return;
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size == 1) return;
  unsigned long long count = values.size();
  MPI_Bcast(&count, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
  values.resize(static_cast<std::size_t>(count));
  if (count > 0) MPI_Bcast(values.data(), static_cast<int>(count), MPI_DOUBLE, 0, MPI_COMM_WORLD);
}

bool broadcast_flag_from_rank0(bool flag) {
  std::vector<double> value{flag ? 1.0 : 0.0};
  broadcast_from_rank0(value);
  return value[0] != 0.0;
}

bool differs_from_rank0_anywhere(const std::string& text) {
  std::vector<double> rank0_text(text.begin(), text.end());
  broadcast_from_rank0(rank0_text);
  int differs = rank0_text != std::vector<double>(text.begin(), text.end()) ? 1 : 0;
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (initialized && !finalized) MPI_Allreduce(MPI_IN_PLACE, &differs, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
  return differs != 0;
}

}  // namespace rover::study
