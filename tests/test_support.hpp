// Helpers shared by the test executables: paths of the source tree and the
// built `rover` program, and running a command.
#pragma once

#include <string>

namespace rover::testing {

std::string source_path(const std::string& relative);  // <source dir>/relative
std::string rover_binary();                              // path of the built `rover`
std::string mpiexec();                                   // "mpirun --oversubscribe" (root allowed)
std::string temp_dir();  // a fresh directory for this test, removed if it passes
// The text of a file ("" if it cannot be read).
std::string read_file(const std::string& path);
// Writes `text` to `path`; returns the path.
std::string write_file(const std::string& path, const std::string& text);
// A short drop scenario (0.25 s at 200 Hz, the horizontal drop's start) in
// `dir`, so that studies run in seconds; returns its path.
std::string short_drop_scenario(const std::string& dir);
// Runs a shell command; returns its exit status and captures stdout+stderr.
int run_command(const std::string& command, std::string* output = nullptr);
// A shell command that starts `command` in the background and sends it
// `signal` ("KILL", "INT", ...) once `checkpoint` has grown past the size it
// first had: at least one record was appended after the header, whatever the
// speed of the machine. Gives up waiting after 60 s or when the command ends;
// the command's exit status is the script's.
std::string signal_once_checkpoint_grows(const std::string& command, const std::string& checkpoint,
                                         const std::string& signal);

}  // namespace rover::testing
