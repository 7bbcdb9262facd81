// What may stand at an output path, and how it is written.
//
// Result files are written to a temporary file beside the destination and
// renamed onto it, so that a failure never leaves half a file. A rename
// replaces whatever directory entry is at the path, so before any work the
// path is inspected (lstat, following no link):
//   * nothing, or a writable regular file: written by rename;
//   * a device, a pipe, a terminal, or an open descriptor
//     (/dev/stdout, /dev/fd/N, /proc/self/fd/N, or a link to one): text
//     output (CSV) is written through it in place (appended, so a shell's
//     `>>` keeps what is there); a file format that must seek (HDF5, PNG,
//     a terrain file) is refused;
//   * a symbolic link to anything else: refused (a rename would replace the
//     link by a regular file; the message names the link's target);
//   * a read-only regular file (no write permission bit, or not writable by
//     this user): refused, also for root;
//   * a directory or a socket (which no open() accepts): refused;
//   * a mount point (a file bound over the path): refused, as no rename may
//     replace it;
//   * a file name that is only an extension (".h5"): refused.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace rover::io {

enum class OutputFormat {
  kSeekable,  // HDF5, PNG, JSON terrain: needs a regular file
  kText,      // CSV: may also stream to a device, a pipe or a terminal
};

enum class OutputMode {
  kReplace,  // temporary file + rename
  kStream,   // opened in place and appended to
};

struct OutputTarget {
  OutputMode mode = OutputMode::kReplace;
  std::string refusal;  // empty if the path may be written; else why not, e.g. "is read-only (mode 0444); ..."
};

OutputTarget inspect_output(const std::string& path, OutputFormat format);

// Why the file name of `path` is only the extension of a format rover
// writes ("r/.h5", ".csv": a hidden file with no name), or empty.
std::string extension_only_refusal(const std::string& path);

// Whether a config's "name" may name a file in results/ (the default output
// results/<name>.h5): not empty, no directory separator or control
// character (a NUL ends a path), not "." or "..".
bool is_plain_file_name(const std::string& name);

// The descriptor of this process that `path` names, also through links:
// /dev/stdin 0, /dev/stdout 1, /dev/stderr 2, /dev/fd/N, /proc/self/fd/N and
// /proc/<this process>/fd/N give N; -1 for any other path. Text for such a
// path is written through the descriptor itself, so that it shares the
// file offset with whatever else writes there (`> log 2>&1`).
int own_descriptor(const std::string& path);

// inspect_output's mode; throws std::runtime_error "<path>: <refusal>" when refused.
OutputMode require_output(const std::string& path, OutputFormat format);

// The longest name rover writes beside an output "<name>": a study's
// temporary checkpoint (a writer's "<name>.partial", a lock "<name>.lock" and
// a probe "<name>.probe-<pid>" are shorter).
inline constexpr std::string_view kLongestSiblingSuffix = ".checkpoint.partial";

// Why `output`'s file name leaves no room for a file "<name><sibling_suffix>"
// beside it, in the file system of the nearest existing directory above it
// (its NAME_MAX, 255 on Linux's own), or empty. Found before any run: a
// checkpoint that cannot be created would lose the runs.
std::string name_length_refusal(const std::string& output, std::string_view sibling_suffix);

// Why the directory of `output` could not be made, or empty when it exists
// or can be: its nearest existing ancestor is a directory this process may
// write in; when it exists, a file can be created in it (found by making
// and removing "<output>.probe-<pid>": a read-only file system, /proc or
// /sys refuse it; an append-only or immutable directory is refused unprobed),
// and its name leaves room for kLongestSiblingSuffix. Leaves nothing (a refused command or a dry run leaves no
// folder).
std::string parent_directory_refusal(const std::string& output);

// Makes the missing directories above `output` (a command calls it when its
// run begins; the writers themselves never make a directory); throws
// std::runtime_error naming `output` and the directory when it cannot.
void create_parent_directories(const std::string& output);

// Makes `temporary` (a writer's "<output>.partial") a new, empty regular
// file of this process before the writer opens it: whatever stands there (a
// crashed run's leftover, a symbolic link) is removed, never followed or
// written through, and the file is created exclusively (O_EXCL). Throws
// std::runtime_error naming `output` and `temporary` when it cannot. When
// `output` is a regular file already, the temporary file gets its permission
// bits, so that the renamed output keeps them (0600 stays 0600).
void create_temporary(const std::string& temporary, const std::string& output);

// The plots written beside a result file `output` are <stem>.png and
// <stem>_*.png in its directory (results/m.h5: results/m.png,
// results/m_summary.png). For each such entry that exists and that
// inspect_output refuses (a link, a read-only file, a directory, a device),
// "<path>: <refusal>": checked before any run, so that a study never ends
// without the figure it was asked for.
std::vector<std::string> plots_beside_refused(const std::string& output);

}  // namespace rover::io
