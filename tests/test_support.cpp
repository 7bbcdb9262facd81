#include "test_support.hpp"

#include <fstream>
#include <iterator>

#include <array>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <sys/wait.h>
#include <unistd.h>
#include <string>
#include <system_error>
#include <vector>

#include <gtest/gtest.h>

namespace rover::testing {

std::string source_path(const std::string& relative) {
  return std::string(ROVER_SOURCE_DIR) + "/" + relative;
}

namespace {
// Open MPI refuses root unless told, and CI runs as root with 2 cores.
const bool kMpiEnvironment = [] {
  setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 0);
  setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 0);
  setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 0);
  return true;
}();

// A fresh directory for the Open MPI session tree of one command.
std::filesystem::path new_mpi_session_base() {
  static std::atomic<long> count{0};
  std::error_code error;
  const std::filesystem::path base =
      std::filesystem::temp_directory_path(error) /
      ("rover_test_ompi_" + std::to_string(getpid()) + "_" + std::to_string(count++));
  std::filesystem::create_directories(base, error);
  return error ? std::filesystem::path() : base;
}
}  // namespace

std::string rover_binary() {
  const char* env = std::getenv("ROVER_BINARY");
  return env ? env : std::string(ROVER_BINARY_PATH);
}

std::string mpiexec() {
  (void)kMpiEnvironment;
  const std::string exe = std::string(ROVER_MPIEXEC).empty() ? "mpirun" : ROVER_MPIEXEC;
  return exe + " --oversubscribe";
}

namespace {
// Removes the directories of temp_dir(): a test's own when it passes (a failed
// test's stay, and their paths are printed, for a look at what it wrote), and
// those made outside any test (a suite's shared set-up) when the program ends
// with every test passed.
class TempDirCleaner : public ::testing::EmptyTestEventListener {
 public:
  void add(const std::filesystem::path& dir, bool in_test) { (in_test ? test_dirs_ : program_dirs_).push_back(dir); }

 private:
  static void remove_or_keep(std::vector<std::filesystem::path>& dirs, bool passed) {
    for (const auto& dir : dirs) {
      std::error_code ignored;
      if (passed)
        std::filesystem::remove_all(dir, ignored);
      else
        std::printf("kept %s\n", dir.c_str());
    }
    dirs.clear();
  }
  void OnTestEnd(const ::testing::TestInfo& info) override {
    remove_or_keep(test_dirs_, !info.result()->Failed());
  }
  void OnTestProgramEnd(const ::testing::UnitTest& unit) override {
    remove_or_keep(program_dirs_, unit.Passed());
  }
  std::vector<std::filesystem::path> test_dirs_, program_dirs_;
};

TempDirCleaner& temp_dir_cleaner() {
  static TempDirCleaner* cleaner = [] {
    auto* c = new TempDirCleaner;  // owned by gtest's listener list
    ::testing::UnitTest::GetInstance()->listeners().Append(c);
    return c;
  }();
  return *cleaner;
}
}  // namespace

std::string temp_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "_" + info->name() : "rover";
  for (char& c : name)
    if (c == '/') c = '_';
  std::random_device rd;
  const auto dir = std::filesystem::temp_directory_path() /
                   ("rover_test_" + name + "_" + std::to_string(rd()));
  std::filesystem::create_directories(dir);
  temp_dir_cleaner().add(dir, info != nullptr);
  return dir.string();
}

// Each command's MPI programs get a session-directory tree of their own
// (OMPI_MCA_orte_tmpdir_base), removed after it: MPI singletons started at the
// same moment (tests running side by side, a test's cases run on threads)
// otherwise create and remove the same /tmp/ompi.<host>.<uid>/jf.0 and fail
// orte_init ("A call to mkdir was unable to create the desired directory").
int run_command(const std::string& command, std::string* output) {
  (void)kMpiEnvironment;
  const std::filesystem::path session = std::getenv("OMPI_MCA_orte_tmpdir_base") ? std::filesystem::path()
                                                                                 : new_mpi_session_base();
  const std::string prefix = session.empty() ? "" : "export OMPI_MCA_orte_tmpdir_base='" + session.string() + "'; ";
  FILE* pipe = popen((prefix + command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buffer{};
  std::string text;
  while (fgets(buffer.data(), buffer.size(), pipe)) text += buffer.data();
  const int status = pclose(pipe);
  if (!session.empty()) {
    std::error_code ignored;
    std::filesystem::remove_all(session, ignored);
  }
  if (output) *output = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string signal_once_checkpoint_grows(const std::string& command, const std::string& checkpoint,
                                         const std::string& signal) {
  const std::string file = "'" + checkpoint + "'";
  return "(" + command + " & pid=$!; first=; for i in $(seq 6000); do "
         "if [ -s " + file + " ]; then size=$(stat -c %s " + file + "); "
         "[ -z \"$first\" ] && first=$size; [ \"$size\" -gt \"$first\" ] && break; fi; "
         "kill -0 $pid 2>/dev/null || break; sleep 0.01; done; kill -" + signal + " $pid 2>/dev/null; wait $pid)";
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::string write_file(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

std::string short_drop_scenario(const std::string& dir) {
  return write_file(dir + "/short_drop.json", R"({"name": "short_drop", "rover": ")" +
                                                  source_path("configs/rover.json") +
                                                  R"(", "duration": 0.25, "output_rate": 200,
      "initial_q": {"z": 0.281, "chi": 0.039, "psi": 0.0042}})");
}

}  // namespace rover::testing
