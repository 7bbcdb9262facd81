// The `rover` command-line program: one subcommand per task (see --help).
//
// A mistyped subcommand gets the nearest known name by the optimal string
// alignment distance (Levenshtein distance with adjacent transpositions,
// Damerau 1964): "rover simulat" -> did you mean 'simulate'? Whatever a
// subcommand printed on stdout is flushed and checked before the exit status
// is returned, so a full disk or a closed pipe is an error, not a success.
// Exit status: 0 done, 1 refused (a bad file, or a bad command line, also one
// CLI11 refuses itself, or an option given an empty value), 2 some runs
// failed (the subcommand's own), 130 interrupted.
//
// A study allocates the same few hundred kilobytes for every run (the
// trajectory's rows) and frees them at its end. glibc would hand that memory
// back to the kernel after each run (its trim and mmap thresholds) and take
// it again, zero-filled, page by page, for the next: keep_freed_memory()
// raises both thresholds so that it is reused (measured on a 2-rank drop
// study: 0.4 ms of system time a run, 3.6 % of its wall time).
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <exception>
#include <iostream>
#include <map>
#include <string_view>
#include <vector>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "drivers/command_registry.hpp"
#include "drivers/options.hpp"
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

// Optimal string alignment distance: insertions, deletions, substitutions and
// transpositions of adjacent characters, each costing 1.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + substitution});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

// "unknown subcommand 'simulat'; did you mean 'simulate'?" (or the list of
// subcommands when none is near).
std::string unknown_subcommand_message(const std::string& typed,
                                       const std::vector<CommandEntry>& registry) {
  std::string nearest, names;
  std::size_t best = std::string::npos;
  for (const CommandEntry& entry : registry) {
    names += (names.empty() ? "" : ", ") + entry.name;
    const std::size_t distance = edit_distance(typed, entry.name);
    if (distance < best) {
      best = distance;
      nearest = entry.name;
    }
  }
  std::string message = "rover: unknown subcommand '" + typed + "'";
  // Near: at most 2 edits, or a third of the name for long names.
  if (best <= std::max<std::size_t>(2, nearest.size() / 3)) return message + "; did you mean '" + nearest + "'?";
  return message + " (subcommands: " + names + ")";
}

// An option given an empty value (`--f ""`, typically an unset shell
// variable) is an error, never the option's default: CLI11 reads an empty
// value into an optional number as "not given".
void collect_empty_values(const CLI::App& app, FlagChecks& checks) {
  for (const CLI::Option* option : app.get_options()) {
    if (option->count() == 0 || option->get_expected_max() == 0) continue;  // not given, or a flag
    for (const std::string& value : option->results())
      if (value.find_first_not_of(" \t") == std::string::npos)
        checks.add(option->get_name() + " was given an empty value");
  }
  for (const CLI::App* sub : app.get_subcommands()) collect_empty_values(*sub, checks);
}

void reject_empty_values(const CLI::App& app) {
  FlagChecks checks;
  collect_empty_values(app, checks);
  checks.throw_if_any();
}

}  // namespace
}  // namespace rover::cli

int main(int argc, char** argv) {
  using namespace rover::cli;
  keep_freed_memory();
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
  for (auto& entry : registry) {
    CLI::App* sub = app.add_subcommand(entry.name, entry.description);
    runners[sub] = entry.setup(*sub);
  }
  if (argc > 1 && argv[1][0] != '-' &&
      std::none_of(registry.begin(), registry.end(),
                   [&](const CommandEntry& entry) { return entry.name == argv[1]; })) {
    std::cerr << unknown_subcommand_message(argv[1], registry) << "\nRun 'rover --help' for the list.\n";
    return 1;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every refused command line exits 1, as a
    // refused config file does (CLI11's own codes, 101-115, are not documented).
    return app.exit(e) == 0 ? 0 : 1;
  }
  for (auto& [sub, run] : runners) {
    if (!sub->parsed()) continue;
    const std::string prefix = "rover " + sub->get_name() + ": error: ";
    int status = 1;
    try {
      reject_empty_values(*sub);
      status = run();
    } catch (const CommandLineError& e) {
      for (const std::string& problem : e.problems()) std::cerr << prefix << problem << "\n";
      return 1;
    } catch (const rover::study::StudyInterrupted& e) {
      std::cerr << "rover " << sub->get_name() << ": " << e.what() << "\n";
      return rover::study::StudyInterrupted::kExitCode;
    } catch (const std::exception& e) {
      std::cerr << prefix << e.what() << "\n";
      return 1;
    }
    std::cout.flush();
    if (!std::cout) {
      std::cerr << prefix << "cannot write to standard output" << (errno ? std::string(" (") + std::strerror(errno) + ")" : "") << "\n";
      return 1;
    }
    return status;
  }
  return 1;
}
