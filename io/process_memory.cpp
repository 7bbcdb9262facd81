// See process_memory.hpp.
#include "io/process_memory.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <utility>

namespace rover::io {

MemoryLimit process_memory_limit() {
  const double page = static_cast<double>(::sysconf(_SC_PAGESIZE));
  MemoryLimit limit{page * static_cast<double>(::sysconf(_SC_PHYS_PAGES)), "this machine's physical memory"};
  double mapped = 0.0;  // pages the process maps already
  if (std::ifstream statm("/proc/self/statm"); statm >> mapped) mapped *= page;
  const std::pair<int, const char*> limits[] = {{RLIMIT_AS, "the address-space limit (ulimit -v)"},
                                                {RLIMIT_DATA, "the data-size limit (ulimit -d)"}};
  for (const auto& [resource, name] : limits) {
    struct rlimit r {};
    if (::getrlimit(resource, &r) != 0 || r.rlim_cur == RLIM_INFINITY) continue;
    const double left = std::max(0.0, static_cast<double>(r.rlim_cur) - mapped);
    if (left < limit.bytes) limit = {left, std::string(name) + " less what the process maps already"};
  }
  return limit;
}

}  // namespace rover::io
