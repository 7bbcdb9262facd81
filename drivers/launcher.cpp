// See launcher.hpp.
#include "drivers/launcher.hpp"

#include <algorithm>
#include <cstdlib>

namespace rover::cli {

int launcher_size() {
  int size = 1;
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    if (const char* value = std::getenv(name); value != nullptr) size = std::max(size, std::atoi(value));
  return size;
}

int launcher_rank() {
  bool in_a_job = launcher_size() > 1;
  if (const char* value = std::getenv("SLURM_NTASKS"); value != nullptr && std::atoi(value) > 1) in_a_job = true;
  if (!in_a_job) return 0;
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
    if (const char* value = std::getenv(name); value != nullptr && *value != '\0') return std::atoi(value);
  return 0;
}

std::string one_process_refusal(int size) {
  return "runs on one process, but mpirun started " + std::to_string(size) +
         " (every one would do the same work and print or write the same): run it without mpirun";
}

}  // namespace rover::cli
