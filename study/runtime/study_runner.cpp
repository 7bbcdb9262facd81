#include "study/runtime/study_runner.hpp"

#include <filesystem>
#include <iostream>

#include <mpi.h>

#include <csignal>
#include <ctime>

#include <unistd.h>

#include "io/checkpoint.hpp"
#include "study/runtime/ordered_sink.hpp"

namespace rover::study {

int world_rank() {
  int initialized = 0;
  MPI_Initialized(&initialized);
  int rank = 0;
  if (initialized) MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

int world_size() {
  int initialized = 0;
  MPI_Initialized(&initialized);
  int size = 1;
  if (initialized) MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

std::vector<TaskResult> run_study_tasks(int task_count,
                                        const std::function<TaskResult(int)>& compute,
                                        const StudyRunOptions& options) {
  std::vector<TaskResult> all;
  stream_study_tasks(task_count, compute, [&](TaskResult&& r) { all.push_back(std::move(r)); }, options);
  return all;
}

namespace {

// The one piece of process-wide state: a signal handler can only reach a
// static. Set by SIGINT/SIGTERM while an InterruptGuard is alive.
std::atomic<bool> g_interrupted{false};
// CLOCK_MONOTONIC time of the signal that set the flag; 0 while none did (the
// task farm raises the flag when a worker rank was signalled alone).
std::atomic<long long> g_first_signal_ns{0};
using Handler = void (*)(int);
Handler g_previous_int = SIG_DFL, g_previous_term = SIG_DFL;
int g_guard_depth = 0;  // guards alive; only the outermost installs and restores the handlers

long long monotonic_ns() {  // clock_gettime is async-signal-safe
  constexpr long long kNanosecondsPerSecond = 1'000'000'000;
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<long long>(now.tv_sec) * kNanosecondsPerSecond + now.tv_nsec;
}

extern "C" void on_interrupt(int signal_number) {
  const long long now_ns = monotonic_ns();
  const bool raised = g_interrupted.exchange(true);
  if (!raised || g_first_signal_ns.load() == 0) {  // this process's first signal
    g_first_signal_ns.store(now_ns);
    return;
  }
  constexpr double kNanosecondsPerSecond = 1e9;
  const auto since_first_ns = static_cast<double>(now_ns - g_first_signal_ns.load());
  if (since_first_ns < InterruptGuard::kSignalRepeatWindow_s * kNanosecondsPerSecond) return;
  // A later second signal kills as it would have without the guard.
  const Handler previous = signal_number == SIGINT ? g_previous_int : g_previous_term;
  std::signal(signal_number, previous);
  std::raise(signal_number);
}

// Before the first guard: the command is still reading its inputs (perhaps
// blocked on a pipe no one writes yet) and has written nothing of its own.
extern "C" void on_interrupt_before_guard(int signal_number) {
  static constexpr char kInt[] = "rover: interrupted (SIGINT); nothing written\n";
  static constexpr char kTerm[] = "rover: interrupted (SIGTERM); nothing written\n";
  // write(2) and _exit are async-signal-safe; a short write only shortens the message.
  const bool by_int = signal_number == SIGINT;
  const char* message = by_int ? kInt : kTerm;
  const std::size_t length = by_int ? sizeof kInt - 1 : sizeof kTerm - 1;
  [[maybe_unused]] const ssize_t written = write(STDERR_FILENO, message, length);
  _exit(StudyInterrupted::kExitCode);
}

// The handler a guard restores: the system's default in place of the one of
// exit_on_interrupt_until_guarded(), which is retired by the first guard.
Handler restorable(Handler previous) {
  return previous == SIG_ERR || previous == on_interrupt_before_guard ? SIG_DFL : previous;
}

// "12 of 600 runs are saved in <checkpoint>", or, before any run finished,
// that nothing is (no checkpoint file exists to resume from).
std::string saved_runs_text(const io::ResultCheckpoint& checkpoint, int task_count) {
  if (checkpoint.size() == 0)
    return "none of the " + std::to_string(task_count) + " runs had finished, so nothing is saved";
  return std::to_string(checkpoint.size()) + " of " + std::to_string(task_count) + " runs are saved in " +
         checkpoint.path();
}

}  // namespace

void exit_on_interrupt_until_guarded() {
  std::signal(SIGINT, on_interrupt_before_guard);
  std::signal(SIGTERM, on_interrupt_before_guard);
}

void retire_exit_on_interrupt() {
  for (const int signal_number : {SIGINT, SIGTERM}) {
    const Handler current = std::signal(signal_number, SIG_DFL);
    if (current != on_interrupt_before_guard && current != SIG_ERR) std::signal(signal_number, current);
  }
}

InterruptGuard::InterruptGuard() {
  if (g_guard_depth++ > 0) return;
  g_interrupted.store(false);
  g_first_signal_ns.store(0);
  g_previous_int = restorable(std::signal(SIGINT, on_interrupt));
  g_previous_term = restorable(std::signal(SIGTERM, on_interrupt));
}

InterruptGuard::~InterruptGuard() {
  if (--g_guard_depth > 0) return;
  std::signal(SIGINT, g_previous_int);
  std::signal(SIGTERM, g_previous_term);
}

std::atomic<bool>& InterruptGuard::flag() { return g_interrupted; }

void stream_study_tasks(int task_count, const std::function<TaskResult(int)>& compute,
                        const std::function<void(TaskResult&&)>& consume,
                        const StudyRunOptions& options) {
  const bool root = world_rank() == 0;
  std::unique_ptr<io::ResultCheckpoint> checkpoint;
  OrderedSink<TaskResult> sink([&](int, TaskResult&& r) { consume(std::move(r)); });
  std::vector<int> todo;
  if (root) {
    if (const auto dir = std::filesystem::path(options.results_path).parent_path(); !dir.empty())
      std::filesystem::create_directories(dir);
    checkpoint = std::make_unique<io::ResultCheckpoint>(options.results_path, options.fingerprint,
                                                        options.checkpoint);
    std::vector<TaskResult> done;
    std::error_code error;
    // A link there is this directory entry, dangling or not (never followed).
    const bool present = std::filesystem::exists(std::filesystem::symlink_status(checkpoint->path(), error));
    if (options.resume && !present) {
      std::cerr << options.label << ": --resume found no checkpoint " << checkpoint->path()
                << "; every run is computed\n";
    } else if (options.resume) {
      done = checkpoint->load();
      std::cerr << options.label << ": resuming, " << done.size() << " of " << task_count
                << " runs already done (" << checkpoint->path() << ")\n";
    } else if (present) {
      // The drivers refuse a leftover checkpoint unless --restart discards it.
      std::cerr << options.label << ": starting afresh; the old checkpoint " << checkpoint->path()
                << " is deleted\n";
      checkpoint->remove();
    }
    todo = io::missing_indices(task_count, done);
    for (TaskResult& r : done)
      if (r.index >= 0 && r.index < task_count) sink.push(r.index, std::move(r));
  }
  TaskFarmOptions farm;
  farm.label = options.label;
  farm.progress_interval_s = options.progress_interval_s;
  farm.keep_results = false;
  farm.stop = &g_interrupted;
  const std::string resume_hint =
      "Continue with:\n  " + (options.resume_command.empty() ? std::string("the same command with --resume")
                                                             : options.resume_command);
  // At the signal, at once (under mpirun, rank 0's own run may still be
  // computing; Open MPI kills the ranks 1 s after its SIGTERM): what is
  // finished goes to disk and the user learns how to resume. From then on
  // every arriving run is written as it comes.
  farm.on_stop = [&] {
    checkpoint->save();
    std::cerr << options.label << ": interrupt: no new runs are handed out; "
              << saved_runs_text(*checkpoint, task_count) << "; runs still in progress are added if they finish"
              << (checkpoint->size() == 0 ? "." : ". " + resume_hint) << std::endl;
  };
  run_task_farm(
      todo, compute,
      [&](const TaskResult& r) {
        checkpoint->add(r);
        if (g_interrupted.load()) checkpoint->save();
        sink.push(r.index, TaskResult(r));
      },
      farm);
  if (!root) return;
  checkpoint->save();
  if (g_interrupted.load()) {
    throw StudyInterrupted(options.label + ": interrupted; " + saved_runs_text(*checkpoint, task_count) + ". " +
                           (checkpoint->size() == 0 ? std::string("Run the same command again.") : resume_hint));
  }
  if (sink.buffered() != 0)
    throw std::logic_error(options.label + ": " + std::to_string(sink.buffered()) +
                           " results wait for a missing run");
}

void remove_checkpoint(const std::string& results_path) {
  const std::string path = io::ResultCheckpoint::path_for(results_path);
  if (io::ResultCheckpoint::is_foreign_file(path)) return;  // someone's data, never removed
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
}

GaussianProcessSettings interruptible(GaussianProcessSettings settings) {
  settings.stop = &InterruptGuard::flag();
  return settings;
}

}  // namespace rover::study
