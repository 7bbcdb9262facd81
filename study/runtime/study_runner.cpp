#include "study/runtime/study_runner.hpp"

#include <filesystem>
#include <iostream>
#include <iterator>

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
// static. Set by a stop signal (kStopSignals) while an InterruptGuard is alive.
std::atomic<bool> g_interrupted{false};
// The signal that raised the flag first; 0 while none did (the task farm
// raises the flag when a worker rank was signalled alone).
std::atomic<int> g_signal{0};
// CLOCK_MONOTONIC time of the signal that set the flag; 0 while none did.
std::atomic<long long> g_first_signal_ns{0};
using Handler = void (*)(int);
// The signals a guard turns into a request to stop: Ctrl-C, kill, a closed
// terminal or ssh session, and a write to a pipe whose reader is gone
// (`rover ... | head`). SIGQUIT keeps its default action: it asks for a core
// dump, and gets one.
constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};
constexpr std::size_t kStopSignalCount = std::size(kStopSignals);
Handler g_previous[kStopSignalCount] = {SIG_DFL, SIG_DFL, SIG_DFL, SIG_DFL};  // restored by the outermost guard
int g_guard_depth = 0;  // guards alive; only the outermost installs and restores the handlers
// A SIGPIPE outside the guards: an output pipe's reader has gone. The write
// failed (EPIPE) and the stream stays failed, writing nothing more that could
// raise it again: the next guard starts with its flag raised.
std::atomic<bool> g_output_pipe_closed{false};

std::size_t slot_of(int signal_number) {  // async-signal-safe
  for (std::size_t i = 0; i < kStopSignalCount; ++i)
    if (kStopSignals[i] == signal_number) return i;
  return 0;
}

long long monotonic_ns() {  // clock_gettime is async-signal-safe
  constexpr long long kNanosecondsPerSecond = 1'000'000'000;
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<long long>(now.tv_sec) * kNanosecondsPerSecond + now.tv_nsec;
}

extern "C" void on_interrupt(int signal_number) {
  int none = 0;
  g_signal.compare_exchange_strong(none, signal_number);
  if (signal_number == SIGPIPE) {
    // Every later write to the closed pipe raises it again (the message of the
    // stop included): a request to stop, never a second one that kills.
    g_interrupted.store(true);
    return;
  }
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
  std::signal(signal_number, g_previous[slot_of(signal_number)]);
  std::raise(signal_number);
}

// Before the first guard: the command is still reading its inputs (perhaps
// blocked on a pipe no one writes yet) and has written nothing of its own.
extern "C" void on_interrupt_before_guard(int signal_number) {
  static constexpr char kInt[] = "rover: interrupted (SIGINT); nothing written\n";
  static constexpr char kTerm[] = "rover: interrupted (SIGTERM); nothing written\n";
  static constexpr char kHup[] = "rover: interrupted (SIGHUP); nothing written\n";
  // write(2) and _exit are async-signal-safe; a short write only shortens the message.
  const char* message = signal_number == SIGINT ? kInt : signal_number == SIGHUP ? kHup : kTerm;
  const std::size_t length = signal_number == SIGINT ? sizeof kInt - 1 : signal_number == SIGHUP ? sizeof kHup - 1
                                                                                                   : sizeof kTerm - 1;
  [[maybe_unused]] const ssize_t written = write(STDERR_FILENO, message, length);
  _exit(StudyInterrupted::kExitCode);
}

extern "C" void on_pipe_outside_guards(int) { g_output_pipe_closed.store(true); }

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
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal_number, on_interrupt_before_guard);
  // A write to a closed pipe fails (EPIPE), and is reported, instead of
  // ending the process without a word.
  std::signal(SIGPIPE, on_pipe_outside_guards);
}

void retire_exit_on_interrupt() {
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    const Handler current = std::signal(signal_number, SIG_DFL);
    if (current != on_interrupt_before_guard && current != SIG_ERR) std::signal(signal_number, current);
  }
}

InterruptGuard::InterruptGuard() {
  if (g_guard_depth++ > 0) return;
  g_interrupted.store(false);
  g_signal.store(0);
  g_first_signal_ns.store(0);
  for (std::size_t i = 0; i < kStopSignalCount; ++i)
    g_previous[i] = restorable(std::signal(kStopSignals[i], on_interrupt));
  if (g_output_pipe_closed.load()) {  // the banner went into a closed pipe: stop at once
    g_signal.store(SIGPIPE);
    g_interrupted.store(true);
  }
}

InterruptGuard::~InterruptGuard() {
  if (--g_guard_depth > 0) return;
  for (std::size_t i = 0; i < kStopSignalCount; ++i) std::signal(kStopSignals[i], g_previous[i]);
}

std::atomic<bool>& InterruptGuard::flag() { return g_interrupted; }

std::string InterruptGuard::signal_name() {
  switch (g_signal.load()) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    case SIGPIPE: return "SIGPIPE: an output pipe was closed";
    default: return "a signal to another rank";
  }
}

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
      report_dropped_checkpoint_bytes(*checkpoint, options.label, "runs");
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
    throw StudyInterrupted(options.label + ": interrupted (" + InterruptGuard::signal_name() + "); " +
                           saved_runs_text(*checkpoint, task_count) + ". " +
                           (checkpoint->size() == 0 ? std::string("Run the same command again.") : resume_hint));
  }
  if (sink.buffered() != 0)
    throw std::logic_error(options.label + ": " + std::to_string(sink.buffered()) +
                           " results wait for a missing run");
}

void report_dropped_checkpoint_bytes(const io::ResultCheckpoint& checkpoint, const std::string& label,
                                     const std::string& records) {
  if (const std::uint64_t dropped = checkpoint.torn_tail_bytes(); dropped > 0)
    std::cerr << label << ": the checkpoint's last " << dropped << " bytes hold no whole, intact record (a write "
              << "cut short, or damage) and were dropped: their " << records << " are computed again\n";
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
