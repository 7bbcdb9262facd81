// See input_files.hpp.
#include "io/input_files.hpp"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string_view>
#include <system_error>
#include <utility>

#include "io/json_reader.hpp"
#include "io/scenario_config.hpp"

namespace rover::io {
namespace {

namespace fs = std::filesystem;

// Configs name each other a few levels deep (study -> scenario -> rover); a
// deeper chain is a loop the visited check has not caught (hard links).
constexpr int kMaxConfigDepth = 8;
// A JSON input larger than this (a fine terrain grid) is protected but not
// searched for names: it names no further files.
constexpr std::uintmax_t kMaxSearchedConfigBytes = 4u << 20;

bool is_regular_file(const std::string& path) {
  std::error_code error;
  return fs::is_regular_file(path, error);
}

// Calls visit(key path, string) for every string in `value`: "rover",
// "qoi[0].reference", "data[1].file".
template <class Visit>
void each_string(const Json& value, const std::string& where, const Visit& visit) {
  if (value.is_string()) {
    visit(where, value.get<std::string>());
  } else if (value.is_array()) {
    for (std::size_t i = 0; i < value.size(); ++i) each_string(value[i], where + "[" + std::to_string(i) + "]", visit);
  } else if (value.is_object()) {
    for (auto it = value.begin(); it != value.end(); ++it)
      each_string(it.value(), where.empty() ? it.key() : where + "." + it.key(), visit);
  }
}

// A field whose string is words for people, never a file name, whatever it
// spells: a "description" at any depth.
bool is_free_text(const std::string& key) {
  constexpr std::string_view kFreeText = "description";
  const std::size_t dot = key.rfind('.');
  return std::string_view(key).substr(dot == std::string::npos ? 0 : dot + 1) == kFreeText;
}

bool equivalent_files(const std::string& a, const std::string& b) {
  std::error_code error;
  const bool same = fs::equivalent(a, b, error);
  return !error && same;
}

}  // namespace

void InputFiles::add(const std::string& path, const std::string& named_by) {
  if (path.empty()) return;
  files_.push_back({path, named_by});
}

void InputFiles::add_all(const InputFiles& other) {
  files_.insert(files_.end(), other.files_.begin(), other.files_.end());
}

void InputFiles::add_config(const std::string& path, const std::string& named_by) {
  const bool known = same_file_as(path) != nullptr;
  add(path, named_by);
  if (!known) add_named_in(path, 0);
}

void InputFiles::add_named_in(const std::string& config, int depth) {
  if (depth >= kMaxConfigDepth || !is_regular_file(config)) return;
  std::error_code error;
  if (fs::path(config).extension() != ".json" || fs::file_size(config, error) > kMaxSearchedConfigBytes || error)
    return;
  std::ifstream in(config, std::ios::binary);
  std::string content;
  try {
    content.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  } catch (const std::exception&) {
    return;  // unreadable: its loader says so
  }
  const Json json = parse_json_quietly(content);
  if (json.is_discarded()) return;
  each_string(json, "", [&](const std::string& key, const std::string& name) {
    if (is_free_text(key) || name.empty() || name.size() > 4096 || name.find('\0') != std::string::npos) return;
    const std::string resolved = resolve_relative(config, name);
    if (!is_regular_file(resolved) || same_file_as(resolved) != nullptr) return;
    add(resolved, "'" + key + "' in " + config);
    add_named_in(resolved, depth + 1);
  });
}

const InputFiles::File* InputFiles::same_file_as(const std::string& output) const {
  for (const File& f : files_)
    if (equivalent_files(output, f.path)) return &f;
  return nullptr;
}

const InputFiles::File* InputFiles::named_like(const std::string& directory, const std::string& prefix,
                                               const std::string& suffix) const {
  std::error_code error;
  const fs::path dir = fs::weakly_canonical(directory.empty() ? "." : directory, error);
  if (error) return nullptr;
  for (const File& f : files_) {
    const fs::path real = fs::canonical(f.path, error);  // where a rename would land
    if (error || real.parent_path() != dir) continue;
    const std::string name = real.filename().string();
    if (name.size() >= prefix.size() + suffix.size() && name.compare(0, prefix.size(), prefix) == 0 &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      return &f;
  }
  return nullptr;
}

namespace {

// An entry of `dir` that a rename beside an output <stem><ext> would replace
// (a plot <stem>.png or <stem>_*.png, or <stem><ext>.*) and that is an input
// under another name (a hard or symbolic link: same device and inode), with
// that input; {"", nullptr} if none.
std::pair<std::string, const InputFiles::File*> input_beside(const InputFiles& inputs, const std::string& dir,
                                                            const std::string& stem, const std::string& name,
                                                            bool plots) {
  std::error_code error;
  for (fs::directory_iterator it(dir.empty() ? fs::path(".") : fs::path(dir), error), end; !error && it != end;
       it.increment(error)) {
    const std::string entry = it->path().filename().string();
    const bool plot = plots && entry.ends_with(".png") && (entry == stem + ".png" || entry.starts_with(stem + "_"));
    if (!plot && !entry.starts_with(name + ".")) continue;
    const std::string path = (fs::path(dir) / entry).string();
    if (const InputFiles::File* input = inputs.same_file_as(path)) return {path, input};
  }
  return {"", nullptr};
}

}  // namespace

std::vector<std::string> outputs_over_inputs(const std::string& flag, const std::string& output,
                                             const InputFiles& inputs, WrittenBeside beside) {
  std::vector<std::string> problems;
  if (output.empty()) return problems;
  auto destroys = [&](const std::string& what, const InputFiles::File& input) {
    // "--scenario 'a.json'", or "the file 'r.json' named by 'rover' in a.json".
    const std::string named = input.named_by.rfind("-", 0) == 0
                                  ? input.named_by + " '" + input.path + "'"
                                  : "the file '" + input.path + "' named by " + input.named_by;
    problems.push_back(flag + " '" + output + "'" + what + " " + named + "; writing it would destroy it");
  };
  if (const InputFiles::File* input = inputs.same_file_as(output)) {
    destroys(" is the same file as", *input);
    return problems;
  }
  if (beside == WrittenBeside::kNothing) return problems;
  const bool plotted = beside == WrittenBeside::kTemporariesAndPlots;
  const fs::path out(output);
  const std::string dir = out.parent_path().string(), name = out.filename().string();
  const std::string stem = name.substr(0, name.size() - out.extension().string().size());
  const std::string plots = (fs::path(dir) / stem).string() + "*.png";
  if (const InputFiles::File* input = plotted ? inputs.named_like(dir, stem, ".png") : nullptr) {
    destroys(": a plot written beside it (" + plots + ") would replace", *input);
  } else if (const InputFiles::File* next_to = inputs.named_like(dir, name + ".", "")) {
    destroys(": its checkpoint or temporary file (" + output + ".*) would replace", *next_to);
  } else if (const auto [entry, linked] = input_beside(inputs, dir, stem, name, plotted); linked != nullptr) {
    destroys(": " + entry + (entry.ends_with(".png") ? ", a plot written beside it (" + plots + ")," :
                                                      ", its checkpoint or temporary file (" + output + ".*),") +
                 " is a link to", *linked);
  }
  return problems;
}

}  // namespace rover::io
