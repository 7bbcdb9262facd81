// The `rover` command-line program: one subcommand per task (see --help).
#include <algorithm>
#include <exception>
#include <iostream>
#include <map>

#include "drivers/command_registry.hpp"

namespace rover::cli {
std::vector<CommandEntry>& command_registry() {
  static std::vector<CommandEntry> registry;
  return registry;
}
}  // namespace rover::cli

int main(int argc, char** argv) {
  using namespace rover::cli;
  CLI::App app{
      "rover: semi-analytical dynamics of the Archimede rover (Caruso et al.) and the\n"
      "uncertainty/sensitivity studies built on it. Model: ../shared/MODEL.md.\n"
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
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  for (auto& [sub, run] : runners) {
    if (sub->parsed()) {
      try {
        return run();
      } catch (const std::exception& e) {
        std::cerr << "rover " << sub->get_name() << ": error: " << e.what() << "\n";
        return 1;
      }
    }
  }
  return 1;
}
