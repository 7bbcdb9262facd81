// See task_farm.hpp.
//
// Protocol on a private duplicate of MPI_COMM_WORLD, master = rank 0's
// communication thread:
//   worker -> master  kTagRequest  int n: "send me n tasks" (once, at start)
//   worker -> master  kTagResult   a serialised TaskResult; also asks for one more task
//   master -> worker  kTagTask     int: a task index, or kStop
//   worker -> master  kTagReturned int: a task handed back unrun (the worker's
//                                  stop flag is set); asks for nothing more
// Every request for a task is answered by exactly one kTagTask message, so a
// worker knows how many answers are pending and stops when none is. A worker
// that handed a task back is retired: it gets kStop only, and its task goes
// back to the queue (unless rank 0 is stopping too). The master
// keeps a worker's second task (the one "in hand") back when few tasks remain,
// so that no rank sits idle while another holds two; those requests are answered
// later (a task when the worker returns a result, kStop once the queue is empty).
#include "study/runtime/task_farm.hpp"
#include "study/estimators/work_stopped.hpp"
#include "study/runtime/elapsed_time.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <deque>
#include <exception>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

// The C API only: study/CMakeLists.txt defines OMPI_SKIP_MPICXX and
// MPICH_SKIP_MPICXX for every user of rover_study.
#include <mpi.h>

namespace rover::study {
namespace {

constexpr int kTagRequest = 1;
constexpr int kTagResult = 2;
constexpr int kTagTask = 3;
constexpr int kTagReturned = 4;
constexpr int kStop = -1;
constexpr int kTasksInHand = 2;  // a worker computes one and holds the next
constexpr auto kMasterPoll = std::chrono::milliseconds(1);

using Clock = std::chrono::steady_clock;

std::string format_duration(double seconds) {
  const long long s = std::llround(std::max(seconds, 0.0));
  char text[32];
  if (s < 60)
    std::snprintf(text, sizeof text, "%llds", s);
  else if (s < 3600)
    std::snprintf(text, sizeof text, "%lldm%02llds", s / 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%lldh%02lldm", s / 3600, (s % 3600) / 60);
  return text;
}

std::string format_rate(double per_second) {
  char text[32];
  std::snprintf(text, sizeof text,
                per_second >= 10  ? "%.0f"
                : per_second >= 1 ? "%.1f"
                                  : "%.2f",
                per_second);
  return text;
}

// Runs one task; an exception becomes a failed result, except WorkStopped
// (a stop request ended the task midway): the task is not done (nullopt).
std::optional<TaskResult> run_one(const std::function<TaskResult(int)>& compute, int index) {
  TaskResult result;
  try {
    result = compute(index);
  } catch (const WorkStopped&) {
    return std::nullopt;
  } catch (const std::exception& e) {
    result = TaskResult{};
    result.status = 1;
    result.message = e.what();
  } catch (...) {
    result = TaskResult{};
    result.status = 1;
    result.message = "unknown exception";
  }
  result.index = index;
  return result;
}

// One bit per index up to the largest: 10^8 tasks are checked in a second
// and 12 MB (a std::set took minutes and 40 bytes per task).
void validate_tasks(const std::vector<int>& tasks) {
  int largest = -1;
  for (const int index : tasks) {
    if (index < 0)
      throw std::invalid_argument("run_task_farm: negative task index " + std::to_string(index));
    largest = std::max(largest, index);
  }
  std::vector<bool> seen(static_cast<std::size_t>(largest + 1), false);
  for (const int index : tasks) {
    if (seen[static_cast<std::size_t>(index)])
      throw std::invalid_argument("run_task_farm: task index " + std::to_string(index) +
                                  " listed twice");
    seen[static_cast<std::size_t>(index)] = true;
  }
}

// TaskResult <-> bytes (index, status, message size, value count, message, values).
std::vector<char> serialize(const TaskResult& result) {
  const std::int32_t fixed[2] = {result.index, result.status};
  const std::uint64_t sizes[2] = {result.message.size(), result.values.size()};
  std::vector<char> bytes(sizeof fixed + sizeof sizes + result.message.size() +
                          result.values.size() * sizeof(double));
  char* out = bytes.data();
  std::memcpy(out, fixed, sizeof fixed);
  out += sizeof fixed;
  std::memcpy(out, sizes, sizeof sizes);
  out += sizeof sizes;
  std::memcpy(out, result.message.data(), result.message.size());
  out += result.message.size();
  if (!result.values.empty())
    std::memcpy(out, result.values.data(), result.values.size() * sizeof(double));
  return bytes;
}

TaskResult deserialize(const std::vector<char>& bytes) {
  std::int32_t fixed[2];
  std::uint64_t sizes[2];
  if (bytes.size() < sizeof fixed + sizeof sizes)
    throw std::runtime_error("run_task_farm: truncated result message");
  const char* in = bytes.data();
  std::memcpy(fixed, in, sizeof fixed);
  in += sizeof fixed;
  std::memcpy(sizes, in, sizeof sizes);
  in += sizeof sizes;
  if (bytes.size() != sizeof fixed + sizeof sizes + sizes[0] + sizes[1] * sizeof(double))
    throw std::runtime_error("run_task_farm: malformed result message");
  TaskResult result;
  result.index = fixed[0];
  result.status = fixed[1];
  result.message.assign(in, sizes[0]);
  in += sizes[0];
  result.values.resize(sizes[1]);
  if (sizes[1]) std::memcpy(result.values.data(), in, sizes[1] * sizeof(double));
  return result;
}

// Counts finished tasks and prints progress lines; shared by rank 0's threads.
class Progress {
 public:
  Progress(const TaskFarmOptions& options, std::size_t total)
      : options_(options), total_(total), start_(Clock::now()), last_report_(start_) {}

  void record(const TaskResult& result) {
    const std::lock_guard lock(mutex_);
    ++done_;
    if (result.status != 0) ++failed_;
  }

  void maybe_report() {
    if (!options_.progress || options_.progress_interval_s <= 0) return;
    const std::lock_guard lock(mutex_);
    if (seconds_since(last_report_) < options_.progress_interval_s) return;
    last_report_ = Clock::now();
    *options_.progress << progress_line(options_.label, done_, total_, failed_,
                                        seconds_since(start_))
                       << std::endl;
  }

  void final_report() {
    if (!options_.progress) return;
    const std::lock_guard lock(mutex_);
    const double elapsed = seconds_since(start_);
    *options_.progress << options_.label << ": " << done_ << "/" << total_ << " done (" << failed_
                       << " failed) in " << format_duration(elapsed) << ", "
                       << format_rate(elapsed > 0 ? static_cast<double>(done_) / elapsed : 0.0)
                       << " runs/s" << std::endl;
  }

 private:
  const TaskFarmOptions& options_;
  const std::size_t total_;
  const Clock::time_point start_;
  std::mutex mutex_;
  Clock::time_point last_report_;
  std::size_t done_ = 0, failed_ = 0;
};

// Hands finished tasks to on_result (and keeps them) under one lock, so that
// rank 0's two threads never deliver at the same time.
class Delivery {
 public:
  Delivery(const std::function<void(const TaskResult&)>& on_result, bool keep_results,
           std::size_t expected)
      : on_result_(on_result), keep_(keep_results) {
    if (keep_) results_.reserve(expected);
  }
  std::unique_lock<std::mutex> lock() { return std::unique_lock(mutex_); }
  // The caller holds lock().
  void deliver(TaskResult&& result) {
    if (on_result_) on_result_(result);
    ++delivered_;
    if (keep_) results_.push_back(std::move(result));
  }
  std::size_t delivered() const { return delivered_; }
  std::vector<TaskResult> take_results() { return std::move(results_); }

 private:
  const std::function<void(const TaskResult&)>& on_result_;
  const bool keep_;
  std::mutex mutex_;
  std::size_t delivered_ = 0;
  std::vector<TaskResult> results_;
};

// What rank 0's two threads share: the task queue and the results received
// from workers, waiting for the main thread.
struct Rank0State {
  Rank0State(const std::vector<int>& task_list, std::atomic<bool>* stop_flag)
      : tasks(task_list), stop(stop_flag) {}

  std::optional<int> take() {
    const std::lock_guard lock(mutex);
    if (halted()) return std::nullopt;
    if (!returned.empty()) {
      const int index = returned.back();
      returned.pop_back();
      return index;
    }
    if (next == tasks.size()) return std::nullopt;
    return tasks[next++];
  }
  std::size_t remaining() {
    const std::lock_guard lock(mutex);
    return halted() ? 0 : tasks.size() - next + returned.size();
  }
  // A task a stopped worker handed back unrun: that worker was signalled,
  // and so the whole farm stops (when it has a stop flag to raise).
  void give_back(int index) {
    const std::lock_guard lock(mutex);
    returned.push_back(index);
    if (stop != nullptr) stop->store(true);
  }
  // Cancelled, or asked to stop handing out work (a signal).
  bool halted() const { return cancelled || (stop != nullptr && stop->load()); }
  void cancel() {
    const std::lock_guard lock(mutex);
    cancelled = true;
  }

  const std::vector<int>& tasks;
  std::atomic<bool>* stop;
  std::mutex mutex;
  std::condition_variable changed;  // inbox filled or master finished
  std::size_t next = 0;
  std::vector<int> returned;
  bool cancelled = false;
  std::deque<TaskResult> inbox;
  bool master_done = false;
  std::exception_ptr master_error;
};

// Delivers what the master queued in the inbox; the caller holds the
// delivery's lock (lock order: the delivery's, then the state's).
void deliver_inbox_locked(Rank0State& state, Delivery& delivery) {
  std::deque<TaskResult> batch;
  {
    const std::lock_guard lock(state.mutex);
    batch = std::move(state.inbox);
    state.inbox.clear();
  }
  for (TaskResult& result : batch) delivery.deliver(std::move(result));
}

// The master: rank 0's communication thread, the only thread calling MPI
// while it runs; its run returns once no worker can send anything more.
class Master {
 public:
  Master(MPI_Comm comm, int size, Rank0State& state, Progress& progress, Delivery& delivery,
         const std::function<void()>& on_stop)
      : comm_(comm), size_(size), state_(state), progress_(progress), delivery_(delivery), on_stop_(on_stop),
        workers_(static_cast<std::size_t>(size)), owed_(workers_, 0), in_hand_(workers_, 0),
        retired_(workers_, false) {}

  void run() {
    while (true) {
      progress_.maybe_report();
      if (!stop_seen_ && state_.stop != nullptr && state_.stop->load()) handle_stop();
      if (state_.remaining() == 0) {
        for (int worker = 1; worker < size_; ++worker) serve(worker);
        if (started_ == size_ - 1 && total_in_hand_ == 0) return;
      }
      int arrived = 0;
      MPI_Status status;
      MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, comm_, &arrived, &status);
      if (!arrived) {
        std::this_thread::sleep_for(kMasterPoll);
        continue;
      }
      const int worker = status.MPI_SOURCE;
      if (status.MPI_TAG == kTagRequest) {
        receive_request(worker);
      } else if (status.MPI_TAG == kTagResult) {
        receive_result(worker, status);
      } else if (status.MPI_TAG == kTagReturned) {
        receive_returned(worker);
      } else {
        throw std::runtime_error("run_task_farm: unexpected message tag " + std::to_string(status.MPI_TAG) +
                                 " from rank " + std::to_string(worker));
      }
      serve(worker);
    }
  }

 private:
  void send(int worker, int message) {
    MPI_Send(&message, 1, MPI_INT, worker, kTagTask, comm_);
    --owed_[static_cast<std::size_t>(worker)];
  }

  // Answers worker's owed requests: a task if it has none in hand (or few
  // ranks would be left without work otherwise), kStop once the queue is empty.
  void serve(int worker) {
    const auto w = static_cast<std::size_t>(worker);
    while (owed_[w] > 0) {
      const std::size_t remaining = state_.remaining();
      if (remaining == 0 || retired_[w]) {
        send(worker, kStop);
      } else if (in_hand_[w] == 0 || remaining >= 2 * workers_) {
        const std::optional<int> task = state_.take();  // may have been emptied meanwhile
        if (task) {
          ++in_hand_[w];
          ++total_in_hand_;
        }
        send(worker, task.value_or(kStop));
      } else {
        return;  // hold the request until this worker returns a result
      }
    }
  }

  // A stop: deliver what the main thread has not taken yet, then on_stop;
  // later results are delivered as they arrive.
  void handle_stop() {
    stop_seen_ = true;
    auto delivering = delivery_.lock();
    deliver_inbox_locked(state_, delivery_);
    if (on_stop_) on_stop_();
  }

  void receive_request(int worker) {
    int count = 0;
    MPI_Recv(&count, 1, MPI_INT, worker, kTagRequest, comm_, MPI_STATUS_IGNORE);
    owed_[static_cast<std::size_t>(worker)] += count;
    ++started_;
  }

  void receive_result(int worker, const MPI_Status& status) {
    const auto w = static_cast<std::size_t>(worker);
    int bytes = 0;
    MPI_Get_count(&status, MPI_BYTE, &bytes);
    buffer_.resize(static_cast<std::size_t>(bytes));
    MPI_Recv(buffer_.data(), bytes, MPI_BYTE, worker, kTagResult, comm_, MPI_STATUS_IGNORE);
    TaskResult result = deserialize(buffer_);
    --in_hand_[w];
    --total_in_hand_;
    ++owed_[w];
    progress_.record(result);
    if (stop_seen_) {
      auto delivering = delivery_.lock();
      delivery_.deliver(std::move(result));
      return;
    }
    {
      const std::lock_guard lock(state_.mutex);
      state_.inbox.push_back(std::move(result));
    }
    state_.changed.notify_one();
  }

  void receive_returned(int worker) {
    const auto w = static_cast<std::size_t>(worker);
    int index = kStop;
    MPI_Recv(&index, 1, MPI_INT, worker, kTagReturned, comm_, MPI_STATUS_IGNORE);
    --in_hand_[w];
    --total_in_hand_;
    retired_[w] = true;
    state_.give_back(index);
  }

  MPI_Comm comm_;
  int size_;
  Rank0State& state_;
  Progress& progress_;
  Delivery& delivery_;
  const std::function<void()>& on_stop_;
  std::size_t workers_;
  std::vector<int> owed_;      // requests for a task not answered yet
  std::vector<int> in_hand_;   // tasks sent, result not received
  std::vector<bool> retired_;  // handed a task back: gets kStop only
  bool stop_seen_ = false;
  int started_ = 0;            // workers whose first request arrived
  int total_in_hand_ = 0;
  std::vector<char> buffer_;
};

// Rank 0's communication thread: runs the master and, whatever happens,
// tells the main thread it is done (with the master's error, if any).
void master_loop(MPI_Comm comm, int size, Rank0State& state, Progress& progress, Delivery& delivery,
                 const std::function<void()>& on_stop) {
  try {
    Master(comm, size, state, progress, delivery, on_stop).run();
  } catch (...) {
    const std::lock_guard lock(state.mutex);
    state.master_error = std::current_exception();
    state.cancelled = true;
  }
  {
    const std::lock_guard lock(state.mutex);
    state.master_done = true;
  }
  state.changed.notify_one();
}

// A result on its way to rank 0. The worker starts its next task as soon as
// the message is handed to MPI and waits for the delivery only before its next
// send: a blocking send of a record above the shared-memory fast-path size
// (Open MPI's 4 kB) returns only once rank 0's communication thread, which
// polls every millisecond, has taken it (half a millisecond a run, 3 % of a
// drop's time). The buffer lives until the send is complete.
class ResultSender {
 public:
  explicit ResultSender(MPI_Comm comm) : comm_(comm) {}
  ~ResultSender() { wait(); }
  ResultSender(const ResultSender&) = delete;
  ResultSender& operator=(const ResultSender&) = delete;

  void send(std::vector<char>&& bytes) {
    wait();
    bytes_ = std::move(bytes);
    MPI_Isend(bytes_.data(), static_cast<int>(bytes_.size()), MPI_BYTE, 0, kTagResult, comm_,
              &request_);
  }
  void wait() {
    if (request_ != MPI_REQUEST_NULL) MPI_Wait(&request_, MPI_STATUS_IGNORE);
  }

 private:
  MPI_Comm comm_;
  std::vector<char> bytes_;
  MPI_Request request_ = MPI_REQUEST_NULL;
};

void worker_loop(MPI_Comm comm, const std::function<TaskResult(int)>& compute,
                 const std::atomic<bool>* stop) {
  ResultSender sender(comm);
  int pending = kTasksInHand;
  MPI_Send(&pending, 1, MPI_INT, 0, kTagRequest, comm);
  while (pending > 0) {
    int index = kStop;
    MPI_Recv(&index, 1, MPI_INT, 0, kTagTask, comm, MPI_STATUS_IGNORE);
    --pending;
    if (index == kStop) continue;
    std::optional<TaskResult> result;
    if (stop == nullptr || !stop->load()) result = run_one(compute, index);
    if (!result) {  // stopped, before or during the task: hand it back unrun
      MPI_Send(&index, 1, MPI_INT, 0, kTagReturned, comm);
      continue;
    }
    std::vector<char> bytes = serialize(*result);
    if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
      throw std::runtime_error("run_task_farm: result of task " + std::to_string(index) +
                               " is too large for one MPI message");
    sender.send(std::move(bytes));
    ++pending;  // a result asks for the next task
  }
  // The sender's destructor waits for the last result, which rank 0 has
  // received: it answered it with kStop.
}

void sort_by_index(std::vector<TaskResult>& results) {
  std::sort(results.begin(), results.end(),
            [](const TaskResult& a, const TaskResult& b) { return a.index < b.index; });
}

std::vector<TaskResult> run_serial(const std::vector<int>& tasks,
                                   const std::function<TaskResult(int)>& compute,
                                   const std::function<void(const TaskResult&)>& on_result,
                                   const TaskFarmOptions& options) {
  validate_tasks(tasks);
  Progress progress(options, tasks.size());
  std::vector<TaskResult> results;
  if (options.keep_results) results.reserve(tasks.size());
  for (const int index : tasks) {
    if (options.stop != nullptr && options.stop->load()) break;
    std::optional<TaskResult> result = run_one(compute, index);
    if (!result) break;  // stopped midway: not done
    progress.record(*result);
    if (on_result) on_result(*result);
    if (options.keep_results) results.push_back(std::move(*result));
    progress.maybe_report();
  }
  progress.final_report();
  sort_by_index(results);
  return results;
}

std::vector<TaskResult> run_rank0(MPI_Comm comm, int size, const std::vector<int>& tasks,
                                  const std::function<TaskResult(int)>& compute,
                                  const std::function<void(const TaskResult&)>& on_result,
                                  const TaskFarmOptions& options) {
  Rank0State state(tasks, options.stop);
  std::exception_ptr invalid;
  try {
    validate_tasks(tasks);
  } catch (...) {
    invalid = std::current_exception();
    state.cancelled = true;  // the master then only sends the workers home
  }
  Progress progress(options, tasks.size());
  Delivery delivery(on_result, options.keep_results, tasks.size());
  std::thread master(master_loop, comm, size, std::ref(state), std::ref(progress), std::ref(delivery),
                     std::cref(options.on_stop));
  const auto deliver_inbox = [&] {
    auto delivering = delivery.lock();
    deliver_inbox_locked(state, delivery);
  };

  try {
    if (invalid) std::rethrow_exception(invalid);
    while (const std::optional<int> index = state.take()) {
      std::optional<TaskResult> result = run_one(compute, *index);
      if (result) {  // else stopped midway: not done, and nothing more is handed out
        progress.record(*result);
        auto delivering = delivery.lock();
        delivery.deliver(std::move(*result));
      }
      deliver_inbox();
    }
    while (true) {  // the queue is empty: collect the workers' last results
      bool done = false;
      {
        std::unique_lock lock(state.mutex);
        state.changed.wait(lock, [&] { return !state.inbox.empty() || state.master_done; });
        done = state.master_done;
      }
      deliver_inbox();
      if (done) break;
    }
  } catch (...) {
    state.cancel();
    master.join();
    throw;
  }
  master.join();
  if (state.master_error) std::rethrow_exception(state.master_error);
  if (delivery.delivered() != tasks.size() && !state.halted())
    throw std::logic_error("run_task_farm: " + std::to_string(delivery.delivered()) + " results for " +
                           std::to_string(tasks.size()) + " tasks");
  progress.final_report();
  std::vector<TaskResult> results = delivery.take_results();
  sort_by_index(results);
  return results;
}

// A private communicator, so the farm's messages never mix with others.
class DuplicateComm {
 public:
  explicit DuplicateComm(MPI_Comm parent) { MPI_Comm_dup(parent, &comm_); }
  ~DuplicateComm() { MPI_Comm_free(&comm_); }
  DuplicateComm(const DuplicateComm&) = delete;
  DuplicateComm& operator=(const DuplicateComm&) = delete;
  MPI_Comm get() const { return comm_; }

 private:
  MPI_Comm comm_ = MPI_COMM_NULL;
};

}  // namespace

std::string progress_line(const std::string& label, std::size_t done, std::size_t total,
                          std::size_t failed, double elapsed_s) {
  const double rate = elapsed_s > 0 ? static_cast<double>(done) / elapsed_s : 0.0;
  std::string line = label + ": " + std::to_string(done) + "/" + std::to_string(total) + " done (" +
                     std::to_string(failed) + " failed), " + format_rate(rate) + " runs/s";
  if (done < total)
    line += ", ETA " + (done == 0 || rate <= 0
                            ? std::string("?")
                            : format_duration(static_cast<double>(total - done) / rate));
  return line;
}

std::vector<TaskResult> run_task_farm(const std::vector<int>& tasks,
                                      const std::function<TaskResult(int)>& compute,
                                      const std::function<void(const TaskResult&)>& on_result,
                                      const TaskFarmOptions& options) {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  int rank = 0, size = 1;
  if (initialized && !finalized) {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
  }
  if (size == 1) return run_serial(tasks, compute, on_result, options);

  int provided = MPI_THREAD_SINGLE;
  MPI_Query_thread(&provided);
  if (provided < MPI_THREAD_SERIALIZED)
    throw std::runtime_error(
        "run_task_farm: MPI was initialised without MPI_THREAD_SERIALIZED support "
        "(use study::MpiSession)");

  const DuplicateComm comm(MPI_COMM_WORLD);
  if (rank == 0) return run_rank0(comm.get(), size, tasks, compute, on_result, options);
  worker_loop(comm.get(), compute, options.stop);
  return {};
}

}  // namespace rover::study
