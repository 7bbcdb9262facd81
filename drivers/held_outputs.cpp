// See held_outputs.hpp.
#include "drivers/held_outputs.hpp"

#include <filesystem>
#include <stdexcept>

#include "drivers/options.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::cli {

void HeldOutputs::hold(const std::string& flag, const std::string& path) {
  if (path.empty()) return;
  study::retire_exit_on_interrupt();  // from here on, a signal ends the command as the system does
  std::error_code error;
  // A link (/dev/stdout) or a special file is written through: its lock would
  // stand in a folder that is not the user's.
  const std::filesystem::file_status entry = std::filesystem::symlink_status(path, error);
  if (std::filesystem::exists(entry) && !std::filesystem::is_regular_file(entry)) return;
  io::create_parent_directories(path);
  try {
    locks_.push_back(std::make_unique<io::OutputLock>(path, flag));
  } catch (const std::runtime_error& e) {
    throw CommandLineError({flag + " '" + path + "': " + e.what()});
  }
}

}  // namespace rover::cli
