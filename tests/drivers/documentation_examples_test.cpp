// Every `rover` command the documentation shows runs as written: each rover
// line of a ```sh block, and each inline `rover ...` example, of README.md and
// docs/*.md, in document order, in a scratch directory holding a copy of
// configs/. A ```json block with a "name" is written there as <name>.json
// first (docs/studies.md's my_fit.json). Commands that have --dry-run run
// with it (the study, every file it names and the output path are read and
// checked; the studies' numbers are tested elsewhere); one whose result a later
// example of the same document reads runs fully, so that example finds it. The
// other commands (simulate, synthesize, compare, ...) run fully. `mpirun -np N`
// is left out: the runs do not depend on the ranks.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <iterator>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/json_reader.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

using rover::testing::read_file;
using rover::testing::rover_binary;
using rover::testing::run_command;
using rover::testing::source_path;

// One example: the command after "rover" (subcommand and arguments, shell
// syntax kept), or a study file to write, with its line in the document.
struct Example {
  int line = 0;
  std::string command;           // "simulate --scenario ..." (empty for a file)
  std::string file_name, file_text;  // a ```json block with a "name"
};

int line_of(const std::string& text, std::size_t offset) {
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(offset), '\n'));
}

// The part of a shell line from its `rover` word on ("mpirun -np 2
// build/drivers/rover x" -> "x"); empty when the line does not run rover.
std::string rover_arguments(const std::string& line) {
  std::istringstream words(line);
  std::size_t consumed = 0;
  for (std::string word; words >> word;) {
    consumed = line.find(word, consumed) + word.size();
    if (word == "rover" || (word.ends_with("/rover") && word.find('=') == std::string::npos)) {
      const std::size_t start = line.find_first_not_of(' ', consumed);
      return start == std::string::npos ? "" : line.substr(start);
    }
    if (word != "mpirun" && word.rfind("-", 0) != 0 && !std::all_of(word.begin(), word.end(), ::isdigit) &&
        word != "hosts")
      return "";  // another program
  }
  return "";
}

// A word in capitals stands for the user's value: A, B, FILE, SURROGATE.h5
// (but X.csv is a file the examples share).
bool is_placeholder(const std::string& word) {
  const std::size_t dot = word.find('.');
  const std::string stem = word.substr(0, dot);
  const bool capitals =
      !stem.empty() && std::all_of(stem.begin(), stem.end(), [](char c) { return std::isupper(static_cast<unsigned char>(c)); });
  return capitals && (stem.size() > 1 || dot == std::string::npos);
}

// An inline example names a subcommand and at least one argument, and no
// placeholder (`rover compare A B`, `--next-experiment FILE`); a lone flag
// names a mode (`rover surrogate --predict`) unless it is --help.
bool is_inline_example(const std::string& arguments) {
  std::istringstream words(arguments);
  std::vector<std::string> tokens{std::istream_iterator<std::string>(words), {}};
  if (tokens.size() < 2) return false;
  bool has_value = false;
  for (std::size_t i = 1; i < tokens.size(); ++i) {
    const std::string& t = tokens[i];
    if (is_placeholder(t)) return false;
    has_value = has_value || t.rfind("--", 0) != 0 || t == "--help";
  }
  return has_value;
}

std::vector<Example> examples_of(const std::string& text) {
  std::vector<Example> out;
  const std::regex block("```(\\w*)\\n([\\s\\S]*?)```");
  std::vector<std::pair<std::size_t, std::size_t>> blocks;
  for (auto m = std::sregex_iterator(text.begin(), text.end(), block); m != std::sregex_iterator(); ++m) {
    const auto at = static_cast<std::size_t>(m->position(0));
    blocks.emplace_back(at, at + static_cast<std::size_t>(m->length(0)));
    const std::string lang = (*m)[1], body = (*m)[2];
    if (lang == "json") {
      const io::Json json = io::Json::parse(body, nullptr, false, true);
      if (json.is_object() && json.contains("name") && json["name"].is_string())
        out.push_back({line_of(text, at), "", json["name"].get<std::string>() + ".json", body});
      continue;
    }
    if (lang != "sh" && lang != "bash") continue;
    const std::string joined = std::regex_replace(body, std::regex("\\\\\\n\\s*"), " ");
    std::istringstream lines(joined);
    int offset = 0;
    for (std::string line; std::getline(lines, line); ++offset) {
      line = std::regex_replace(line, std::regex("\\s+#\\s.*$"), "");
      if (const std::string args = rover_arguments(line); !args.empty())
        out.push_back({line_of(text, at) + 1 + offset, args, "", ""});
    }
  }
  const std::regex span("`((?:mpirun[^`]*?)?rover [a-z][^`]*)`");
  for (auto m = std::sregex_iterator(text.begin(), text.end(), span); m != std::sregex_iterator(); ++m) {
    const auto at = static_cast<std::size_t>(m->position(0));
    const bool inside_block =
        std::any_of(blocks.begin(), blocks.end(), [&](const auto& b) { return at >= b.first && at < b.second; });
    const std::string args = rover_arguments((*m)[1]);
    if (!inside_block && is_inline_example(args)) out.push_back({line_of(text, at), args, "", ""});
  }
  std::stable_sort(out.begin(), out.end(), [](const Example& a, const Example& b) { return a.line < b.line; });
  return out;
}

// The value of `flag` in a command line ("" if absent).
std::string flag_value(const std::string& command, const std::string& flag) {
  std::smatch m;
  return std::regex_search(command, m, std::regex(flag + "[ =](\\S+)")) ? m[1].str() : "";
}

// Where a study command writes: --out, or results/<name>.h5 of its --study file.
std::string result_of(const std::string& command, const std::string& dir) {
  if (const std::string out = flag_value(command, "--out"); !out.empty()) return out;
  const std::string study = flag_value(command, "--study");
  if (study.empty()) return "";
  const io::Json json = io::Json::parse(read_file(dir + "/" + study), nullptr, false, true);
  return json.is_object() && json.contains("name") && json["name"].is_string()
             ? "results/" + json["name"].get<std::string>() + ".h5"
             : "";
}

// Whether an example after `index` reads `result` (on its command line or in
// its study file) before another one writes it again.
bool read_later(const std::vector<Example>& examples, std::size_t index, const std::string& result,
                const std::string& dir) {
  for (std::size_t k = index + 1; k < examples.size() && !result.empty(); ++k) {
    const std::string& later = examples[k].command;
    if (later.empty()) continue;
    if (result_of(later, dir) == result) return false;
    if (later.find(result) != std::string::npos) return true;
    const std::string study = flag_value(later, "--study");
    if (!study.empty() && read_file(dir + "/" + study).find(result) != std::string::npos) return true;
  }
  return false;
}

constexpr int kCoordinates = 23;  // docs/model.md section 2

class DocumentationExamples : public ::testing::TestWithParam<std::string> {};

TEST_P(DocumentationExamples, RunAsWritten) {
  const std::string document = GetParam();
  const std::string text = read_file(source_path(document));
  const std::vector<Example> examples = examples_of(text);
  const std::string dir = rover::testing::temp_dir();
  std::filesystem::copy(source_path("configs"), dir + "/configs", std::filesystem::copy_options::recursive);
  std::filesystem::create_directories(dir + "/results");
  // Inputs the examples take from the user: a design over (f, c_q) and a state.
  rover::testing::write_file(dir + "/X.csv", "f,c_q\n1e4,0.25\n300,0.1\n");
  std::string q = "0, 0, 0.281", u = "0";
  for (int k = 3; k < kCoordinates; ++k) q += ", 0";
  for (int k = 1; k < kCoordinates; ++k) u += ", 0";
  rover::testing::write_file(dir + "/state.json", "{\"q\": [" + q + "], \"u\": [" + u + "]}");
  std::map<std::string, bool> dry_run_of;  // subcommand -> has --dry-run
  for (std::size_t i = 0; i < examples.size(); ++i) {
    const Example& e = examples[i];
    if (!e.file_name.empty()) {
      rover::testing::write_file(dir + "/" + e.file_name, e.file_text);
      continue;
    }
    const std::string subcommand = e.command.substr(0, e.command.find(' '));
    if (!dry_run_of.count(subcommand)) {
      std::string help;
      run_command(rover_binary() + " " + subcommand + " --help", &help);
      dry_run_of[subcommand] = help.find("--dry-run") != std::string::npos;
    }
    const bool dry = dry_run_of[subcommand] && e.command.find("--help") == std::string::npos &&
                     !read_later(examples, i, result_of(e.command, dir), dir);
    std::string log;
    const int status =
        run_command("cd " + dir + " && " + rover_binary() + " " + e.command + (dry ? " --dry-run" : ""), &log);
    EXPECT_EQ(status, 0) << document << ":" << e.line << ": rover " << e.command << "\n" << log;
  }
  EXPECT_FALSE(examples.empty()) << document << " shows no rover command";
}

const std::vector<std::string> kDocumentsWithExamples{
    "README.md",        "docs/studies.md",     "docs/configuration.md", "docs/cluster.md",
    "docs/validation.md", "docs/reliability.md", "docs/performance.md"};

// A new document with a rover example joins the list above.
TEST(DocumentationExamples, EveryDocumentWithAnExampleIsRun) {
  for (const auto& entry : std::filesystem::directory_iterator(source_path("docs"))) {
    if (entry.path().extension() != ".md") continue;
    const std::string document = "docs/" + entry.path().filename().string();
    const bool listed = std::find(kDocumentsWithExamples.begin(), kDocumentsWithExamples.end(), document) !=
                        kDocumentsWithExamples.end();
    const std::vector<Example> examples = examples_of(read_file(entry.path().string()));
    const bool has_examples =
        std::any_of(examples.begin(), examples.end(), [](const Example& e) { return !e.command.empty(); });
    EXPECT_EQ(listed, has_examples) << document;
  }
}

INSTANTIATE_TEST_SUITE_P(Docs, DocumentationExamples, ::testing::ValuesIn(kDocumentsWithExamples),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

}  // namespace
}  // namespace rover
