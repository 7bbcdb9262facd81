// Command-line options shared by several subcommands: overrides of the study
// inputs (f, c_q, the 8 preloads M0), the help of --integrator, and the checks
// every subcommand runs on its flags before any work:
//   * numbers must be finite and in range, judged as the JSON configs judge
//     the same quantities (a negative preload is refused as rover.json
//     refuses it); every bad flag is reported, not just the first;
//   * seeds are read as JSON seeds are (io::exact_unsigned_integer): -1 or
//     2^64 + 5 are errors, never 2^64 - 1 or 4; every other integer flag
//     takes an integral number in exponent form too (--samples 1e3, as
//     "samples": 1e3 in a study file; drivers/main.cpp);
//   * an output path must be new or a writable regular file (a stream for
//     text), and no file the command reads (io/input_files.hpp);
//   * a default config path ("configs/rover.json") that does not exist from
//     the working directory is looked up in the repository the program
//     belongs to (build/drivers/rover -> ../../configs/rover.json);
//   * JSON printed on stdout must hold finite numbers only (nlohmann would
//     print NaN as null).
#pragma once

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/model_scale.hpp"
#include "core/number_text.hpp"
#include "core/scenario.hpp"
#include "core/simulate.hpp"
#include "drivers/launcher.hpp"
#include "io/decimal_number.hpp"
#include "io/input_files.hpp"
#include "io/json_reader.hpp"
#include "io/output_target.hpp"
#include "io/plot.hpp"

namespace rover::cli {

// One or more bad command-line flags; main() prints one line per problem.
class CommandLineError : public std::invalid_argument {
 public:
  explicit CommandLineError(std::vector<std::string> problems)
      : std::invalid_argument(joined(problems)), problems_(std::move(problems)) {}
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  static std::string joined(const std::vector<std::string>& problems) {
    std::string text;
    for (const std::string& p : problems) text += (text.empty() ? "" : "; ") + p;
    return text;
  }
  std::vector<std::string> problems_;
};

// Collects the problems of a command line; throw_if_any() reports them all.
class FlagChecks {
 public:
  void add(std::string problem) { problems_.push_back(std::move(problem)); }

  void finite(const std::string& flag, double value) {
    if (!std::isfinite(value)) add(flag + " must be a finite number, got " + typed(value));
  }
  void positive(const std::string& flag, double value) {
    if (!(std::isfinite(value) && value > 0.0))
      add(flag + " must be a positive finite number, got " + typed(value));
  }
  void non_negative(const std::string& flag, double value) {
    if (!(std::isfinite(value) && value >= 0.0))
      add(flag + " must be a finite number >= 0, got " + typed(value));
  }
  // A number as the user may have typed it: one beyond the largest double
  // (1e400) reads as infinite.
  static std::string typed(double value) {
    if (!std::isinf(value)) return number_text(value);
    return std::string(value > 0 ? "" : "-") + "inf (a number beyond 1.8e308, the largest a double holds, reads as inf)";
  }
  // An output file: nothing, or a writable regular file, at `path` (for a
  // text output also a device, a pipe or standard output; never a link, a
  // read-only file or a directory: io/output_target.hpp), in a directory that
  // exists or can be made (it is made only when the output is written). With
  // `regular_only`, a device or a pipe is refused too (HDF5 must seek).
  void output_file(const std::string& flag, const std::string& path, bool regular_only = false) {
    if (path.empty()) return;
    // The files a study keeps beside its result (io/checkpoint.hpp, io/output_lock.hpp).
    for (const std::string suffix : {".checkpoint", ".lock"})
      if (path.ends_with(suffix)) {
        add(flag + " '" + path + "' ends in " + suffix + ", the name of " +
            (suffix == ".lock" ? "the lock rover holds beside an output while it writes it"
                               : "a study's checkpoint (its finished runs) beside its result, which a study "
                                 "reads, replaces and removes") +
            ": give another name");
        return;
      }
    const io::OutputTarget target =
        io::inspect_output(path, regular_only ? io::OutputFormat::kSeekable : io::OutputFormat::kText);
    if (!target.refusal.empty()) {
      add(flag + " '" + path + "' " + target.refusal);
    } else if (target.mode == io::OutputMode::kReplace && launcher_rank() == 0) {
      // The probe makes and removes a directory: under mpirun rank 0 alone
      // makes it, as rank 0 alone makes the directory itself. Another
      // rank's probe could remove rank 0's new directory under it.
      if (const std::string refusal = io::parent_directory_refusal(path); !refusal.empty())
        add(flag + " '" + path + "': " + refusal);
    }
  }

  // An output named for another format than the one written ("x.h5" for
  // CSV text): the next program to open it by its name would fail. Names
  // without one of these extensions (.txt, /dev/stdout) are any format's.
  // `written`: "CSV", and its extension `written_extension`: ".csv".
  void output_format(const std::string& flag, const std::string& path, std::string_view written,
                     std::string_view written_extension) {
    struct NamedFormat {
      std::string_view extension, format, article;
    };
    static constexpr std::array<NamedFormat, 6> kFormatOfExtension{{{".h5", "HDF5", "an"},
                                                                    {".hdf5", "HDF5", "an"},
                                                                    {".csv", "CSV", "a"},
                                                                    {".json", "JSON", "a"},
                                                                    {".png", "PNG", "a"},
                                                                    {".pdf", "PDF", "a"}}};
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    for (const auto& [known, format, article] : kFormatOfExtension)
      if (extension == known && format != written)
        add(flag + " '" + path + "' ends in " + extension + ", the name of " + std::string(article) + " " +
            std::string(format) + " file, but " +
            flag + " writes " + std::string(written) + ": give a name ending in " + std::string(written_extension));
  }

  // The plots beside a result file `path` (io::plots_beside_refused): each
  // one that may not be written is refused now, not skipped after the run.
  void plots_beside(const std::string& flag, const std::string& path) {
    for (const std::string& problem : io::plots_beside_refused(path))
      add(flag + " '" + path + "': the plot " + problem + "; or pass --no-plot");
  }

  // gnuplot on PATH (io::plotter_problem) for the plot `asked_by` asks for;
  // `without` says how to do without it ("pass --no-plot").
  void plotter(const std::string& asked_by, const std::string& without) {
    if (const std::string problem = io::plotter_problem(); !problem.empty())
      add(asked_by + " needs gnuplot (with the pngcairo terminal), but " + problem + ", or " + without);
  }

  // An output that would replace one of `inputs`, the files the command reads
  // (io/input_files.hpp), also through the files written `beside` it.
  void not_an_input(const std::string& flag, const std::string& output, const io::InputFiles& inputs,
                    io::WrittenBeside beside = io::WrittenBeside::kNothing) {
    for (std::string& problem : io::outputs_over_inputs(flag, output, inputs, beside)) add(std::move(problem));
  }

  // An output that would replace an input: the same file, however spelt
  // (a relative path, a symbolic or hard link).
  void distinct_files(const std::string& output_flag, const std::string& output, const std::string& input_flag,
                      const std::string& input) {
    if (same_file(output, input))
      add(output_flag + " '" + output + "' is the same file as " + input_flag + " '" + input +
          "'; writing it would destroy it");
  }

  // The outputs of one command (each a flag, or a description such as "the
  // plot of --out 'r.h5'", and its path; empty paths are skipped) must be
  // pairwise different files, or one would replace the other.
  struct NamedOutput {
    std::string flag, path;
  };
  void distinct_outputs(const std::vector<NamedOutput>& outputs) {
    for (std::size_t i = 0; i < outputs.size(); ++i)
      for (std::size_t j = i + 1; j < outputs.size(); ++j)
        if (same_file(outputs[i].path, outputs[j].path))
          add(outputs[j].flag + " '" + outputs[j].path + "' is the same file as " + outputs[i].flag + " '" +
              outputs[i].path + "'; one output would replace the other: give different names");
  }

  // A seed flag, read as the JSON configs read "seed".
  std::uint64_t seed(const std::string& flag, const std::string& text) {
    std::optional<std::uint64_t> value;
    try {
      value = io::exact_unsigned_integer(io::parse_json_text(text, flag));
    } catch (const io::ConfigError&) {
    }
    if (!value) {
      add(flag + " must be an integer from 0 to 18446744073709551615" + io::kExponentFormLimit + ", got '" + text + "'");
      return 0;
    }
    return *value;
  }

  bool any() const { return !problems_.empty(); }
  void throw_if_any() const {
    if (!problems_.empty()) throw CommandLineError(problems_);
  }

 private:
  // Whether two paths name the same file, however spelt (a relative path, a
  // symbolic or hard link); two names not yet written compare as names.
  static bool same_file(const std::string& a, const std::string& b) {
    if (a.empty() || b.empty()) return false;
    namespace fs = std::filesystem;
    std::error_code e1, e2, e3;
    if (fs::exists(a, e1) && fs::exists(b, e2)) return fs::equivalent(a, b, e3) && !e3;  // also through links
    const fs::path ca = fs::weakly_canonical(a, e1), cb = fs::weakly_canonical(b, e2);
    return !e1 && !e2 && ca == cb;
  }

  std::vector<std::string> problems_;
};

struct InputOverrides {
  std::optional<double> f, c_q;
  std::string M0;  // comma-separated, 8 values
};

inline void add_input_overrides(CLI::App& app, InputOverrides& o) {
  app.add_option("--f", o.f, "S-structure sharpness f [1/rad] (default: the rover config)");
  app.add_option("--cq", o.c_q, "S-structure damping c_q [N m s/rad] (default: the rover config)");
  app.add_option("--M0", o.M0,
                 "The 8 preloads M0 [N m] (>= 0), comma-separated, order 11,12,21,22,31,32,41,42");
}

// "dopri5 (rtol 1e-06, atol 1e-09), rk4 (step 1e-05 s), rosenbrock (...)": the
// methods --integrator takes, with the defaults default_integrator_settings()
// gives them, so the help cannot drift from the code.
inline std::string integrator_choices_text() {
  const IntegratorSettings dopri5 = default_integrator_settings(IntegratorMethod::kDormandPrince45);
  const IntegratorSettings rk4 = default_integrator_settings(IntegratorMethod::kRungeKutta4);
  const IntegratorSettings rosenbrock = default_integrator_settings(IntegratorMethod::kRosenbrockW);
  return "dopri5 (rtol " + number_text(dopri5.relative_tolerance) + ", atol " +
         number_text(dopri5.absolute_tolerance) + "), rk4 (step " + number_text(rk4.fixed_step_s) +
         " s), rosenbrock (stiff, rtol " + number_text(rosenbrock.relative_tolerance) + ", atol " +
         number_text(rosenbrock.absolute_tolerance) + ")";
}

// An --integrator flag names a method.
inline void check_integrator_flag(FlagChecks& checks, const std::string& name) {
  if (name.empty()) return;
  try {
    integrator_from_name(name);
  } catch (const std::invalid_argument& e) {
    checks.add(std::string("--integrator: ") + e.what());
  }
}

// The names of a comma-separated list flag (--qoi B_l_z_min,t_min), each
// trimmed of spaces; an empty name (a stray comma) is a problem added to
// `checks`.
inline std::vector<std::string> split_names(const std::string& flag, const std::string& text, FlagChecks& checks) {
  std::vector<std::string> names;
  std::stringstream ss(text + ",");  // a trailing comma leaves an empty last item
  std::size_t position = 0;
  for (std::string item; std::getline(ss, item, ',');) {
    ++position;
    const std::size_t begin = item.find_first_not_of(" \t"), end = item.find_last_not_of(" \t");
    if (begin == std::string::npos) {
      if (!text.empty()) checks.add(flag + " '" + text + "': name " + std::to_string(position) + " is empty (a stray comma?)");
      continue;
    }
    names.push_back(item.substr(begin, end - begin + 1));
  }
  return names;
}

// The 8 preloads of --M0, or the problems with them added to `checks`.
inline std::optional<std::array<double, kNumSJoints>> parse_preloads(const std::string& text,
                                                                      FlagChecks& checks) {
  std::array<double, kNumSJoints> preloads{};
  if (const std::size_t last = text.find_last_not_of(" \t"); last != std::string::npos && text[last] == ',') {
    checks.add("--M0 '" + text + "': ends with a comma (a stray comma?); give the 8 preloads separated by commas");
    return std::nullopt;
  }
  std::stringstream ss(text);
  std::size_t n = 0;
  bool ok = true;
  for (std::string item; std::getline(ss, item, ',');) {
    if (n == preloads.size()) {
      checks.add("--M0 takes 8 values, got more: '" + text + "'");
      return std::nullopt;
    }
    const std::size_t index = n++;
    const std::size_t first = item.find_first_not_of(" \t"), last = item.find_last_not_of(" \t");
    const io::DecimalNumber value =
        io::parse_decimal_number(first == std::string::npos ? "" : item.substr(first, last - first + 1));
    if (value.status == io::DecimalStatus::kNotANumber) {
      const std::string hint = io::decimal_number_hint(item);
      checks.add("--M0: '" + item + "' is not a number" + (hint.empty() ? "" : ": " + hint));
      ok = false;
      continue;
    }
    preloads[index] = value.status == io::DecimalStatus::kOk ? value.value : std::strtod(item.c_str(), nullptr);
    if (!(std::isfinite(preloads[index]) && preloads[index] >= 0.0)) {
      checks.add("--M0: value " + std::to_string(index + 1) + " must be a finite preload >= 0 N m (as in rover.json), got " +
                 number_text(preloads[index]));
      ok = false;
    } else if (const std::string beyond = beyond_scale(preloads[index], kMaxPreload_Nm, "N m", kSStructureScaleReason);
               !beyond.empty()) {
      checks.add("--M0: value " + std::to_string(index + 1) + ": " + beyond);
      ok = false;
    }
  }
  if (n != preloads.size()) {
    checks.add("--M0 takes 8 values, got " + std::to_string(n));
    return std::nullopt;
  }
  if (!ok) return std::nullopt;
  return preloads;
}

// Checks the overrides (adding each problem to `checks`); call before any work.
inline void check_overrides(const InputOverrides& o, FlagChecks& checks) {
  if (o.f) checks.positive("--f", *o.f);
  if (o.c_q) checks.non_negative("--cq", *o.c_q);
  // The bounds of rover.json (core/model_scale.hpp).
  if (o.f && std::isfinite(*o.f)) {
    if (const std::string beyond = beyond_scale(*o.f, kMaxSharpness_per_rad, "1/rad", kSStructureScaleReason);
        !beyond.empty())
      checks.add("--f " + beyond);
    if (*o.f > 0.0 && *o.f < kMinSharpness_per_rad)
      checks.add("--f " + number_text(*o.f) + " 1/rad is below " + number_text(kMinSharpness_per_rad) + " 1/rad: " +
                 kSharpnessBelowScaleReason);
  }
  if (o.c_q && std::isfinite(*o.c_q))
    if (const std::string beyond = beyond_scale(*o.c_q, kMaxDamping_Nms_per_rad, "N m s/rad", kSStructureScaleReason);
        !beyond.empty())
      checks.add("--cq " + beyond);
  if (!o.M0.empty()) parse_preloads(o.M0, checks);
}

// The inputs with the overrides applied; throws CommandLineError if any is bad.
inline ModelInputs apply_overrides(const InputOverrides& o, ModelInputs in) {
  FlagChecks checks;
  check_overrides(o, checks);
  checks.throw_if_any();
  if (o.f) in.sharpness_f = *o.f;
  if (o.c_q) in.damping_c_q = *o.c_q;
  if (!o.M0.empty()) in.preload_Nm = *parse_preloads(o.M0, checks);
  return in;
}

// The rover description a command reads unless told otherwise.
inline constexpr const char* kDefaultRoverConfig = "configs/rover.json";

// The file a default path names. `relative` is relative to the repository
// root ("configs/rover.json"); when it does not exist from the working
// directory, the repository the running program belongs to is searched: the
// directories above the executable (build/drivers/rover -> ../../). Throws
// std::invalid_argument saying how to pass the file when neither exists.
inline std::string resolve_default_path(const std::string& relative, const std::string& flag) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::exists(relative, error)) return relative;
  const fs::path executable = fs::read_symlink("/proc/self/exe", error);
  constexpr int kSearchedLevels = 4;  // build/drivers/rover and deeper build trees
  if (!error) {
    fs::path dir = executable.parent_path();
    for (int level = 0; level < kSearchedLevels && !dir.empty(); ++level, dir = dir.parent_path()) {
      const fs::path candidate = dir / relative;
      if (fs::is_regular_file(candidate, error)) return candidate.lexically_normal().string();
      if (dir == dir.root_path()) break;
    }
  }
  throw std::invalid_argument("the default " + flag + " " + relative +
                              " exists neither in the working directory (" +
                              fs::current_path(error).string() +
                              ") nor in the " + std::to_string(kSearchedLevels) +
                              " directories above this program (" + executable.string() +
                              ", which a build of the repository puts in build/drivers/); run from the "
                              "repository root or pass " +
                              flag + " FILE");
}

// The value of a path option: as given, or the resolved default when not given.
inline std::string path_option(const CLI::Option* option, const std::string& value,
                               const std::string& default_relative) {
  if (option != nullptr && option->count() > 0) return value;
  return resolve_default_path(default_relative, option != nullptr ? option->get_name() : "path");
}

// The first non-finite number in `value` and where it is: "F[3]",
// "points.B_l[2]"; empty if there is none.
struct NonFiniteEntry {
  std::string where;
  double value;
};
inline std::optional<NonFiniteEntry> first_non_finite(const io::Json& value,
                                                      const std::string& path = "") {
  if (value.is_number_float() && !std::isfinite(value.get<double>()))
    return NonFiniteEntry{path, value.get<double>()};
  if (value.is_array()) {
    for (std::size_t i = 0; i < value.size(); ++i)
      if (auto entry = first_non_finite(value[i], path + "[" + std::to_string(i) + "]")) return entry;
  } else if (value.is_object()) {
    for (auto it = value.begin(); it != value.end(); ++it)
      if (auto entry = first_non_finite(it.value(), path.empty() ? it.key() : path + "." + it.key()))
        return entry;
  }
  return std::nullopt;
}

// Throws std::runtime_error naming the first non-finite quantity of `out`
// (which would print as null) and, if given, the input it came from.
inline void require_finite_output(const io::Json& out, const std::string& from_input = "") {
  if (const std::optional<NonFiniteEntry> entry = first_non_finite(out))
    throw std::runtime_error(entry->where + " is " + number_text(entry->value) + ", not a finite number" +
                             (from_input.empty() ? "" : " " + from_input) + "; nothing printed");
}

}  // namespace rover::cli
