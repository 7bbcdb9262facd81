// The files a command reads, so that no output can replace one of them.
//
// A command's inputs are the files its flags name and, transitively, every
// file named inside a config: a scenario's rover and terrain, a study's
// scenario, reference curves and measured data. Each loader knows which of
// its fields name files and lists what it read (io::ScenarioSources::files,
// study::StudySpec::files, ...); the command adds the files its flags name.
// add_config() is the fallback of the loaders that do not list their files
// yet (calibration, surrogate): every string in a JSON config that names an
// existing regular file (relative to the config's directory) counts, except
// a "description", and a JSON input is searched the same way.
//
// Two ways an output replaces an input:
//   * it is the same file, under any spelling or link (std::filesystem::
//     equivalent: same device and inode);
//   * it is written by rename onto the directory entry the input resolves
//     to: a plot <stem>*.png, <out>.checkpoint or <out>.partial beside --out
//     where an input (or the file an input's link points to) lives.
#pragma once

#include <string>
#include <vector>

namespace rover::io {

class InputFiles {
 public:
  struct File {
    std::string path;      // as named (resolved against its config's directory)
    std::string named_by;  // "--scenario", or "'rover' in configs/scenarios/drop.json"
  };

  void add(const std::string& path, const std::string& named_by);
  // Every file of `other`, after those already here.
  void add_all(const InputFiles& other);
  // `path` and every file named inside it, recursively (the fallback above).
  void add_config(const std::string& path, const std::string& named_by);

  const std::vector<File>& files() const { return files_; }

  // The input that writing `output` would destroy (same file under any name), or nullptr.
  const File* same_file_as(const std::string& output) const;
  // The input whose file lies in `directory` under a name starting with
  // `prefix` and ending with `suffix` (the files written beside an output), or nullptr.
  const File* named_like(const std::string& directory, const std::string& prefix, const std::string& suffix) const;

 private:
  void add_named_in(const std::string& config, int depth);
  std::vector<File> files_;
};

// What a command writes next to an output: nothing (a CSV), its temporary
// file and checkpoint (<out>.*), and the plots <stem>*.png too.
enum class WrittenBeside { kNothing, kTemporaries, kTemporariesAndPlots };

// "--out 'x' is the same file as --scenario 'x'; writing it would destroy it"
// (or "... as the file 'r.json' named by 'rover' in s.json ..."), or the same
// for the files written beside it (`beside`): one problem per output that
// would replace an input; empty if none does. `flag` names the output ("--out").
std::vector<std::string> outputs_over_inputs(const std::string& flag, const std::string& output,
                                             const InputFiles& inputs, WrittenBeside beside);

}  // namespace rover::io
