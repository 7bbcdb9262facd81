// The memory this process may still take: the physical memory, or less where
// a limit of the process (ulimit -v, ulimit -d) leaves less beside what it
// maps already (MPI and HDF5 map hundreds of MB). Read at the call, so a
// limit set before the program started is seen (docs/reliability.md, the
// study's memory).
#pragma once

#include <string>

namespace rover::io {

struct MemoryLimit {
  double bytes = 0.0;
  std::string what;  // "this machine's physical memory", "the address-space limit (ulimit -v) less ..."
};

MemoryLimit process_memory_limit();

}  // namespace rover::io
