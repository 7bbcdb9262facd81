// The command that resumes a study (study_options.hpp): the flags the user
// gave, in the order given, so every study's hint has the same form.
#include <set>
#include <string>

#include "drivers/study_options.hpp"

namespace rover::cli {
namespace {

// A word the shell reads back as itself.
std::string shell_word(const std::string& word) {
  if (!word.empty() && word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
                                              "_-+=./,:@%") == std::string::npos)
    return word;
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace

std::string resume_command(const CLI::App& subcommand) {
  std::string command = "rover " + subcommand.get_name();
  std::set<const CLI::Option*> given;
  for (const CLI::Option* option : subcommand.parse_order()) {
    const std::string name = option->get_name(false, true);
    if (!given.insert(option).second || name == "--resume") continue;
    command += " " + name;
    if (option->get_expected_max() == 0) continue;  // a flag
    for (const std::string& value : option->results()) command += " " + shell_word(value);
  }
  return command + " --resume";
}

}  // namespace rover::cli
