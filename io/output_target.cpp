// See output_target.hpp.
#include "io/output_target.hpp"

#include <fcntl.h>
#include <linux/fs.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <system_error>

namespace rover::io {
namespace {

// ASCII control characters (a newline, a tab, DEL); bytes of UTF-8 are not.
bool is_control_byte(char c) {
  const auto byte = static_cast<unsigned char>(c);
  return byte < 0x20 || byte == 0x7f;
}
// "0x0a"
std::string byte_text(unsigned char byte) {
  char text[8];
  std::snprintf(text, sizeof text, "0x%02x", byte);
  return text;
}

// "immutable" or "append-only" for a file with that attribute (chattr +i,
// +a), which neither rename nor unlink may replace; empty otherwise or where
// the file system keeps no such attributes.
std::string locking_file_attribute(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return "";
  int flags = 0;
  const bool known = ::ioctl(fd, FS_IOC_GETFLAGS, &flags) == 0;
  ::close(fd);
  if (!known) return "";
  if ((flags & FS_IMMUTABLE_FL) != 0) return "immutable";
  if ((flags & FS_APPEND_FL) != 0) return "append-only";
  return "";
}

namespace fs = std::filesystem;

// Linux follows at most 40 links in a path.
constexpr int kMaxLinkHops = 40;
// The read, write and execute bits of owner, group and others (no set-id or
// sticky bit is carried over to a replacement).
constexpr mode_t kPermissionBits = 0777;

// /dev/stdout, /dev/fd/N, /proc/self/fd/N and the like: a name of an open
// descriptor, whose "link" is no file to replace.
bool names_descriptor(const fs::path& absolute) {
  const std::string s = absolute.lexically_normal().string();
  if (s == "/dev/stdin" || s == "/dev/stdout" || s == "/dev/stderr") return true;
  if (s.rfind("/dev/fd/", 0) == 0) return true;
  return s.rfind("/proc/", 0) == 0 && s.find("/fd/") != std::string::npos;
}

// The first descriptor's name passed by following the links from `path`
// (lexically normal), or empty.
std::string descriptor_name_reached(const std::string& path) {
  std::error_code error;
  fs::path p = fs::absolute(path, error);
  if (error) return "";
  for (int hop = 0; hop < kMaxLinkHops; ++hop) {
    if (names_descriptor(p)) return p.lexically_normal().string();
    if (!fs::is_symlink(fs::symlink_status(p, error))) return "";
    const fs::path target = fs::read_symlink(p, error);
    if (error) return "";
    p = target.is_absolute() ? target : p.parent_path() / target;
  }
  return "";
}

bool reaches_descriptor(const std::string& path) { return !descriptor_name_reached(path).empty(); }

// N of "<prefix>N" (digits only), or -1.
int number_after(const std::string& text, const std::string& prefix) {
  if (text.rfind(prefix, 0) != 0 || text.size() == prefix.size() || text.size() - prefix.size() > 9) return -1;
  const std::string digits = text.substr(prefix.size());
  if (digits.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stoi(digits);
}

std::string octal_mode(mode_t mode) {
  char text[8];
  std::snprintf(text, sizeof text, "%04o", static_cast<unsigned>(mode & 07777));
  return text;
}

// The mount points of this process's mount namespace, as /proc/self/mountinfo
// lists them (its fifth field, with the octal escapes \040 of spaces and the
// like decoded).
std::vector<std::string> mount_points() {
  std::vector<std::string> points;
  std::ifstream mountinfo("/proc/self/mountinfo");
  for (std::string line; std::getline(mountinfo, line);) {
    std::istringstream fields(line);
    std::string id, parent, device, root, point;
    if (!(fields >> id >> parent >> device >> root >> point)) continue;
    std::string decoded;
    for (std::size_t i = 0; i < point.size(); ++i) {
      const bool escape = point[i] == '\\' && i + 3 < point.size() &&
                          point.substr(i + 1, 3).find_first_not_of("01234567") == std::string::npos;
      if (escape) {
        decoded += static_cast<char>(std::stoi(point.substr(i + 1, 3), nullptr, 8));
        i += 3;
      } else {
        decoded += point[i];
      }
    }
    points.push_back(decoded);
  }
  return points;
}

// Whether something is mounted at `path` itself (mount --bind of a file onto
// it): no rename may replace a mount point (EBUSY).
bool is_mount_point(const std::string& path) {
  std::error_code error;
  const fs::path resolved = fs::canonical(path, error);
  if (error) return false;
  const std::vector<std::string> points = mount_points();
  return std::find(points.begin(), points.end(), resolved.string()) != points.end();
}

OutputTarget refused(std::string why) { return {OutputMode::kReplace, std::move(why)}; }

// What a writer appends to its output's name for the temporary file.
constexpr std::string_view kTemporarySuffix = ".partial";

constexpr const char* kNeedsFile =
    "this output is written to a temporary file and renamed into place, which needs a regular "
    "file: give a file name";

// A path that streams: text goes through it, a seekable format is refused.
OutputTarget stream_target(OutputFormat format, const std::string& what) {
  if (format == OutputFormat::kSeekable) return refused("is not a regular file but " + what + "; " + kNeedsFile);
  return {OutputMode::kStream, ""};
}

}  // namespace

OutputTarget inspect_output(const std::string& path, OutputFormat format) {
  if (path.empty()) return refused("is an empty path");
  if (const auto control = std::find_if(path.begin(), path.end(), is_control_byte); control != path.end())
    return refused("holds a control character (byte " + byte_text(static_cast<unsigned char>(*control)) +
                   " at position " + std::to_string(control - path.begin() + 1) +
                   "), which every listing and message of the file would show garbled: give a name without one");
  // "dir/", "dir/." or "..": a directory, existing or not (nothing is made for it).
  if (const fs::path name = fs::path(path).filename(); name.empty() || name == "." || name == "..")
    return refused("names a directory; give a file name");
  if (const std::string refusal = extension_only_refusal(path); !refusal.empty()) return refused(refusal);
  if (path.ends_with(kTemporarySuffix))
    return refused("ends in " + std::string(kTemporarySuffix) + ", the name of a writer's temporary file, which the " +
                   "next write beside it would remove: give another name");
  std::error_code error;
  const fs::file_status own = fs::symlink_status(path, error);
  if (reaches_descriptor(path)) {
    if (!fs::exists(fs::status(path, error))) return refused("names a descriptor that is not open");
    if (const int fd = own_descriptor(path); fd >= 0) {
      const int flags = ::fcntl(fd, F_GETFL);
      if (flags < 0) return refused("names descriptor " + std::to_string(fd) + ", which is not open");
      if ((flags & O_ACCMODE) == O_RDONLY)
        return refused("names descriptor " + std::to_string(fd) + ", which is open for reading only");
    } else if (fs::is_regular_file(fs::status(path, error))) {
      // Opened anew, the file would be written from its own offset, over
      // what the other process writes there.
      return refused("names another process's descriptor of the file '" + fs::canonical(path, error).string() +
                     "'; give that file's path, or /dev/stdout for this command's own output");
    }
    return stream_target(format, "an open descriptor (such as standard output)");
  }
  if (fs::is_symlink(own)) {
    const fs::path target = fs::read_symlink(path, error);
    const bool dangling = !fs::exists(fs::status(path, error));
    return refused("is a symbolic link (to '" + target.string() + "'" + (dangling ? ", which does not exist" : "") +
                   "); writing by rename would replace the link by a file: give the target's path or "
                   "another name");
  }
  if (const std::string temporary = path + std::string(kTemporarySuffix);
      fs::is_directory(fs::symlink_status(temporary, error)))
    return refused("would be written to the temporary file " + temporary + " first, but a directory is there: "
                   "remove it, or give another name");
  if (!fs::exists(own)) return {};
  if (fs::is_directory(own)) return refused("is a directory; give a file name");
  if (fs::is_character_file(own) || fs::is_block_file(own)) return stream_target(format, "a device");
  if (fs::is_fifo(own)) return stream_target(format, "a pipe");
  if (fs::is_socket(own)) return refused("is a socket, which cannot be opened as a file; give a file name");
  if (!fs::is_regular_file(own)) return stream_target(format, "a socket or another special file");
  if (const std::string attribute = locking_file_attribute(path); !attribute.empty())
    return refused("is " + attribute + " (lsattr shows it): no program can replace it, whatever its mode; an "
                   "existing result that is not writable is never replaced: give another name, or clear the "
                   "attribute (chattr)");
  if (is_mount_point(path))
    return refused("is a mount point (a file mounted over this path, as by mount --bind): no program can replace "
                   "it by rename; give another name");
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && ((st.st_mode & 0222) == 0 || ::access(path.c_str(), W_OK) != 0))
    return refused("is read-only (mode " + octal_mode(st.st_mode) +
                   "); an existing result that is not writable is never replaced: make it writable "
                   "(chmod u+w) or give another name");
  return {};
}

std::string extension_only_refusal(const std::string& path) {
  static constexpr std::array<std::string_view, 6> kWrittenExtensions{".h5", ".hdf5", ".csv", ".json", ".png",
                                                                      ".pdf"};
  std::string name = fs::path(path).filename().string();
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (std::find(kWrittenExtensions.begin(), kWrittenExtensions.end(), name) == kWrittenExtensions.end()) return "";
  const std::string typed = fs::path(path).filename().string();
  return "has no name before its extension " + typed + ": give the file a name, such as '" +
         (fs::path(path).parent_path() / ("result" + typed)).string() + "'";
}

int own_descriptor(const std::string& path) {
  const std::string name = descriptor_name_reached(path);
  if (name == "/dev/stdout") return STDOUT_FILENO;
  if (name == "/dev/stderr") return STDERR_FILENO;
  if (name == "/dev/stdin") return STDIN_FILENO;
  if (const int fd = number_after(name, "/dev/fd/"); fd >= 0) return fd;
  if (const int fd = number_after(name, "/proc/self/fd/"); fd >= 0) return fd;
  return number_after(name, "/proc/" + std::to_string(::getpid()) + "/fd/");
}

namespace {

// The longest file name where a file system does not say (Linux's NAME_MAX).
constexpr long kDefaultNameMax = 255;

// Why no file can be made beside `output` in its existing directory (a
// read-only file system, /proc, /sys; permissions alone do not tell), found
// by making one under a name of this process and removing it; empty when one can.
// An append-only or immutable directory is refused unprobed: a result is
// written under a temporary name and renamed, which neither allows.
// What a probe says when another process (another MPI rank of the same job,
// probing the same path) made or removed the directory under it: look again.
constexpr std::string_view kProbeRaced = "\x01probe raced";
constexpr int kProbeAttempts = 5;

std::string creation_refusal(const std::string& output) {
  const fs::path dir = fs::path(output).parent_path();
  const std::string dir_name = dir.empty() ? std::string(".") : dir.string();
  if (const std::string attribute = locking_file_attribute(dir_name); !attribute.empty())
    return "the directory '" + dir_name + "' is " + attribute + " (lsattr -d shows it): rover writes a file " +
           "under a temporary name and renames it, which such a directory does not allow: clear the attribute " +
           "(chattr) or write elsewhere";
  const std::string probe = output + ".probe-" + std::to_string(::getpid());
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd < 0) {
    if (errno == EEXIST) return "";
    if (errno == ENOENT && !dir.empty() && !fs::is_directory(dir)) return std::string(kProbeRaced);  // another rank's probe removed it
    return "no file can be created in '" + dir_name + "' (" + std::strerror(errno) + ")";
  }
  ::close(fd);
  ::unlink(probe.c_str());
  return "";
}

}  // namespace

std::string name_length_refusal(const std::string& output, std::string_view sibling_suffix) {
  const fs::path path(output);
  std::error_code error;
  fs::path existing = path.parent_path();
  while (!existing.empty() && !fs::is_directory(existing, error)) existing = existing.parent_path();
  long name_max = ::pathconf(existing.empty() ? "." : existing.c_str(), _PC_NAME_MAX);
  if (name_max <= 0) name_max = kDefaultNameMax;
  const std::string name = path.filename().string();
  if (name.size() + sibling_suffix.size() <= static_cast<std::size_t>(name_max)) return "";
  return "its file name has " + std::to_string(name.size()) + " characters; rover writes a file beside it whose " +
         "name is " + std::to_string(sibling_suffix.size()) + " characters longer (<name>" +
         std::string(sibling_suffix) + "), and this file system allows " + std::to_string(name_max) +
         ": give a name of at most " + std::to_string(name_max - static_cast<long>(sibling_suffix.size())) +
         " characters";
}

namespace {

// parent_directory_refusal's one look at the path (kProbeRaced if another
// process changed it meanwhile).
std::string parent_directory_refusal_once(const std::string& output) {
  std::error_code error;
  fs::path dir = fs::path(output).parent_path();
  if (dir.empty()) {
    if (const std::string refusal = name_length_refusal(output, kLongestSiblingSuffix); !refusal.empty())
      return refusal;
    return creation_refusal(output);
  }
  fs::path existing = dir;
  while (!existing.empty() && !fs::exists(existing, error)) existing = existing.parent_path();
  if (existing.empty()) existing = ".";
  if (!fs::is_directory(existing, error))
    return "cannot create the directory '" + dir.string() + "' ('" + existing.string() +
           "' is a file, not a directory)";
  if (const std::string refusal = name_length_refusal(output, kLongestSiblingSuffix); !refusal.empty())
    return refusal;
  if (existing == dir) return creation_refusal(output);
  // Whether the first missing directory can be made is found by making it
  // and removing it again (permissions alone do not tell: root, /proc).
  fs::path first = dir;
  while (first.parent_path() != existing && !first.parent_path().empty()) first = first.parent_path();
  if (fs::is_symlink(fs::symlink_status(first, error)))  // exists() followed it to nothing
    return "cannot create the directory '" + dir.string() + "': '" + first.string() +
           "' is a symbolic link to '" + fs::read_symlink(first, error).string() +
           "', which does not exist; create its target or give another path";
  if (::mkdir(first.c_str(), 0777) != 0) {
    const int failure = errno;
    // Made meanwhile, or its parent (another process's probe) removed meanwhile.
    if ((failure == EEXIST && !fs::is_regular_file(fs::symlink_status(first, error))) ||
        (failure == ENOENT && !fs::is_directory(first.parent_path(), error)))
      return std::string(kProbeRaced);
    return "cannot create the directory '" + dir.string() + "' (" + std::strerror(failure) + ")";
  }
  fs::remove(first, error);
  return "";
}

}  // namespace

std::string parent_directory_refusal(const std::string& output) {
  // The ranks of an MPI job probe the same path at once: one's directory can
  // appear or vanish under another's look, which is then taken again.
  for (int attempt = 0; attempt < kProbeAttempts; ++attempt)
    if (std::string refusal = parent_directory_refusal_once(output); refusal != kProbeRaced) return refusal;
  return "";  // made and removed by others all along: it can be made
}

void create_parent_directories(const std::string& output) {
  const fs::path dir = fs::path(output).parent_path();
  if (dir.empty()) return;
  std::error_code error;
  fs::create_directories(dir, error);
  if (error || !fs::is_directory(dir, error))
    throw std::runtime_error(output + ": cannot create the directory '" + dir.string() + "'" +
                             (error ? " (" + error.message() + ")" : std::string()));
}

void create_temporary(const std::string& temporary, const std::string& output) {
  std::error_code error;
  const fs::file_status there = fs::symlink_status(temporary, error);
  if (fs::exists(there) && !fs::is_directory(there)) fs::remove(temporary, error);  // a link itself, not its target
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0)
    throw std::runtime_error(output + ": cannot create the temporary file '" + temporary + "': " +
                             std::strerror(errno));
  // The file it will replace keeps its permissions (a private 0600 stays
  // private); a new output gets 0644 less the umask.
  struct stat replaced {};
  if (::stat(output.c_str(), &replaced) == 0 && S_ISREG(replaced.st_mode) &&
      ::fchmod(fd, replaced.st_mode & kPermissionBits) != 0) {
    const int error_number = errno;
    ::close(fd);
    throw std::runtime_error(output + ": cannot give the temporary file '" + temporary + "' the permissions of " +
                             output + ": " + std::strerror(error_number));
  }
  ::close(fd);
}

std::vector<std::string> plots_beside_refused(const std::string& output) {
  std::vector<std::string> problems;
  if (output.empty()) return problems;
  const fs::path out(output);
  const fs::path dir = out.parent_path();
  const std::string stem = out.stem().string();
  std::error_code error;
  for (fs::directory_iterator it(dir.empty() ? fs::path(".") : dir, error), end; !error && it != end;
       it.increment(error)) {
    const std::string name = it->path().filename().string();
    const bool plot_name = name.ends_with(".png") && (name == stem + ".png" || name.starts_with(stem + "_"));
    if (!plot_name) continue;
    const std::string path = (dir / name).string();
    if (const OutputTarget target = inspect_output(path, OutputFormat::kSeekable); !target.refusal.empty())
      problems.push_back(path + ": " + target.refusal);
  }
  return problems;
}

OutputMode require_output(const std::string& path, OutputFormat format) {
  const OutputTarget target = inspect_output(path, format);
  if (!target.refusal.empty()) throw std::runtime_error(path + ": " + target.refusal);
  return target.mode;
}

bool is_plain_file_name(const std::string& name) {
  const bool control = std::any_of(name.begin(), name.end(), [](unsigned char c) { return c < 0x20 || c == 0x7f; });
  return !name.empty() && !control && name.find_first_of("/\\") == std::string::npos && name != "." && name != "..";
}

}  // namespace rover::io
