// The `rover` command-line program: one subcommand per task (see --help).
//
// A mistyped subcommand gets the nearest known name, and a refused command
// line a message in rover's words (command_line_errors.hpp). Whatever a
// subcommand printed on stdout is flushed and checked before the exit status
// is returned, so a full disk or a closed pipe is an error, not a success.
// Exit status: 0 done, 1 refused (a bad file, or a bad command line, also one
// CLI11 refuses itself, or an option given an empty value), 2 some runs
// failed (the subcommand's own), 130 interrupted (also while it reads its
// inputs, perhaps waiting on a pipe).
//
// A study allocates the same few hundred kilobytes for every run (the
// trajectory's rows) and frees them at its end. glibc would hand that memory
// back to the kernel after each run (its trim and mmap thresholds) and take
// it again, zero-filled, page by page, for the next: keep_freed_memory()
// raises both thresholds so that it is reused (measured on a 2-rank drop
// study: 0.4 ms of system time a run, 3.6 % of its wall time).
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <map>
#include <new>
#include <optional>
#include <vector>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "drivers/command_line_errors.hpp"
#include "drivers/command_registry.hpp"
#include "drivers/launcher.hpp"
#include "drivers/options.hpp"
#include "io/decimal_number.hpp"
#include "io/json_reader.hpp"
#include "study/runtime/mpi_session.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::cli {
std::vector<CommandEntry>& command_registry() {
  static std::vector<CommandEntry> registry;
  return registry;
}
namespace {

void keep_freed_memory() {
#ifdef __GLIBC__
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

// "unknown subcommand 'simulat'; did you mean 'simulate'?" (or the list of
// subcommands when none is near).
std::string unknown_subcommand_message(const std::string& typed,
                                       const std::vector<CommandEntry>& registry) {
  std::vector<std::string> names;
  for (const CommandEntry& entry : registry) names.push_back(entry.name);
  const std::string message = "rover: unknown subcommand '" + typed + "'";
  if (const std::string near = nearest_name(typed, names); !near.empty())
    return message + "; did you mean '" + near + "'?";
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
  return message + " (subcommands: " + list + ")";
}

// Whether `word` is the name of one of `app`'s options ("--no-plot").
bool is_option_name(const CLI::App& app, const std::string& word) {
  if (!word.starts_with("--")) return false;
  for (const CLI::Option* option : app.get_options())
    for (const std::string& name : option->get_lnames())
      if (word == "--" + name) return true;
  return false;
}

// An option given an empty value (`--f ""`, typically an unset shell
// variable) is an error, never the option's default: CLI11 reads an empty
// value into an optional number as "not given". So is an option whose value
// is the next option (`--out --no-plot`: CLI11 takes "--no-plot" as the file).
void collect_empty_values(const CLI::App& app, FlagChecks& checks) {
  for (const CLI::Option* option : app.get_options()) {
    if (option->count() == 0 || option->get_expected_max() == 0) continue;  // not given, or a flag
    for (const std::string& value : option->results())
      if (value.find_first_not_of(" \t") == std::string::npos)
        checks.add(option->get_name() + " was given an empty value");
      else if (is_option_name(app, value))
        checks.add(option->get_name() + " " + std::string(kGivenNoValue) + ": the word after it, '" + value +
                   "', is an option of its own");
  }
  for (const CLI::App* sub : app.get_subcommands()) collect_empty_values(*sub, checks);
}

// An integer flag takes what a JSON config takes for a count or a seed
// (io::exact_unsigned_integer): digits, or an integral number written in
// exponent or decimal form up to 2^53 (--samples 1e3 is 1000, as --seed 1e3
// and "samples": 1e3 are); 2.5 or 1e-3 are refused as not whole, and 0x10 or
// 0b11 (which CLI11 reads as hexadecimal or binary) as not decimal.
void read_integral_numbers_as_integers(CLI::App& app) {
  for (CLI::Option* option : app.get_options()) {
    const std::string type = option->get_type_name();  // "INT:INT in [2 - 100000000]" with a range
    if (!type.starts_with("INT") && !type.starts_with("UINT")) continue;
    std::string range;  // ", from 2 to 100000000"
    if (const std::size_t open = type.find(" in ["), dash = type.find(" - ", open), close = type.find(']', open);
        open != std::string::npos && dash != std::string::npos && close != std::string::npos)
      range = ", from " + type.substr(open + 5, dash - open - 5) + " to " + type.substr(dash + 3, close - dash - 3);
    option->transform(CLI::Validator(
        [range](std::string& text) {
          const bool negative = text.starts_with('-');
          io::Json number;
          try {
            number = io::parse_json_text(text.substr(negative ? 1 : 0), "flag");
          } catch (const io::ConfigError&) {  // 0x10, 1_000: CLI11 would read some of these
            number = io::Json();
          }
          if (text.starts_with("--"))  // `--samples --dry-run`: CLI11 took the next option as the value
            return std::string(kGivenNoValue) + ": the word after it, '" + text + "', is an option of its own";
          if (!number.is_number())
            return text.empty() ? std::string()
                                : "must be a whole number in decimal digits (as 1000 or 1e3)" + range + ", got " + text;
          const auto value = io::exact_unsigned_integer(number);
          if (!value)  // beyond 2^53 (1e30) the flag's range says so
            return std::trunc(number.get<double>()) == number.get<double>() ? std::string()
                                                                           : "must be a whole number" + range + ", got " + text;
          text = (negative ? "-" : "") + std::to_string(*value);
          return std::string();
        },
        "", "integral"));
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) read_integral_numbers_as_integers(*sub);
}

// A real-valued flag takes decimal digits as a JSON config does: CLI11 would
// also read C's hexadecimal floats (--cq 0x1p-3 as 0.125).
void read_real_numbers_in_decimal(CLI::App& app) {
  for (CLI::Option* option : app.get_options()) {
    if (!option->get_type_name().starts_with("FLOAT")) continue;
    option->check(CLI::Validator(
        [](std::string& text) {
          if (!io::is_hexadecimal_number(text)) return std::string();
          return "must be a number in decimal digits (as 0.125 or 1.25e-1), got " + text;
        },
        "", "decimal"));
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) read_real_numbers_in_decimal(*sub);
}

void reject_empty_values(const CLI::App& app) {
  FlagChecks checks;
  collect_empty_values(app, checks);
  checks.throw_if_any();
}

// Prints `lines` on stderr in one write, so that the messages of several
// ranks never interleave within a line.
void print_lines(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  std::cerr << text << std::flush;
}

// A problem of the command line or of an input file: under mpirun every rank
// checks the same arguments and files and finds the same problem, so rank 0
// alone reports it; another rank keeps its lines in `held`, to print them if
// it finds itself alone in refusing. Other errors (a rank's own) are
// reported by the rank, which then names itself.
void report_input_problem(const std::vector<std::string>& lines, std::vector<std::string>* held = nullptr) {
  if (launcher_rank() == 0)
    print_lines(lines);
  else if (held != nullptr)
    held->insert(held->end(), lines.begin(), lines.end());
}
std::string rank_label() {
  const int rank = launcher_rank();
  return rank == 0 ? "" : "(rank " + std::to_string(rank) + ") ";
}
void report_error(const std::string& prefix, const std::string& what) {
  print_lines({prefix + rank_label() + what});
}

// The subcommands typed, as far as CLI11 knows them: "simulate", "terrain
// obstacle" (for the message of a refused command line).
std::string typed_subcommands(const CLI::App& app, int argc, char** argv) {
  std::string command;
  const CLI::App* level = &app;
  for (int i = 1; i < argc && level != nullptr; ++i) {
    const CLI::App* next = nullptr;
    for (const CLI::App* sub : level->get_subcommands([](const CLI::App*) { return true; }))
      if (sub->get_name() == argv[i]) next = sub;
    if (next != nullptr) command += (command.empty() ? "" : " ") + next->get_name();
    level = next;
  }
  return command;
}

// Runs the parsed subcommand `sub`: its exit status, or 1 with rover's
// message for every error (130 when a study was interrupted). A refusal of
// the inputs that rank 0 does not print is kept in `held`.
int run_reporting_errors(CLI::App& sub, const std::function<int()>& run, std::vector<std::string>& held) {
  const std::string prefix = "rover " + sub.get_name() + ": error: ";
  int status = 1;
  try {
    reject_empty_values(sub);
    status = run();
  } catch (const CommandLineError& e) {
    std::vector<std::string> lines;
    for (const std::string& problem : e.problems()) lines.push_back(prefix + problem);
    report_input_problem(lines, &held);
    return 1;
  } catch (const rover::study::StudyInterrupted& e) {
    std::cerr << "rover " << sub.get_name() << ": " << e.what() << "\n";
    return rover::study::StudyInterrupted::kExitCode;
  } catch (const rover::io::ConfigError& e) {
    report_input_problem({prefix + e.what()}, &held);
    return 1;
  } catch (const std::invalid_argument& e) {  // refused before any run
    report_input_problem({prefix + e.what()}, &held);
    return 1;
  } catch (const std::bad_alloc&) {
    const bool has_samples = sub.get_option_no_throw("--samples") != nullptr;
    report_error(prefix, "out of memory while running rover " + sub.get_name() +
                             ": its inputs ask for more than this process may hold (physical memory, ulimit -v); " +
                             (has_samples ? "reduce --samples or the study's size"
                                          : "reduce the run's size (the scenario's duration or output_rate)"));
    return 1;
  } catch (const std::exception& e) {
    report_error(prefix, e.what());
    return 1;
  }
  std::cout.flush();
  // A study stopped by a closed output pipe (SIGPIPE) keeps its status 130.
  if (!std::cout && status != rover::study::StudyInterrupted::kExitCode) {
    std::cerr << prefix << "cannot write to standard output" << (errno ? std::string(" (") + std::strerror(errno) + ")" : "") << "\n";
    return 1;
  }
  return status;
}

// Meets the other ranks on the way out (MpiSession::meet_on_exit); a rank
// that stopped `early` (it refused, or was given --help) while they went on
// prints its `held` lines, named, and ends the job.
void leave_together(rover::study::MpiSession& mpi, int status, bool early, std::vector<std::string> held,
                    const std::string& command) {
  if (mpi.meet_on_exit(early)) return;
  held.push_back(command + ": error: the other ranks did not stop here and went on to the runs; ending the job");
  for (std::string& line : held) line = rank_label() + line;
  print_lines(held);
  std::cout.flush();
  mpi.end_job(status == 0 ? 1 : status);
}

// Runs `sub`; under mpirun a command that shares its runs (`shares_runs`)
// holds MPI until every rank has reached its exit, so that rank 0 prints
// before mpirun ends the job on another rank's exit. A rank that refused
// alone, while the others went on to the runs, prints its held message and
// ends the job instead of leaving them waiting.
int run_subcommand(CLI::App& sub, const std::function<int()>& run, bool shares_runs) {
  std::optional<rover::study::MpiSession> mpi;
  try {
    if (shares_runs && launcher_size() > 1) mpi.emplace(nullptr, nullptr);
  } catch (const std::invalid_argument& e) {  // an environment MPI could not start with
    // Said by every rank that has it: without MPI no rank can tell whether
    // the others have it too (an environment set for one rank only).
    report_error("rover " + sub.get_name() + ": error: ", e.what());
    return 1;
  }
  std::vector<std::string> held;
  const int status = run_reporting_errors(sub, run, held);
  if (mpi) leave_together(*mpi, status, status == 1, held, "rover " + sub.get_name());
  return status;
}

// Ends, with `status`, a command that stopped before any subcommand ran (a
// refused command line, --help, --version). Under mpirun the ranks meet as
// run_subcommand's do, so that a rank stopping alone (an MPMD launch that
// gave it another command line) says why, with its `held` lines, and ends
// the job, while a stop that every rank shares is reported once, by rank 0.
int stop_before_subcommand(int status, const std::vector<std::string>& held) {
  if (launcher_size() <= 1) return status;
  std::optional<rover::study::MpiSession> mpi;
  try {
    mpi.emplace(nullptr, nullptr);
  } catch (const std::invalid_argument& e) {  // an environment MPI could not start with (as above)
    report_error("rover: error: ", e.what());
    return 1;
  }
  leave_together(*mpi, status, /*early=*/true, held, "rover");
  return status;
}

// A command line refused before any subcommand ran: exit status 1.
int refuse_command_line(const std::vector<std::string>& lines) {
  std::vector<std::string> held;
  report_input_problem(lines, &held);
  return stop_before_subcommand(1, held);
}

// --help or --version: printed by rank 0 (or alone), exit status 0.
int print_help(const CLI::App& app, const CLI::Success& request) {
  if (launcher_rank() == 0) return stop_before_subcommand(app.exit(request), {});
  return stop_before_subcommand(0, {"rover: error: this rank was given --help or --version and runs nothing"});
}

}  // namespace
}  // namespace rover::cli

int main(int argc, char** argv) {
  using namespace rover::cli;
  keep_freed_memory();
  // Reading inputs, perhaps from a pipe: a signal gives 130 and a word; a
  // closed output pipe fails the write (reported), instead of killing.
  rover::study::exit_on_interrupt_until_guarded();
  CLI::App app{
      "rover: semi-analytical dynamics of the Archimede rover (Caruso et al.) and the\n"
      "uncertainty/sensitivity studies built on it. Model: docs/model.md.\n"
      "Run `rover <subcommand> --help` for the options and an example of each subcommand."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string(ROVER_VERSION));
  auto& registry = command_registry();
  std::sort(registry.begin(), registry.end(),
            [](const CommandEntry& a, const CommandEntry& b) { return a.order < b.order; });
  std::map<CLI::App*, std::function<int()>> runners;
  std::map<CLI::App*, Processes> processes;
  std::string shared_among_processes;  // "montecarlo, sensitivity, ..."
  for (auto& entry : registry) {
    CLI::App* sub = app.add_subcommand(entry.name, entry.description);
    runners[sub] = entry.setup(*sub);
    processes[sub] = entry.processes;
    if (entry.processes == Processes::kMany)
      shared_among_processes += (shared_among_processes.empty() ? "" : ", ") + entry.name;
  }
  read_integral_numbers_as_integers(app);
  read_real_numbers_in_decimal(app);
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (const std::vector<std::string> lines = typed_word_error_lines(args, app, typed_subcommands(app, argc, argv));
      !lines.empty())
    return refuse_command_line(lines);
  if (argc > 1 && argv[1][0] != '-' &&
      std::none_of(registry.begin(), registry.end(),
                   [&](const CommandEntry& entry) { return entry.name == argv[1]; }))
    return refuse_command_line({unknown_subcommand_message(argv[1], registry), "Run 'rover --help' for the list."});
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return print_help(app, e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    // Every refused command line exits 1, as a refused config file does
    // (CLI11's own codes, 101-115, are not documented), in rover's words.
    return refuse_command_line(command_line_error_lines(e, app, typed_subcommands(app, argc, argv), args));
  }
  for (auto& [sub, run] : runners) {
    if (!sub->parsed()) continue;
    if (const int size = launcher_size(); size > 1 && processes[sub] == Processes::kOne) {
      return refuse_command_line({"rover " + sub->get_name() + ": error: " + one_process_refusal(size) + "; only " +
                                  shared_among_processes + " share their runs among processes"});
    }
    return run_subcommand(*sub, run, processes[sub] == Processes::kMany);
  }
  return 1;
}
