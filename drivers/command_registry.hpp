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

struct CommandEntry {
  int order;
  std::string name;
  std::string description;
  CommandSetup setup;
};

std::vector<CommandEntry>& command_registry();

struct RegisterCommand {
  RegisterCommand(int order, std::string name, std::string description, CommandSetup setup) {
    command_registry().push_back({order, std::move(name), std::move(description), std::move(setup)});
  }
};

}  // namespace rover::cli
