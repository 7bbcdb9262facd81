// Self-registering subcommands of the `rover` program.
//
// Each subcommand lives in its own file (cmd_<name>.cpp) and registers itself
// with a static RegisterCommand object: a sort key (its place in --help), and a
// function that adds the CLI11 subcommand and returns the code to run.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace rover::cli {

// Adds the subcommand's options to `app`; the returned function runs it and
// returns the process exit code.
using CommandSetup = std::function<std::function<int()>(CLI::App& app)>;

// Whether a subcommand shares its work among the ranks of mpirun (the
// studies) or runs on one process: under mpirun with more than one process a
// one-process subcommand is refused before it reads or writes anything
// (docs/cluster.md), so that no output is written twice.
enum class Processes { kOne, kMany };

struct CommandEntry {
  int order;
  std::string name;
  std::string description;
  CommandSetup setup;
  Processes processes = Processes::kOne;
};

std::vector<CommandEntry>& command_registry();

struct RegisterCommand {
  RegisterCommand(int order, std::string name, std::string description, CommandSetup setup,
                  Processes processes = Processes::kOne) {
    command_registry().push_back({order, std::move(name), std::move(description), std::move(setup), processes});
  }
};

}  // namespace rover::cli
