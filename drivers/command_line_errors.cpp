// See command_line_errors.hpp.
#include "drivers/command_line_errors.hpp"

#include <algorithm>
#include <iterator>
#include <sstream>

#include "io/json_reader.hpp"

namespace rover::cli {
namespace {

bool starts_with(const std::string& text, const std::string& prefix) { return text.rfind(prefix, 0) == 0; }

// `text` after `prefix`, if it starts so.
bool after(const std::string& text, const std::string& prefix, std::string* rest) {
  if (!starts_with(text, prefix)) return false;
  *rest = text.substr(prefix.size());
  return true;
}

// Splits "NAME: message" at the first ": ".
std::pair<std::string, std::string> name_and_message(const std::string& text) {
  const std::size_t colon = text.find(": ");
  if (colon == std::string::npos) return {"", text};
  return {text.substr(0, colon), text.substr(colon + 2)};
}

std::vector<const CLI::App*> subcommands(const CLI::App* app) {
  return app->get_subcommands([](const CLI::App*) { return true; });
}

// The option `name` of `app` or of one of its subcommands (`rover terrain obstacle`).
const CLI::Option* find_option(const CLI::App* app, const std::string& name) {
  if (app == nullptr || name.empty()) return nullptr;
  for (const CLI::Option* option : app->get_options())
    if (option->check_name(name) || option->get_name() == name) return option;
  for (const CLI::App* sub : subcommands(app))
    if (const CLI::Option* option = find_option(sub, name)) return option;
  return nullptr;
}

bool is_number_option(const CLI::Option* option) {
  const std::string type = option == nullptr ? "" : option->get_type_name();
  return type.find("INT") != std::string::npos || type.find("FLOAT") != std::string::npos;
}

// What an option accepts: "a whole number (Override the number of samples N)",
// "Scenario file (configs/scenarios/*.json)".
std::string accepted(const CLI::Option* option) {
  if (option == nullptr) return "a value";
  const std::string type = option->get_type_name();
  const std::string description = option->get_description();
  if (!is_number_option(option)) return description;
  const char* kind = type.find("UINT") != std::string::npos  ? "a whole number >= 0"
                     : type.find("INT") != std::string::npos ? "a whole number"
                                                             : "a number";
  return std::string(kind) + " (" + description + ")";
}

// "--out", or "argument A" for a positional argument.
std::string where(const std::string& name) { return starts_with(name, "-") ? name : "argument " + name; }

std::vector<std::string> option_names(const CLI::App* app) {
  std::vector<std::string> names;
  if (app == nullptr) return names;
  for (const CLI::Option* option : app->get_options())
    for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
  for (const CLI::App* sub : subcommands(app))
    for (std::string& name : option_names(sub)) names.push_back(std::move(name));
  return names;
}

// "it takes 2 arguments, A B, and options" or "every value follows its option".
std::string positional_rule(const CLI::App* sub) {
  std::string names;
  int count = 0;
  for (const CLI::Option* option : sub->get_options())
    if (option->get_lnames().empty() && option->get_snames().empty() && !option->get_name().empty()) {
      names += " " + option->get_name();
      ++count;
    }
  if (count == 0) return "every value follows its option, as in --out FILE";
  return "it takes " + std::to_string(count) + " argument" + (count == 1 ? "" : "s") + "," + names + ", and options";
}

// Arguments CLI11 found no place for; `after_end_of_options` when '--' was
// typed (every word after it is an argument, also one spelt as an option).
std::string extras_text(const std::string& list, const CLI::App* sub, bool after_end_of_options) {
  std::istringstream words(list);
  std::string text;
  bool after_unknown_option = false;  // the next word is taken as its value
  for (std::string word; words >> word;) {
    if (after_unknown_option && !starts_with(word, "-")) {
      after_unknown_option = false;
      continue;
    }
    after_unknown_option = starts_with(word, "-") && word.find('=') == std::string::npos;
    if (!text.empty()) text += "; ";
    if (starts_with(word, "-")) {
      const std::string flag = word.substr(0, word.find('='));
      const std::vector<std::string> known = option_names(sub);
      if (after_end_of_options && std::find(known.begin(), known.end(), flag) != known.end()) {
        text += "'" + flag + "' follows '--', which ends the options (every word after it is taken as an argument): "
                "put '" + flag + "' before the '--', or remove the '--'";
        continue;
      }
      text += "unknown option '" + flag + "'";
      if (const std::string near = nearest_name(flag, known); !near.empty())
        text += "; did you mean '" + near + "'?";
    } else {
      text += "unexpected argument '" + word + "' (" + positional_rule(sub) + ")";
    }
  }
  return text;
}

// "--study 'x.json': no such file", "--progress-interval must be from 1 to 86400, got 0", ...
std::string validation_text(const std::string& what) {
  const auto [name, message] = name_and_message(what);
  if (message.starts_with(kGivenNoValue)) return name + " " + message;  // as collect_empty_values says it
  std::string rest;
  if (after(message, "File does not exist: ", &rest)) {  // or cannot be reached: a link loop, a closed folder
    const std::string problem = io::input_path_problem(rest, "a file");
    if (starts_with(name, "-") && rest.starts_with("--") && (problem.empty() || problem == "no such file"))
      return name + " " + std::string(kGivenNoValue) + ": the word after it, '" + rest + "', is an option of its own";
    return where(name) + " '" + rest + "': " + (problem.empty() ? "no such file" : problem);
  }
  if (after(message, "File is actually a directory: ", &rest))
    return where(name) + " '" + rest + "' is a directory; give a file";
  if (after(message, "Value ", &rest)) {
    const std::size_t range = rest.find(" not in range ");
    if (range != std::string::npos)
      return name + " must be from " + rest.substr(range + 14) + ", got " + rest.substr(0, range);
  }
  const std::size_t not_in = message.find(" not in {");
  if (not_in != std::string::npos)
    return name + ": '" + message.substr(0, not_in) + "' is not one of " + message.substr(not_in + 8);
  return name + ": " + message;
}

std::string conversion_text(const std::string& what, const CLI::App* sub) {
  std::string rest, name, value;
  if (after(what, "Could not convert: ", &rest)) {
    const std::size_t equals = rest.find(" = ");
    name = rest.substr(0, equals);
    value = equals == std::string::npos ? "" : rest.substr(equals + 3);
  } else if (after(what, "The value ", &rest) && rest.find(" is not an allowed value for ") != std::string::npos) {
    const std::size_t for_name = rest.find(" is not an allowed value for ");
    name = rest.substr(for_name + 29);
    value = rest.substr(0, for_name);
  } else {
    name = name_and_message(what).first;
  }
  const CLI::Option* option = find_option(sub, name);
  if (option != nullptr && option->get_expected_max() == 0)
    return name + " is a flag: give it without a value" + (value.empty() ? "" : ", not '" + value + "'");
  if (name.empty()) return what;
  return where(name) + ": '" + value + "' is not " + accepted(option);
}

// "Expected exactly 1 arguments to --out, got 0", "--out: 1 required TEXT missing".
std::string mismatch_text(const std::string& what, const CLI::App* sub) {
  std::string rest, name;
  if (after(what, "Expected exactly ", &rest) || after(what, "Expected at least ", &rest)) {
    const std::size_t to = rest.find(" arguments to ");
    const std::size_t comma = rest.rfind(", got ");
    if (to != std::string::npos && comma != std::string::npos) name = rest.substr(to + 14, comma - to - 14);
  } else {
    name = name_and_message(what).first;
  }
  if (name.empty()) return what;
  const CLI::Option* option = find_option(sub, name);
  if (after(what, name + ": At Most ", &rest) && option != nullptr) {  // "--f 1e4 --f 2e4"
    std::string values;
    for (const std::string& value : option->results()) values += (values.empty() ? "'" : ", '") + value + "'";
    return where(name) + " was given " + std::to_string(option->results().size()) + " times (" + values +
           "); give it once: " + accepted(option);
  }
  return where(name) + " needs a value: " + accepted(option);
}

// `first_unparsed`: the first word CLI11 left over ("flat" in `terrain flat`).
std::string required_text(const std::string& what, const CLI::App* sub, const std::string& first_unparsed) {
  if (starts_with(what, "A subcommand is required") || starts_with(what, "Requires at least")) {
    std::string names;
    std::vector<std::string> known;
    for (const CLI::App* command : subcommands(sub)) {
      names += (names.empty() ? "" : ", ") + command->get_name();
      known.push_back(command->get_name());
    }
    if (first_unparsed.empty()) return "a subcommand is required (" + names + ")";
    const std::string near = nearest_name(first_unparsed, known);
    return "'" + first_unparsed + "' is not a subcommand of " + sub->get_name() + " (its subcommands: " + names +
           ")" + (near.empty() ? "" : "; did you mean '" + near + "'?");
  }
  const std::string suffix = " is required";
  if (what.size() > suffix.size() && what.compare(what.size() - suffix.size(), suffix.size(), suffix) == 0) {
    const std::string name = what.substr(0, what.size() - suffix.size());
    return where(name) + " is required: " + accepted(find_option(sub, name));
  }
  return what;
}

// The innermost subcommand `command` names ("terrain obstacle") below `app`.
const CLI::App* innermost(const CLI::App& app, const std::string& command) {
  const CLI::App* sub = &app;
  std::istringstream names(command);
  for (std::string name; names >> name;)
    for (const CLI::App* candidate : subcommands(sub))
      if (candidate->get_name() == name) {
        sub = candidate;
        break;
      }
  return sub;
}

std::vector<std::string> error_lines(const std::string& command, const std::vector<std::string>& problems) {
  const std::string program = command.empty() ? "rover" : "rover " + command;
  std::vector<std::string> lines;
  for (const std::string& problem : problems) lines.push_back(program + ": error: " + problem);
  lines.push_back("Run '" + program + " --help' for the options.");
  return lines;
}

// A dash other than '-' that documents and word processors put where a
// command line has hyphens: its UTF-8 bytes and its name.
struct LookAlikeDash {
  std::string_view bytes;
  const char* name;
};
constexpr LookAlikeDash kLookAlikeDashes[] = {
    {"\xE2\x80\x94", "an em dash (U+2014)"},       {"\xE2\x80\x93", "an en dash (U+2013)"},
    {"\xE2\x88\x92", "a minus sign (U+2212)"},     {"\xE2\x80\x90", "a Unicode hyphen (U+2010)"},
    {"\xE2\x80\x91", "a non-breaking hyphen (U+2011)"}, {"\xE2\x80\x92", "a figure dash (U+2012)"}};

// "'<em dash>scenario' starts with an em dash (U+2014) ...: type '--scenario'", or empty.
std::string look_alike_dash_text(const std::string& word, const CLI::App* sub) {
  for (const LookAlikeDash& dash : kLookAlikeDashes) {
    if (!starts_with(word, std::string(dash.bytes))) continue;
    std::string rest = word.substr(dash.bytes.size());
    while (starts_with(rest, "-") || starts_with(rest, std::string(dash.bytes)))  // "<dash><dash>scenario"
      rest.erase(0, starts_with(rest, "-") ? 1 : dash.bytes.size());
    const std::string option = "--" + rest.substr(0, rest.find('='));
    std::string text = "'" + word + "' starts with " + dash.name + ", not with ASCII hyphens (copied from a document?)";
    if (find_option(sub, option) != nullptr) return text + ": type '--" + rest + "'";
    return text + ": type it with '-'";
  }
  return "";
}

}  // namespace

std::vector<std::string> typed_word_error_lines(const std::vector<std::string>& args, const CLI::App& app,
                                                const std::string& command) {
  const CLI::App* sub = innermost(app, command);
  std::vector<std::string> problems;
  for (const std::string& arg : args) {
    if (arg == "--") break;
    if (starts_with(arg, "--") && arg.size() > 3 && arg.find('=') == arg.size() - 1)
      problems.push_back(arg.substr(0, arg.size() - 1) + " was given an empty value (nothing follows the '=' of '" +
                         arg + "')");
    if (std::string text = look_alike_dash_text(arg, sub); !text.empty()) problems.push_back(std::move(text));
  }
  if (problems.empty()) return {};
  return error_lines(command, problems);
}

std::vector<std::string> command_line_error_lines(const CLI::ParseError& error, const CLI::App& app,
                                                  const std::string& command, const std::vector<std::string>& args) {
  const CLI::App* sub = innermost(app, command);
  const bool end_of_options = std::find(args.begin(), args.end(), "--") != args.end();
  const std::string what = error.what();
  std::string text;
  // An unknown option is the first thing to fix (CLI11 may report a required
  // option first: `--scenaro x` leaves --scenario unset).
  std::string unparsed;
  const std::vector<std::string> remaining = sub->remaining();
  for (const std::string& arg : remaining) unparsed += (unparsed.empty() ? "" : " ") + arg;
  if (dynamic_cast<const CLI::ExtrasError*>(&error)) {
    // CLI11 lists them last first.
    std::istringstream words(what.substr(what.find(": ") + 2));
    std::vector<std::string> extras{std::istream_iterator<std::string>(words), std::istream_iterator<std::string>()};
    std::string in_order;
    for (auto it = extras.rbegin(); it != extras.rend(); ++it) in_order += (in_order.empty() ? "" : " ") + *it;
    text = extras_text(in_order, sub, end_of_options);
  } else if (!unparsed.empty() && starts_with(unparsed, "-")) {
    text = extras_text(unparsed, sub, end_of_options);
  } else if (dynamic_cast<const CLI::ValidationError*>(&error)) {
    text = validation_text(what);
  } else if (dynamic_cast<const CLI::ConversionError*>(&error)) {
    text = conversion_text(what, sub);
  } else if (dynamic_cast<const CLI::ArgumentMismatch*>(&error)) {
    text = mismatch_text(what, sub);
  } else if (dynamic_cast<const CLI::RequiredError*>(&error)) {
    text = required_text(what, sub, remaining.empty() ? "" : remaining.front());
  } else if (dynamic_cast<const CLI::ExcludesError*>(&error)) {
    const std::size_t word = what.find(" excludes ");
    text = word == std::string::npos ? what
                                     : what.substr(0, word) + " cannot be given together with " + what.substr(word + 10);
  } else if (dynamic_cast<const CLI::RequiresError*>(&error)) {
    const std::size_t word = what.find(" requires ");
    text = word == std::string::npos ? what : what.substr(0, word) + " needs " + what.substr(word + 10) + " as well";
  } else {
    text = what;
  }
  return error_lines(command, {text});
}

}  // namespace rover::cli
