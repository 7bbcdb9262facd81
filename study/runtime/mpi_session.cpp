#include "study/runtime/mpi_session.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

#include <mpi.h>

namespace rover::study {
namespace {

constexpr const char* kEagerLimitVariable = "OMPI_MCA_btl_vader_eager_limit";
constexpr const char* kEagerLimitDefault = "32768";

// Open MPI refuses an eager limit below its message header (56 bytes here);
// beyond 1 GiB it is meaningless for rover's records of kilobytes.
constexpr std::uint64_t kEagerLimitMin = 1024;
constexpr std::uint64_t kEagerLimitMax = std::uint64_t{1} << 30;

// A byte count as Open MPI reads one: digits, optionally followed by k, m or
// g (powers of 1024); empty when `text` is none.
std::optional<std::uint64_t> byte_count(const std::string& text) {
  const std::size_t digits = text.find_first_not_of("0123456789");
  if (digits == 0 || text.empty() || std::min(digits, text.size()) > 12) return std::nullopt;
  const std::uint64_t number = std::stoull(text.substr(0, digits));
  if (digits == std::string::npos) return number;
  const std::string units = "kKmMgG";
  const std::size_t unit = units.find(text.back());
  if (digits + 1 != text.size() || unit == std::string::npos) return std::nullopt;
  if (number > kEagerLimitMax) return number;  // too large with any unit; shifting it could overflow
  return number << (10 * (unit / 2 + 1));
}

// A run's record (its QoIs and one 1,001-sample channel, about 8 kB) is above
// Open MPI's shared-memory eager limit (4 kB): it would go in a rendezvous,
// a handshake with rank 0's communication thread (which polls every
// millisecond) before the data move. 32 kB sends such records in one message
// (a 2-rank drop study: 0.97x the wall time, on top of the workers' MPI_Isend).
// The default only: a user's own setting (OMPI_MCA_... in the environment, or
// mpirun --mca) wins; other MPI libraries ignore the name. A setting Open MPI
// cannot read would abort inside MPI_Init with Open MPI's own text: it is
// refused here, before MPI starts.
void prefer_eager_shared_memory_sends() {
  const char* value = std::getenv(kEagerLimitVariable);
  if (value == nullptr) {
    setenv(kEagerLimitVariable, kEagerLimitDefault, /*overwrite=*/0);
    return;
  }
  if (const std::optional<std::uint64_t> bytes = byte_count(value);
      !bytes || *bytes < kEagerLimitMin || *bytes > kEagerLimitMax)
    throw std::invalid_argument(std::string("the environment variable ") + kEagerLimitVariable + "='" + value +
                                "' is not a byte count from 1024 to 1g (a whole number, optionally with k, m or "
                                "g, such as " + kEagerLimitDefault + "); unset it (rover then uses " +
                                kEagerLimitDefault + ") or give such a count");
}

// Started without a launcher (mpirun, srun), Open MPI 4 starts a singleton
// with a local daemon, whose remote launcher (ssh or rsh) it looks up
// although it never uses it: without either, MPI_Init aborts with Open MPI's
// own text. An isolated singleton starts no daemon (rover spawns no
// processes), so it needs neither, and starts in about half the CPU time.
// A user's own setting wins; other MPI libraries ignore the name.
void isolate_singletons() {
  for (const char* launched : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMIX_NAMESPACE"})
    if (std::getenv(launched) != nullptr) return;
  setenv("OMPI_MCA_ess_singleton_isolated", "1", /*overwrite=*/0);
}

}  // namespace

MpiSession::MpiSession(int* argc, char*** argv) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) {
    prefer_eager_shared_memory_sends();
    isolate_singletons();
    int provided = 0;
    // Rank 0 runs a communication thread beside its compute thread; only one
    // thread calls MPI at a time.
    MPI_Init_thread(argc, argv, MPI_THREAD_SERIALIZED, &provided);
    owns_ = true;
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  if (owns_ && size_ > 1) MPI_Comm_dup(MPI_COMM_WORLD, &exit_comm_);  // the outermost session meets on exit
}

bool MpiSession::meet_on_exit(bool refused) {
  if (exit_comm_ == MPI_COMM_NULL) return true;
  constexpr std::chrono::milliseconds kPollInterval{10};
  MPI_Request meeting = MPI_REQUEST_NULL;
  MPI_Ibarrier(exit_comm_, &meeting);
  if (!refused) {
    MPI_Wait(&meeting, MPI_STATUS_IGNORE);
    return true;
  }
  const auto deadline = std::chrono::steady_clock::now() + kRefusalGrace;
  for (int met = 0;; std::this_thread::sleep_for(kPollInterval)) {
    MPI_Test(&meeting, &met, MPI_STATUS_IGNORE);
    if (met) return true;
    if (std::chrono::steady_clock::now() > deadline) return false;
  }
}

void MpiSession::end_job(int exit_status) {
  std::_Exit(exit_status);
}

MpiSession::~MpiSession() {
  if (exit_comm_ != MPI_COMM_NULL) MPI_Comm_free(&exit_comm_);
  if (owns_) {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Finalize();
  }
}

}  // namespace rover::study
