// An audit of malformed and extreme input through the built `rover`: every
// file type (rover, scenario, terrain and drive blocks, the four study types,
// design CSVs, measured curves, reference curves) and every subcommand's
// flags, one changed field or flag per case. Each case runs `rover` once,
// under `timeout`, and checks that
//   * it neither crashes nor hangs: the exit status is 0, 1 or 2 (a signal
//     or the timeout gives another), and no raw library or runtime message
//     ("terminate called", a nlohmann exception, a std:: conversion name)
//     reaches the user;
//   * invalid input is refused with status 1 and a message naming the file
//     (or the flag), the field and the offending value;
//   * extreme but valid input runs (status 0; 2 where a run may fail and be
//     recorded as failed).
// The cases are tables; each table's runs go out four at a time (most of a
// study command's time is waiting on MPI start-up, not computing).
// Every case stays well under a second of computing: 0.05 s drops with the
// stiff integrator, two-sample studies, analytic models.
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <hdf5.h>

#include "io/csv.hpp"
#include "io/hdf5_file.hpp"
#include "io/json_reader.hpp"
#include "io/output_lock.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

namespace fs = std::filesystem;
using io::Json;
using testing::rover_binary;
using testing::run_command;
using testing::source_path;
using testing::write_file;

enum class Want {
  kError,        // status 1, and the message holds every mention
  kRuns,         // status 0
  kRunsOrFails,  // status 0, or 2 (a run failed and was recorded as failed)
  kAllFailed,    // status 2: every run failed, and the results say so
  kNotTrusted,   // status 2: the runs ran, and the result says it is not to be trusted
};

struct Case {
  std::string id;
  std::string args;  // after `rover`
  Want want;
  std::vector<std::string> mentions;  // substrings the output must hold
  // After the run: empty if the files are as they must be, else what is wrong
  // (an input or an earlier result changed, a link replaced).
  std::function<std::string()> aftermath = {};
  std::string environment = {};  // VAR=value ... before `rover`
  std::vector<std::string> absent = {};  // substrings the output must not hold (a "nan" for a number)
};

// A Case's environment that runs rover under a 3 GB address-space limit, so
// that a study too large for memory is one on every machine.
const std::string kUnder3GB = "sh -c 'ulimit -v 3000000; exec \"$0\" \"$@\"'";

struct Outcome {
  int status = -1;
  std::string output;
};

// An MPMD launch, `mpirun -np 1 rover <rank0> : -np 1 rover <rank1>`, ended
// after 120 s (status 124); stderr joins stdout.
// `rank1_environment` ("NAME=value"), if given, is set for rank 1 only.
Outcome mpmd_launch(const std::string& rank0, const std::string& rank1, const std::string& rank1_environment = "") {
  Outcome o;
  o.status = run_command("timeout 120 " + testing::mpiexec() + " -np 1 " + rover_binary() + " " + rank0 + " : -np 1 " +
                             (rank1_environment.empty() ? "" : "env " + rank1_environment + " ") + rover_binary() +
                             " " + rank1 + " 2>&1",
                         &o.output);
  return o;
}

// Messages that only a crash or an unhandled library error prints.
const std::vector<std::string> kForbidden = {
    "terminate called", "Segmentation", "core dumped", "Aborted", "[json.exception", "basic_string",
    "std::", "stod", "stoi", "vector::", "bad_alloc", "Assertion", "HDF5-DIAG",
    // CLI11's and Open MPI's own words
    "The following argument", "Could not convert", "not in range", "Run with --help", "Expected exactly",
    "Expected at least", "required TEXT", "MPI_Init", "ompi_mpi_init", "PMIx", "*** An error occurred"};

// A short horizontal drop: 0.05 s at 200 Hz with the stiff integrator.
Json quick_scenario_json() {
  return Json{{"name", "quick"},
              {"rover", source_path("configs/rover.json")},
              {"terrain", source_path("configs/terrains/flat.json")},
              {"duration", 0.05},
              {"output_rate", 200},
              {"initial_q", {{"z", 0.281}, {"chi", 0.039}, {"psi", 0.0042}}},
              {"integrator", {{"method", "rosenbrock"}}}};
}

std::string measured_text(const std::string& line_end, std::size_t rows = 40);

// Writes the files of the cases into one directory.
class Workshop {
 public:
  explicit Workshop(std::string dir) : dir_(std::move(dir)) {
    quick_ = json_file("quick", quick_scenario_json());
    // The shipped synthetic drop's first 40 rows: inside the quick run's span.
    quick_data_ = dir_ + "/quick_data.csv";
    std::ofstream(quick_data_) << measured_text("\n");
    shipped_rover_ = io::read_json_file(source_path("configs/rover.json"));
  }
  const std::string& dir() const { return dir_; }
  const std::string& quick() const { return quick_; }
  std::string out(const std::string& ext = "h5") { return dir_ + "/out_" + std::to_string(++n_) + "." + ext; }

  std::string text_file(const std::string& stem, const std::string& text, const std::string& ext = "json") {
    const std::string path = dir_ + "/" + stem + "_" + std::to_string(++n_) + "." + ext;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  std::string json_file(const std::string& stem, const Json& j) { return text_file(stem, j.dump(1)); }
  // A private copy, for a case that might destroy its input.
  std::string copy_of(const std::string& path) {
    const fs::path p(path);
    const std::string copy = dir_ + "/" + p.stem().string() + "_copy_" + std::to_string(++n_) + p.extension().string();
    fs::copy_file(p, copy);
    return copy;
  }

  // A copy of the shipped rover with `edit` applied.
  std::string rover(const std::function<void(Json&)>& edit) {
    Json j = shipped_rover_;
    edit(j);
    return json_file("rover", j);
  }
  // The quick scenario with `edit` applied.
  std::string scenario(const std::function<void(Json&)>& edit) {
    Json j = quick_scenario_json();
    edit(j);
    return json_file("scenario", j);
  }
  std::string scenario_with_rover(const std::string& rover_path) {
    return scenario([&](Json& j) { j["rover"] = rover_path; });
  }
  std::string scenario_with_terrain(const std::string& terrain_path) {
    return scenario([&](Json& j) { j["terrain"] = terrain_path; });
  }
  // The quick scenario driving `drive` for 0.05 s from 1 mm above the ground.
  std::string drive_scenario(const Json& drive) {
    return scenario([&](Json& j) {
      j.erase("initial_q");
      j["initial_ground_clearance"] = 0.001;
      j["drive"] = drive;
    });
  }

  // A 2-sample Monte Carlo of c_q on the quick drop, `edit` applied.
  std::string montecarlo(const std::function<void(Json&)>& edit) {
    Json j{{"type", "montecarlo"},
           {"name", "m"},
           {"scenario", quick_},
           {"parameters", {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}}}},
           {"design", {{"type", "monte_carlo"}, {"samples", 2}, {"seed", 1}}},
           {"qoi", {"t_min"}}};
    edit(j);
    return json_file("mc", j);
  }
  // Sobol' indices of the Ishigami function from 8 base samples, `edit` applied.
  std::string sensitivity(const std::function<void(Json&)>& edit) {
    Json j{{"type", "sensitivity"},
           {"method", "sobol"},
           {"name", "s"},
           {"model", "ishigami"},
           {"design", {{"type", "sobol"}, {"samples", 8}, {"seed", 1}}},
           {"bootstrap", 100}};
    edit(j);
    return json_file("sens", j);
  }
  // A 2 x 1 (f, c_q) surface on the quick drop, `edit` applied.
  std::string surface(const std::function<void(Json&)>& edit) {
    Json j{{"type", "surface"},
           {"name", "s"},
           {"scenario", quick_},
           {"reference", {{"simulate", {{"f", 1e4}, {"c_q", 0.14}}}}},
           {"f", {{"min", 1e3}, {"max", 1e4}, {"count", 2}, {"spacing", "log"}}},
           {"c_q", {{"min", 0.14}, {"max", 0.14}, {"count", 1}}}};
    edit(j);
    return json_file("surface", j);
  }
  // A fit of c_q to the shipped synthetic drop, `edit` applied.
  std::string calibration(const std::function<void(Json&)>& edit) {
    Json j{{"type", "calibration"},
           {"name", "c"},
           {"scenario", quick_},
           {"data", quick_data_},
           {"fit", {"c_q"}},
           {"bounds", {{"c_q", {0.02, 1.0}}, {"time_offset", {-0.2, 0.2}}}},
           {"initial", {{"c_q", 0.1}}},
           {"max_evaluations", 2}};
    edit(j);
    return json_file("cal", j);
  }

 private:
  std::string dir_, quick_, quick_data_;
  Json shipped_rover_;
  int n_ = 0;
};

// The shipped synthetic drop's rows as text, with `line_end` after each line.
std::string measured_text(const std::string& line_end, std::size_t rows) {
  std::ifstream in(source_path("configs/data/drop_horizontal_synthetic.csv"));
  std::string text, line;
  std::size_t data_rows = 0;
  while (std::getline(in, line) && data_rows <= rows) {
    if (line.empty() || line[0] == '#') continue;
    text += line + line_end;
    ++data_rows;
  }
  return text;
}

// `text` after a UTF-8 byte-order mark, as spreadsheet programs write it.
std::string with_bom(const std::string& text) {
  std::string out = "\xEF\xBB\xBF";
  out += text;
  return out;
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// An aftermath: `path` still holds what it holds now, with the same permissions.
std::function<std::string()> unchanged(const std::string& path) {
  const std::string before = file_bytes(path);
  const fs::perms mode = fs::status(path).permissions();
  return [=] {
    if (file_bytes(path) != before) return path + " was changed";
    if (fs::status(path).permissions() != mode) return path + " changed its permissions";
    return std::string();
  };
}

// An aftermath: nothing was written at `path`.
std::function<std::string()> absent_file(const std::string& path) {
  return [=] { return fs::exists(fs::symlink_status(path)) ? path + " was written" : std::string(); };
}

// An aftermath: `link` is still a symbolic link to `target`.
std::function<std::string()> still_a_link(const std::string& link, const std::string& target) {
  return [=] {
    std::error_code error;
    if (!fs::is_symlink(fs::symlink_status(link, error))) return link + " is no longer a symbolic link";
    if (fs::read_symlink(link, error) != fs::path(target)) return link + " points elsewhere";
    return std::string();
  };
}

// Runs every aftermath in `checks`; the first problem, or empty.
std::function<std::string()> all_of(std::vector<std::function<std::string()>> checks) {
  return [=] {
    for (const auto& check : checks)
      if (std::string problem = check(); !problem.empty()) return problem;
    return std::string();
  };
}

// `output` with every path under `dir` replaced by "<path>": a number a case
// expects must come from the message, not from the name of one of its
// temporary files (the folder's name is random, its files are numbered).
std::string without_paths_under(const std::string& output, const std::string& dir) {
  std::string kept;
  for (std::size_t at = 0; at < output.size();) {
    const std::size_t found = output.find(dir, at);
    kept += output.substr(at, found - at);
    if (found == std::string::npos) break;
    kept += "<path>";
    at = output.find_first_of(" :'\"\n", found);
  }
  return kept;
}

bool is_number(const std::string& text) {
  return !text.empty() && text.find_first_not_of("0123456789.-+e") == std::string::npos;
}

Outcome run_one(const std::string& dir, const Case& c) {
  Outcome o;
  // A hang is the timeout's status 124 (137 once killed), never 0, 1 or 2.
  // The limit leaves room for the slowest case (a 12 s fit, four cases at a
  // time on two cores) on a machine loaded by other work.
  // Each run is a single process: Open MPI's singleton need not start its
  // support daemon (half of a study command's start-up time).
  o.status = run_command("cd " + dir + " && OMPI_MCA_ess_singleton_isolated=1 " + c.environment +
                             " timeout -k 2 90 " + rover_binary() + " " + c.args,
                         &o.output);
  return o;
}

void run_table(const std::string& dir, const std::vector<Case>& cases) {
  std::vector<Outcome> outcomes(cases.size());
  std::atomic<std::size_t> next{0};
  std::vector<std::thread> workers;
  for (int w = 0; w < 4; ++w)
    workers.emplace_back([&] {
      for (std::size_t i = next++; i < cases.size(); i = next++) outcomes[i] = run_one(dir, cases[i]);
    });
  for (std::thread& t : workers) t.join();
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const Outcome& o = outcomes[i];
    SCOPED_TRACE(c.id + ": rover " + c.args + "\n" + o.output);
    EXPECT_TRUE(o.status == 0 || o.status == 1 || o.status == 2) << "crash or hang: status " << o.status;
    for (const std::string& bad : kForbidden) EXPECT_EQ(o.output.find(bad), std::string::npos) << "'" << bad << "'";
    switch (c.want) {
      case Want::kError: EXPECT_EQ(o.status, 1); break;
      case Want::kRuns: EXPECT_EQ(o.status, 0); break;
      case Want::kRunsOrFails: EXPECT_TRUE(o.status == 0 || o.status == 2) << o.status; break;
      case Want::kAllFailed:
      case Want::kNotTrusted: EXPECT_EQ(o.status, 2); break;
    }
    const std::string message = without_paths_under(o.output, dir);
    for (const std::string& m : c.mentions)
      EXPECT_NE((is_number(m) ? message : o.output).find(m), std::string::npos) << "missing '" << m << "'";
    for (const std::string& a : c.absent) EXPECT_EQ(o.output.find(a), std::string::npos) << "'" << a << "'";
    if (c.aftermath) {
      const std::string problem = c.aftermath();
      EXPECT_TRUE(problem.empty()) << problem;
    }
  }
}

class Audit : public ::testing::Test {
 protected:
  void SetUp() override { w_ = std::make_unique<Workshop>(testing::temp_dir()); }
  Workshop& w() { return *w_; }
  // `rover simulate` of `scenario`, without a plot.
  std::string simulate(const std::string& scenario) {
    return "simulate --no-plot --scenario " + scenario + " --out " + w().out();
  }
  std::string study(const std::string& command, const std::string& path) {
    return study_args(command, path, w().out());
  }
  static std::string study_args(const std::string& command, const std::string& path, const std::string& out) {
    return command + " --no-plot --study " + path + " --out " + out;
  }
  // A curve as HDF5 (t, B_l_z, ...): the quick drop simulated into `path`.
  std::string simulated_curve(const std::string& path) {
    std::string output;
    EXPECT_EQ(run_command(rover_binary() + " simulate --no-plot --scenario " + w().quick() + " --out " + path + ".h5",
                          &output),
              0)
        << output;
    fs::rename(path + ".h5", path);
    return path;
  }

 private:
  std::unique_ptr<Workshop> w_;
};

// ---- rover.json: a copy with one field changed -------------------------------

TEST_F(Audit, RoverFile) {
  std::vector<Case> cases;
  auto rover_case = [&](const std::string& id, const std::function<void(Json&)>& edit, Want want,
                        std::vector<std::string> mentions) {
    const std::string path = w().rover(edit);
    if (want == Want::kError) mentions.insert(mentions.begin(), path);
    cases.push_back({id, simulate(w().scenario_with_rover(path)), want, mentions});
  };
  rover_case("gravity as a string", [](Json& j) { j["gravity"] = "9.81"; }, Want::kError, {"'gravity'", "9.81"});
  rover_case("negative gravity", [](Json& j) { j["gravity"] = -9.81; }, Want::kError, {"'gravity'", "-9.81"});
  rover_case("zero gravity", [](Json& j) { j["gravity"] = 0.0; }, Want::kRuns, {});
  rover_case("huge gravity", [](Json& j) { j["gravity"] = 1e300; }, Want::kError, {"'gravity'", "1e+300", "100 m/s^2"});
  rover_case("a chassis of 1e-30 kg", [](Json& j) { j["bodies"]["chassis"]["mass"] = 1e-30; }, Want::kError,
             {"mass'", "1e-30 kg is below 0.01 kg", "tonnes?"});
  rover_case("wheel centre as an object",
             [](Json& j) { j["geometry"]["wheel_centre"] = {{"x", 0.168}, {"y", 0.089}, {"z", -0.033}}; },
             Want::kError, {"'geometry.wheel_centre'", "0.168"});
  rover_case("bogie pivot of 2 numbers", [](Json& j) { j["geometry"]["bogie_pivot"] = {0.0, 0.1325}; },
             Want::kError, {"'geometry.bogie_pivot'", "0.1325", "expected 3 numbers, got 2"});
  rover_case("wheel com of strings", [](Json& j) { j["bodies"]["wheel"]["com"] = {"0", "0", "0"}; }, Want::kError,
             {"'bodies.wheel.com'", "\"0\""});
  rover_case("inertia entry \"NaN\"", [](Json& j) { j["bodies"]["chassis"]["inertia"][1][1] = "NaN"; },
             Want::kError, {"'bodies.chassis.inertia'", "NaN"});
  rover_case("bodies as an array", [](Json& j) { j["bodies"] = Json::array(); }, Want::kError, {"'bodies'", "[]"});
  rover_case("body missing", [](Json& j) { j["bodies"].erase("module1"); }, Want::kError,
             {"'bodies.module1'", "missing"});
  rover_case("preload order reversed",
             [](Json& j) { j["s_structure"]["preload_order"] = {"42", "41", "32", "31", "22", "21", "12", "11"}; },
             Want::kError, {"'s_structure.preload_order'", "\"42\""});
  rover_case("negative preload sd", [](Json& j) { j["s_structure"]["preload_sd"][2] = -0.089; }, Want::kError,
             {"'s_structure.preload_sd'", "-0.089"});
  rover_case("zero sharpness", [](Json& j) { j["s_structure"]["f"] = 0.0; }, Want::kError, {"'s_structure.f'", "0"});
  rover_case("negative k_q", [](Json& j) { j["s_structure"]["k_q"] = -9.91; }, Want::kError,
             {"'s_structure.k_q'", "-9.91"});
  rover_case("c_q as a string", [](Json& j) { j["s_structure"]["c_q"] = "0.14"; }, Want::kError,
             {"'s_structure.c_q'", "0.14"});
  rover_case("steering limit zero", [](Json& j) { j["steering"]["limit"] = 0.0; }, Want::kError,
             {"'steering.limit'", "0"});
  rover_case("steering limit beyond pi", [](Json& j) { j["steering"]["limit"] = 4.0; }, Want::kRuns, {});
  rover_case("zero drive torque", [](Json& j) { j["drive"]["tau_max"] = 0.0; }, Want::kError,
             {"'drive.tau_max'", "0"});
  rover_case("negative contact sigma", [](Json& j) { j["contact"]["sigma"] = -1.8; }, Want::kError,
             {"'contact.sigma'", "-1.8"});
  rover_case("negative mu_s", [](Json& j) { j["friction"]["mu_s"] = -0.3; }, Want::kError,
             {"'friction.mu_s'", "-0.3"});
  rover_case("zero v_s", [](Json& j) { j["friction"]["v_s"] = 0.0; }, Want::kError, {"'friction.v_s'", "0"});
  rover_case("v_k below v_s", [](Json& j) { j["friction"]["v_k"] = 1e-4; }, Want::kError,
             {"'friction.v_k'", "0.0001"});
  rover_case("5 gammas", [](Json& j) { j["friction"]["gammas"].erase(5); }, Want::kError,
             {"'friction.gammas'", "expected 6 numbers, got 5"});
  rover_case("gammas_fitted_to of strings",
             [](Json& j) { j["friction"]["gammas_fitted_to"] = {"0.3", "5.5e-4", "0.2", "2.0e-3"}; }, Want::kError,
             {"'friction.gammas_fitted_to'", "\"0.3\""});
  rover_case("non-ASCII key in a body", [](Json& j) { j["bodies"]["wheel"]["масса"] = 0.231; }, Want::kError,
             {"'bodies.wheel.масса'", "unknown key"});
  rover_case("description as a number", [](Json& j) { j["description"] = 5; }, Want::kError,
             {"'description'", "5"});
  rover_case("huge wheel inertia",
             [](Json& j) { j["bodies"]["wheel"]["inertia"] = {{1e300, 0, 0}, {0, 1e300, 0}, {0, 0, 1e300}}; },
             Want::kError, {"'bodies.wheel.inertia'", "1e+300", "+-1 kg m^2"});
  rover_case("friction far beyond synthesis",
             [](Json& j) {
               j["friction"]["mu_s"] = 1e308;  // its gammas would overflow a double
               j["friction"].erase("gammas");
               j["friction"].erase("gammas_fitted_to");
             },
             Want::kError, {"'friction.mu_s'", "1e+308", "+-10,"});
  // Raw text: duplicate keys, a trailing comma, a NUL byte, empty, an array.
  const std::string shipped = [] {
    std::ifstream in(source_path("configs/rover.json"));
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }();
  auto raw_case = [&](const std::string& id, const std::string& text, std::vector<std::string> mentions) {
    const std::string path = w().text_file("rover_raw", text);
    mentions.insert(mentions.begin(), path);
    cases.push_back({id, simulate(w().scenario_with_rover(path)), Want::kError, mentions});
  };
  std::string dup = shipped;
  dup.replace(dup.find("\"c_g\": 100.0"), 12, "\"c_g\": 100.0, \"c_g\": 50.0");
  raw_case("key given twice", dup, {"'contact.c_g'", "twice"});
  // Syntax errors: "file:line:column: field '...'".
  std::string trailing = shipped;
  trailing.replace(trailing.find("\"sigma\": 1.8}"), 13, "\"sigma\": 1.8,}");
  raw_case("trailing comma", trailing, {"'contact.sigma'", "a comma before '}'"});
  std::string nul = shipped;
  nul[nul.find("9.81")] = '\0';
  raw_case("NUL byte", nul, {"holds a NUL byte"});
  raw_case("empty file", "", {":1:1:"});
  raw_case("a top-level array", "[" + shipped + "]", {"<top level>"});
  std::string beyond = shipped;
  beyond.replace(beyond.find("1.0e6"), 5, "1e400");
  raw_case("number beyond a double", beyond, {"'contact.k_g'", "1e400"});
  run_table(w().dir(), cases);
}

// ---- scenario files -----------------------------------------------------------

TEST_F(Audit, ScenarioFile) {
  std::vector<Case> cases;
  auto scenario_case = [&](const std::string& id, const std::function<void(Json&)>& edit, Want want,
                           std::vector<std::string> mentions) {
    const std::string path = w().scenario(edit);
    if (want == Want::kError) mentions.insert(mentions.begin(), path);
    cases.push_back({id, simulate(path), want, mentions});
  };
  scenario_case("duration as a string", [](Json& j) { j["duration"] = "0.05"; }, Want::kError, {"'duration'", "0.05"});
  scenario_case("tiny duration", [](Json& j) { j["duration"] = 1e-300; }, Want::kError, {"'duration'", "1e-300"});
  scenario_case("output rate below one sample", [](Json& j) { j["output_rate"] = 1e-3; }, Want::kError,
                {"'duration'", "output_rate 0.001 Hz"});
  scenario_case("initial_q as an array", [](Json& j) { j["initial_q"] = Json::array({0.0, 0.0, 0.281}); },
                Want::kError, {"'initial_q'", "0.281"});
  scenario_case("initial_q.z as a string", [](Json& j) { j["initial_q"]["z"] = "high"; }, Want::kError,
                {"'initial_q.z'", "high"});
  scenario_case("fast initial speed", [](Json& j) { j["initial_u"] = {{"x", 50.0}}; }, Want::kError,
                {"'initial_u'", "50 m/s is beyond +-10 m/s"});
  scenario_case("initial yaw of 1e10 rad", [](Json& j) { j["initial_q"]["theta"] = 1e10; }, Want::kError,
                {"theta = 1e+10 rad", "a full turn", "an angle in degrees?"});
  scenario_case("3 wheel speeds", [](Json& j) { j["wheel_speed_ref"] = {1.0, 1.0, 1.0}; }, Want::kError,
                {"'wheel_speed_ref'", "expected 4 numbers, got 3"});
  scenario_case("steering beyond the end-stop", [](Json& j) { j["steer_ref"] = {0.0, 0.0, -10.0, 0.0}; },
                Want::kError, {"'steer_ref'", "element 2 (-10 rad)"});
  scenario_case("integrator method a number", [](Json& j) { j["integrator"] = {{"method", 5}}; }, Want::kError,
                {"'integrator.method'", "5"});
  scenario_case("zero rtol", [](Json& j) { j["integrator"]["rtol"] = 0.0; }, Want::kError,
                {"'integrator.rtol'", "0"});
  scenario_case("initial step above the max step",
                [](Json& j) { j["integrator"] = {{"method", "dopri5"}, {"initial_step", 0.1}, {"max_step", 0.01}}; },
                Want::kError, {"'integrator", "initial_step"});
  scenario_case("integrator as a string", [](Json& j) { j["integrator"] = "rosenbrock"; }, Want::kError,
                {"'integrator'", "rosenbrock"});
  scenario_case("rk4 step of 1e-300 s", [](Json& j) { j["integrator"] = {{"method", "rk4"}, {"fixed_step", 1e-300}}; },
                Want::kError, {"'integrator.fixed_step'", "1e-300"});
  scenario_case("zero wall-time budget", [](Json& j) { j["wall_time_budget"] = 0; }, Want::kError,
                {"'wall_time_budget'", "0"});
  scenario_case("M0 override with a string", [](Json& j) { j["inputs"] = {{"M0", {1, 1, 1, "1", 1, 1, 1, 1}}}; },
                Want::kError, {"'inputs.M0'", "element 3"});
  scenario_case("zero f override", [](Json& j) { j["inputs"] = {{"f", 0}}; }, Want::kError, {"'inputs.f'", "0"});
  scenario_case("unknown input", [](Json& j) { j["inputs"] = {{"k_q", 5}}; }, Want::kError,
                {"'inputs.k_q'", "unknown key"});
  scenario_case("non-ASCII name", [](Json& j) { j["name"] = "падение"; }, Want::kRuns, {});
  scenario_case("empty rover path", [](Json& j) { j["rover"] = ""; }, Want::kError, {"'rover'", "\"\""});
  scenario_case("terrain as a number", [](Json& j) { j["terrain"] = 5; }, Want::kError, {"'terrain'", "5"});
  scenario_case("forward speed as a word", [](Json& j) { j["forward_speed"] = "fast"; }, Want::kError,
                {"'forward_speed'", "fast"});
  scenario_case("travel distance backwards",
                [](Json& j) {
                  j.erase("duration");
                  j["travel_distance"] = 1.0;
                  j["forward_speed"] = -1.0;
                },
                Want::kError, {"'travel_distance'", "forward_speed"});
  scenario_case("negative ground clearance", [](Json& j) { j["initial_ground_clearance"] = -1.0; }, Want::kError,
                {"'initial_ground_clearance'", "-1"});
  scenario_case("drop from 100 m", [](Json& j) {
                  j.erase("initial_q");
                  j["initial_ground_clearance"] = 100.0;
                }, Want::kError, {"'initial_ground_clearance'", "lands at 44", "beyond +-10 m/s"});
  const std::string wrong_rover = w().scenario([&](Json& j) { j["rover"] = w().quick(); });
  cases.push_back({"a rover path that is a scenario", simulate(wrong_rover), Want::kError, {w().quick(), "'rover'", "a scenario file", "not a rover file"}});
  scenario_case("rover path a directory", [&](Json& j) { j["rover"] = w().dir(); }, Want::kError,
                {"'rover'", "is a directory"});
  // Raw text.
  auto raw_case = [&](const std::string& id, const std::string& text, Want want, std::vector<std::string> mentions) {
    const std::string path = w().text_file("scenario_raw", text);
    if (want == Want::kError) mentions.insert(mentions.begin(), path);
    cases.push_back({id, simulate(path), want, mentions});
  };
  std::string crlf;
  for (const char c : with_bom(quick_scenario_json().dump(1))) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  raw_case("byte-order mark and CRLF", crlf, Want::kRuns, {});
  raw_case("a top-level string", "\"quick\"", Want::kError, {"<top level>"});
  raw_case("NUL inside a string", std::string("{\"name\": \"q\0x\"}", 15), Want::kError, {":1:12:", "holds a NUL byte"});
  // Paths that are not regular readable JSON files.
  cases.push_back({"scenario is missing", simulate(w().dir() + "/none.json"), Want::kError,
                   {"--scenario", w().dir() + "/none.json"}});
  cases.push_back({"scenario is /dev/null", simulate("/dev/null"), Want::kError, {"/dev/null"}});
  cases.push_back({"scenario is unreadable", simulate("/proc/self/mem"), Want::kError, {"/proc/self/mem"}});
  run_table(w().dir(), cases);
}

// ---- terrain files ------------------------------------------------------------

TEST_F(Audit, TerrainFile) {
  std::vector<Case> cases;
  auto terrain_case = [&](const std::string& id, const Json& terrain, Want want, std::vector<std::string> mentions) {
    const std::string path = w().json_file("terrain", terrain);
    if (want == Want::kError) mentions.insert(mentions.begin(), path);
    cases.push_back({id, simulate(w().scenario_with_terrain(path)), want, mentions});
  };
  const Json heights2x2 = {{0.0, 0.0}, {0.0, 0.0}};
  auto grid = [&](const Json& counts, const Json& spacing, const Json& heights) {
    return Json{{"type", "grid"}, {"origin", {-1.0, -1.0}}, {"spacing", spacing}, {"counts", counts}, {"heights", heights}};
  };
  terrain_case("zero counts", grid({0, 0}, {2.0, 2.0}, Json::array()), Want::kError, {"'counts'", "0"});
  terrain_case("rows do not match counts", grid({2, 3}, {2.0, 1.0}, heights2x2), Want::kError, {"'heights'", "3"});
  terrain_case("zero spacing", grid({2, 2}, {0.0, 2.0}, heights2x2), Want::kError, {"'spacing'", "0"});
  terrain_case("negative spacing", grid({2, 2}, {-2.0, 2.0}, heights2x2), Want::kError, {"'spacing'", "-2"});
  terrain_case("null height", grid({2, 2}, {2.0, 2.0}, {{0.0, nullptr}, {0.0, 0.0}}), Want::kError,
               {"'heights'", "null"});
  terrain_case("a billion nodes", grid({1000000000, 1000000000}, {1e-3, 1e-3}, heights2x2), Want::kError,
               {"'counts'", "1000000000"});
  terrain_case("fractional count", grid({2.5, 2}, {2.0, 2.0}, heights2x2), Want::kError, {"'counts'", "2.5"});
  terrain_case("origin of one number", Json{{"type", "grid"}, {"origin", {0.0}}, {"spacing", {2.0, 2.0}},
                                            {"counts", {2, 2}}, {"heights", heights2x2}},
               Want::kError, {"'origin'", "expected 2 numbers, got 1"});
  terrain_case("type in capitals", Json{{"type", "Flat"}}, Want::kError, {"'type'", "Flat"});
  terrain_case("height as a string", Json{{"type", "flat"}, {"height", "0"}}, Want::kError, {"'height'", "\"0\""});
  const std::string high_ground = w().scenario_with_terrain(w().json_file("terrain", Json{{"type", "flat"}, {"height", 1000.0}}));
  cases.push_back({"ground 1 km up", simulate(high_ground), Want::kError,
                   {high_ground, "'initial_q'", "1000 m below the ground"}});
  terrain_case("a 1 x 1 grid", grid({1, 1}, {1.0, 1.0}, {{0.0}}), Want::kError, {"'counts'", "[1,1]"});
  const Json control_grid = {{"origin", {-1.0, -1.0}}, {"spacing", {0.5, 0.5}}, {"counts", {5, 5}}};
  terrain_case("two control points",
               Json{{"type", "control_points"}, {"points", {{0, 0, 0}, {1, 1, 0}}}, {"grid", control_grid}},
               Want::kError, {"'points'", "2"});
  terrain_case("collinear control points",
               Json{{"type", "control_points"}, {"points", {{0, 0, 0}, {1, 1, 0}, {2, 2, 0}, {3, 3, 0}}},
                    {"grid", control_grid}},
               Want::kError, {"'points'", "one line"});
  terrain_case("repeated control point",
               Json{{"type", "control_points"}, {"points", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0.1}}},
                    {"grid", control_grid}},
               Want::kError, {"'points'", "(1, 0, 0.1)"});
  terrain_case("unknown interpolation",
               Json{{"type", "control_points"}, {"points", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {"grid", control_grid},
                    {"method", "kriging"}},
               Want::kError, {"'method'", "kriging"});
  terrain_case("no type", Json{{"height", 0.0}}, Want::kError, {"'type'", "missing"});
  terrain_case("empty object", Json::object(), Want::kError, {"'type'"});
  const std::string csv = w().text_file("terrain_csv", "x,y,z\n0,0,0\n", "csv");
  cases.push_back({"a CSV as terrain", simulate(w().scenario_with_terrain(csv)), Want::kError, {csv}});
  run_table(w().dir(), cases);
}

// ---- drive blocks -------------------------------------------------------------

TEST_F(Audit, DriveBlock) {
  std::vector<Case> cases;
  auto drive_case = [&](const std::string& id, const Json& drive, Want want, std::vector<std::string> mentions) {
    const std::string path = w().drive_scenario(drive);
    if (want == Want::kError) mentions.insert(mentions.begin(), path);
    cases.push_back({id, simulate(path), want, mentions});
  };
  const Json ack = {{"mode", "ackermann"}, {"speed", 0.3}, {"radius", 1.0}};
  drive_case("no segments", {{"segments", Json::array()}}, Want::kError, {"'drive.segments'"});
  drive_case("segments as an object", {{"segments", ack}}, Want::kError, {"'drive.segments'", "ackermann"});
  drive_case("unknown mode", {{"segments", {{{"mode", "tank"}, {"speed", 0.3}}}}}, Want::kError,
             {"'drive.segments[0].mode'", "tank"});
  drive_case("starts going back",
             {{"segments", {ack, {{"start", 0.03}, {"mode", "car"}, {"speed", 0.1}},
                            {{"start", 0.02}, {"mode", "car"}, {"speed", 0.2}}}}},
             Want::kError, {"'drive.segments'", "segment 2 starts at 0.02"});
  drive_case("first start later", {{"segments", {{{"start", 0.5}, {"mode", "car"}, {"speed", 0.3}}}}}, Want::kError,
             {"'drive.segments[0].start'", "0.5"});
  drive_case("negative ramp", {{"ramp_time", -1.0}, {"segments", {ack}}}, Want::kError, {"'drive.ramp_time'", "-1"});
  drive_case("ramp as a string", {{"ramp_time", "0.3"}, {"segments", {ack}}}, Want::kError,
             {"'drive.ramp_time'", "0.3"});
  drive_case("allow_flip \"yes\"", {{"allow_flip", "yes"}, {"segments", {ack}}}, Want::kError,
             {"'drive.allow_flip'", "yes"});
  drive_case("unknown initial motion", {{"initial_motion", "moving"}, {"segments", {ack}}}, Want::kError,
             {"'drive.initial_motion'", "moving"});
  drive_case("ackermann about G", {{"segments", {{{"mode", "ackermann"}, {"speed", 0.3}, {"radius", 0.0}}}}},
             Want::kError, {"'drive.segments[0]", "radius"});
  drive_case("ICR at G", {{"segments", {{{"mode", "general-ackermann"}, {"speed", 0.3}, {"icr", {0.0, 0.0}}}}}},
             Want::kError, {"'drive.segments[0]'", "the ICR is G"});
  drive_case("crab angle of 100 rad", {{"segments", {{{"mode", "parallel"}, {"speed", 0.2}, {"crab_angle", 100.0}}}}},
             Want::kError, {"'drive.segments[0].crab_angle'", "100"});
  drive_case("rotation with a forward speed", {{"segments", {{{"mode", "rotation"}, {"forward", 0.1}}}}},
             Want::kError, {"'drive.segments[0]'", "v_x 0.1 m/s"});
  drive_case("speed \"NaN\"", {{"segments", {{{"mode", "car"}, {"speed", "NaN"}}}}}, Want::kError,
             {"'drive.segments[0].speed'", "NaN"});
  drive_case("speed and forward", {{"segments", {{{"mode", "car"}, {"speed", 0.1}, {"forward", 0.1}}}}},
             Want::kError, {"'drive.segments[0].forward'"});
  drive_case("misspelt key", {{"segments", {{{"mode", "car"}, {"spd", 0.1}}}}}, Want::kError,
             {"'drive.segments[0]", "spd"});
  drive_case("speed of 1e300 m/s", {{"segments", {{{"mode", "car"}, {"speed", 1e300}}}}}, Want::kError,
             {"'drive.segments[0].speed'", "1e+300"});
  drive_case("a standstill", {{"segments", {{{"mode", "car"}, {"speed", 0.0}}}}}, Want::kRuns, {});
  // A drive with the references it replaces, or with a travel distance.
  const std::string with_steer = w().scenario([&](Json& j) {
    j["drive"] = {{"segments", {ack}}};
    j["steer_ref"] = {0, 0, 0, 0};
  });
  cases.push_back({"drive and steer_ref", simulate(with_steer), Want::kError, {with_steer, "'steer_ref'"}});
  const std::string with_distance = w().scenario([&](Json& j) {
    j.erase("duration");
    j["travel_distance"] = 1.0;
    j["drive"] = {{"segments", {ack}}};
  });
  cases.push_back({"drive and travel distance", simulate(with_distance), Want::kError,
                   {with_distance, "'travel_distance'"}});
  run_table(w().dir(), cases);
}

// ---- Monte Carlo study files --------------------------------------------------

TEST_F(Audit, MonteCarloStudy) {
  std::vector<Case> cases;
  auto mc_case = [&](const std::string& id, const std::function<void(Json&)>& edit, Want want,
                     std::vector<std::string> mentions) {
    const std::string path = w().montecarlo(edit);
    if (want == Want::kError) mentions.insert(mentions.begin(), path);
    cases.push_back({id, study("montecarlo", path), want, mentions});
  };
  auto param = [](const Json& spec) { return [spec](Json& j) { j["parameters"] = spec; }; };
  auto c_q = [&](const Json& spec) { return param({{"c_q", spec}}); };
  mc_case("no parameters", param(Json::object()), Want::kError, {"'parameters'"});
  mc_case("parameters as an array", param(Json::array({"c_q"})), Want::kError, {"'parameters'", "c_q"});
  mc_case("non-ASCII parameter name", param({{"ц_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}}}),
          Want::kError, {"'parameters.ц_q'"});
  mc_case("one parameter twice by two names",
          param({{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}},
                 {"s_structure.c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}}}),
          Want::kError, {"'parameters.s_structure.c_q'", "same parameter as 'c_q'"});
  mc_case("distribution in capitals", c_q({{"distribution", "Uniform"}, {"min", 0.1}, {"max", 0.2}}), Want::kError,
          {"'parameters.c_q.distribution'", "Uniform"});
  mc_case("min as a string", c_q({{"distribution", "uniform"}, {"min", "0.1"}, {"max", 0.2}}), Want::kError,
          {"'parameters.c_q.min'", "0.1"});
  mc_case("zero sd", c_q({{"distribution", "normal"}, {"sd", 0.0}}), Want::kError, {"'parameters.c_q.sd'", "0"});
  mc_case("negative sd_percent", c_q({{"distribution", "normal"}, {"sd_percent", -5}}), Want::kError,
          {"'parameters.c_q.sd_percent'", "-5"});
  mc_case("lognormal of negative mean", c_q({{"distribution", "lognormal"}, {"mean", -1.0}, {"sd", 0.1}}),
          Want::kError, {"'parameters.c_q.mean'", "-1"});
  mc_case("zero log_sd", c_q({{"distribution", "lognormal"}, {"log_mean", -2.0}, {"log_sd", 0.0}}), Want::kError,
          {"'parameters.c_q.log_sd'", "0"});
  mc_case("log_uniform from 0", c_q({{"distribution", "log_uniform"}, {"min", 0.0}, {"max", 0.2}}), Want::kError,
          {"'parameters.c_q.min'", "0"});
  mc_case("fixed value a word", c_q({{"distribution", "fixed"}, {"value", "x"}}), Want::kError,
          {"'parameters.c_q.value'", "\"x\""});
  mc_case("truncation reversed", c_q({{"distribution", "normal"}, {"sd", 0.01}, {"truncate", {0.3, 0.1}}}),
          Want::kError, {"'parameters.c_q.truncate'", "0.3"});
  mc_case("preload truncation of strings", param({{"M0", {{"from_config", true}, {"truncate", {"a", nullptr}}}}}),
          Want::kError, {"'parameters.M0.truncate'", "\"a\""});
  mc_case("preload truncation reversed", param({{"M0", {{"from_config", true}, {"truncate", {3.0, 2.0}}}}}),
          Want::kError, {"'parameters.M0.truncate'", "[3.0,2.0]"});
  mc_case("preload truncation far in the tail", param({{"M0_11", {{"from_config", true}, {"truncate", {100.0, nullptr}}}}}),
          Want::kError, {"'parameters.M0_11", "100"});
  mc_case("negative sd_scale", param({{"M0_11", {{"from_config", true}, {"sd_scale", -1.0}}}}), Want::kError,
          {"'parameters.M0_11.sd_scale'", "-1"});
  mc_case("from_config on c_q", c_q({{"from_config", true}}), Want::kError, {"'parameters.c_q.from_config'"});
  mc_case("design type halton", [](Json& j) { j["design"]["type"] = "halton"; }, Want::kError,
          {"'design.type'", "halton"});
  mc_case("negative samples", [](Json& j) { j["design"]["samples"] = -3; }, Want::kError, {"'design.samples'", "-3"});
  mc_case("fractional samples", [](Json& j) { j["design"]["samples"] = 2.5; }, Want::kError,
          {"'design.samples'", "2.5"});
  mc_case("negative seed", [](Json& j) { j["design"]["seed"] = -1; }, Want::kError, {"'design.seed'", "-1"});
  mc_case("seed beyond 2^64", [](Json& j) { j["design"]["seed"] = 1e300; }, Want::kError,
          {"'design.seed'", "1e+300"});
  mc_case("zero grid levels", [](Json& j) { j["design"] = {{"type", "grid"}, {"levels", 0}}; }, Want::kError,
          {"'design.levels'", "0"});
  mc_case("grid levels of another input", [](Json& j) { j["design"] = {{"type", "grid"}, {"levels", {{"f", 3}}}}; },
          Want::kError, {"'design.levels'", "c_q"});
  mc_case("a seed of a grid", [](Json& j) { j["design"] = {{"type", "grid"}, {"levels", 3}, {"seed", 4}}; },
          Want::kError, {"'design.seed'", "4", "draws nothing"});
  mc_case("grid of a normal",
          [](Json& j) {
            j["parameters"]["c_q"] = {{"distribution", "normal"}, {"sd", 0.01}};
            j["design"] = {{"type", "grid"}, {"levels", 3}};
          },
          Want::kError, {"'design.type'", "normal"});
  mc_case("grid of 1e10 points",
          [](Json& j) {
            j["parameters"]["f"] = {{"distribution", "uniform"}, {"min", 1e3}, {"max", 1e4}};
            j["design"] = {{"type", "grid"}, {"levels", 100000}};
          },
          Want::kError, {"'design.levels'", "more than 100000000 points"});
  mc_case("no QoIs", [](Json& j) { j["qoi"] = Json::array(); }, Want::kError, {"'qoi'", "[]"});
  mc_case("QoI a number", [](Json& j) { j["qoi"] = {5}; }, Want::kError, {"'qoi[0]'", "got 5"});
  mc_case("QoI twice", [](Json& j) { j["qoi"] = {"t_min", "t_min"}; }, Want::kError, {"'qoi[1]'", "t_min"});
  mc_case("negative settling band", [](Json& j) { j["qoi"] = {{{"name", "settling_time"}, {"band", -1e-3}}}; },
          Want::kError, {"'qoi[0].band'", "-0.001"});
  mc_case("rms_vs of a missing curve",
          [&](Json& j) { j["qoi"] = {{{"name", "rms_vs"}, {"reference", w().dir() + "/missing.csv"}}}; },
          Want::kError, {"'qoi[0].reference'", "missing.csv"});
  mc_case("channels as a string", [](Json& j) { j["channels"] = "B_l_z"; }, Want::kError, {"'channels'", "B_l_z"});
  mc_case("channel Fn_5", [](Json& j) { j["channels"] = {"Fn_5"}; }, Want::kError, {"'channels[0]'", "Fn_5"});
  mc_case("confidence 1.5", [](Json& j) { j["confidence"] = 1.5; }, Want::kError, {"'confidence'", "1.5"});
  mc_case("confidence 0", [](Json& j) { j["confidence"] = 0; }, Want::kError, {"'confidence'", "0"});
  mc_case("negative bootstrap", [](Json& j) { j["bootstrap"] = -1; }, Want::kError, {"'bootstrap'", "-1"});
  mc_case("a billion bootstrap resamples", [](Json& j) { j["bootstrap"] = 1000000000; }, Want::kError,
          {"'bootstrap'", "1000000000"});
  mc_case("type of another study", [](Json& j) { j["type"] = "sensitivity"; }, Want::kError,
          {"'type'", "sensitivity"});
  mc_case("empty name", [](Json& j) { j["name"] = ""; }, Want::kError, {"'name'", "\"\""});
  mc_case("scenario and model", [](Json& j) { j["model"] = "ishigami"; }, Want::kError, {"'scenario'"});
  mc_case("scenario that is a study", [&](Json& j) { j["scenario"] = w().montecarlo([](Json&) {}); }, Want::kError,
          {"'scenario'"});
  cases.push_back({"results beyond memory", study("montecarlo", w().montecarlo([](Json& j) {
                     j["design"]["samples"] = 100000000;
                     j["qoi"] = {"B_l_z_min", "t_min", "deflection", "at_rest", "rebound_peak", "settling_time",
                                 "max_abs_pitch", "max_abs_roll", "max_wheel_load", "B_r_rise", "G_rise"};
                   })),
                   Want::kError, {"N = 100000000", "GB", "in memory"}, {}, kUnder3GB});
  mc_case("non-ASCII name and description",
          [](Json& j) {
            j["name"] = "étude";
            j["description"] = "Monte-Carlo über c_q";
          },
          Want::kRuns, {});
  // Raw text: a parameter given twice.
  const std::string twice = w().text_file(
      "mc_raw", R"({"type": "montecarlo", "name": "m", "scenario": ")" + w().quick() +
                    R"(", "parameters": {"c_q": {"distribution": "uniform", "min": 0.1, "max": 0.2},
                    "c_q": {"distribution": "uniform", "min": 0.2, "max": 0.3}},
                    "design": {"type": "monte_carlo", "samples": 2}, "qoi": ["t_min"]})");
  cases.push_back({"parameter key twice", study("montecarlo", twice), Want::kError, {twice, "'parameters.c_q'", "twice"}});
  run_table(w().dir(), cases);
}

// ---- sensitivity study files --------------------------------------------------

TEST_F(Audit, SensitivityStudy) {
  std::vector<Case> cases;
  auto s_case = [&](const std::string& id, const std::function<void(Json&)>& edit, Want want,
                    std::vector<std::string> mentions) {
    const std::string path = w().sensitivity(edit);
    if (want == Want::kError) mentions.insert(mentions.begin(), path);
    cases.push_back({id, study("sensitivity", path), want, mentions});
  };
  auto morris = [](Json& j) {
    j["method"] = "morris";
    j["design"] = {{"trajectories", 4}, {"levels", 4}, {"seed", 1}};
  };
  s_case("method fast", [](Json& j) { j["method"] = "fast"; }, Want::kError, {"'method'", "fast"});
  s_case("unknown estimator", [](Json& j) { j["estimator"] = "sobol"; }, Want::kError, {"'estimator'", "sobol"});
  s_case("failed fraction above 1", [](Json& j) { j["max_failed_fraction"] = 2; }, Want::kError,
         {"'max_failed_fraction'", "2"});
  s_case("one base sample", [](Json& j) { j["design"]["samples"] = 1; }, Want::kError, {"'design.samples'", "1"});
  s_case("second_order \"yes\"", [](Json& j) { j["second_order"] = "yes"; }, Want::kError,
         {"'second_order'", "yes"});
  s_case("unknown model", [](Json& j) { j["model"] = "ishigami2"; }, Want::kError, {"'model'", "ishigami2"});
  s_case("input the model lacks",
         [](Json& j) { j["parameters"] = {{"x4", {{"distribution", "uniform"}, {"min", 0}, {"max", 1}}}}; },
         Want::kError, {"'parameters.x4'"});
  s_case("one Morris level", [&](Json& j) { morris(j); j["design"]["levels"] = 1; }, Want::kError,
         {"'design.levels'", "1"});
  s_case("no Morris trajectories", [&](Json& j) { morris(j); j["design"]["trajectories"] = 0; }, Want::kError,
         {"'design.trajectories'", "0"});
  s_case("Morris with samples", [&](Json& j) { morris(j); j["design"]["samples"] = 8; }, Want::kError,
         {"'design.samples'"});
  s_case("a grid for Sobol'", [](Json& j) { j["design"] = {{"type", "grid"}, {"levels", 3}}; }, Want::kError,
         {"'design.type'", "grid"});
  s_case("bootstrap as a string", [](Json& j) { j["bootstrap"] = "10"; }, Want::kError, {"'bootstrap'", "10"});
  s_case("Morris of the Ishigami function", morris, Want::kRuns, {});
  s_case("Sobol' of the Ishigami function", [](Json&) {}, Want::kRuns, {});
  run_table(w().dir(), cases);
}

// ---- study-level reliability: degenerate QoIs and parameters, failed studies ---

TEST_F(Audit, StudyLevelReliability) {
  std::vector<Case> cases;
  const Json uniform_c_q{{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}};
  const Json off_diagonal{{"distribution", "uniform"}, {"min", -0.01}, {"max", 0.01}};
  const std::string inertia = "bodies.chassis.inertia[0][1]";
  // Parameters that cannot vary alone: refused, named, before any run.
  for (const auto& [id, name] : std::vector<std::pair<std::string, std::string>>{
           {"montecarlo of an off-diagonal inertia", inertia},
           {"montecarlo of a module's off-diagonal inertia", "bodies.module1.inertia[0][2]"}}) {
    const std::string path = w().montecarlo([&](Json& j) { j["parameters"] = {{name, off_diagonal}}; });
    cases.push_back({id, study("montecarlo", path), Want::kError, {path, "'parameters'", name, "cannot vary alone"}});
  }
  const std::string sens_inertia = w().sensitivity([&](Json& j) {
    j.erase("model");
    j["scenario"] = w().quick();
    j["parameters"] = {{"c_q", uniform_c_q}, {inertia, off_diagonal}};
    j["qoi"] = {"B_l_z_min"};
  });
  cases.push_back({"sobol of an off-diagonal inertia", study("sensitivity", sens_inertia), Want::kError,
                   {sens_inertia, inertia, "cannot vary alone"}});
  // In the quick 0.05 s drop the rover has not landed: t_min is the end time in
  // every run, while the lowest B_l z follows the drop height.
  for (const std::string method : {"sobol", "morris"}) {
    const std::string path = w().sensitivity([&](Json& j) {
      j.erase("model");
      j["method"] = method;
      if (method == "morris") j["design"] = {{"trajectories", 4}, {"levels", 4}, {"seed", 1}};
      j["scenario"] = w().quick();
      j["parameters"] = {{"c_q", uniform_c_q},
                         {"scenario.initial_q.z", {{"distribution", "uniform"}, {"min", 0.28}, {"max", 0.29}}}};
      j["qoi"] = {"t_min", "B_l_z_min"};
    });
    cases.push_back({method + " with a constant QoI", study("sensitivity", path), Want::kRuns,
                     {"t_min: indices undefined", "constant"}});
  }
  // A distribution reaching where the model refuses every run: refused, named, before any run.
  const Json in_the_ground{{"distribution", "uniform"}, {"min", -0.6}, {"max", -0.5}};
  const std::string into_ground =
      w().montecarlo([&](Json& j) { j["parameters"] = {{"scenario.initial_q.z", in_the_ground}}; });
  cases.push_back({"montecarlo of a drop height inside the ground", study("montecarlo", into_ground), Want::kError,
                   {into_ground, "'scenario.initial_q.z'", "reaches -0.6", "below the ground"}});
  const std::string into_ground_sobol = w().sensitivity([&](Json& j) {
    j.erase("model");
    j["scenario"] = w().quick();
    j["parameters"] = {{"c_q", uniform_c_q}, {"scenario.initial_q.z", in_the_ground}};
    j["qoi"] = {"t_min"};
  });
  cases.push_back({"sobol of a drop height inside the ground", study("sensitivity", into_ground_sobol), Want::kError,
                   {"'scenario.initial_q.z'", "reaches -0.6"}});
  // Every run failed (each exceeds its wall-time budget): the results are kept, the status is 2.
  const std::string all_fail = w().montecarlo(
      [&](Json& j) { j["scenario"] = w().scenario([](Json& s) { s["wall_time_budget"] = 1e-9; }); });
  cases.push_back({"montecarlo where every run fails", study("montecarlo", all_fail), Want::kAllFailed,
                   {"every run failed"}});
  const std::string all_fail_calibration = w().calibration(
      [&](Json& j) { j["scenario"] = w().scenario([](Json& s) { s["wall_time_budget"] = 1e-9; }); });
  cases.push_back({"calibrate where every run fails", study("calibrate", all_fail_calibration), Want::kAllFailed,
                   {"NOT CONVERGED", "wall-time budget used up", "every run failed"}});
  run_table(w().dir(), cases);
}

// ---- surface study files ------------------------------------------------------

TEST_F(Audit, SurfaceStudy) {
  std::vector<Case> cases;
  auto s_case = [&](const std::string& id, const std::function<void(Json&)>& edit, Want want,
                    std::vector<std::string> mentions) {
    const std::string path = w().surface(edit);
    if (want == Want::kError) mentions.insert(mentions.begin(), path);
    cases.push_back({id, study("surface", path), want, mentions});
  };
  s_case("a billion f points", [](Json& j) { j["f"]["count"] = 1000000000; }, Want::kError,
         {"'f.count'", "1000000000"});
  s_case("cubic spacing", [](Json& j) { j["c_q"]["spacing"] = "cubic"; }, Want::kError, {"'c_q.spacing'", "cubic"});
  s_case("log spacing from 0", [](Json& j) { j["c_q"] = {{"min", 0.0}, {"max", 0.2}, {"count", 2}, {"spacing", "log"}}; },
         Want::kError,
         {"'c_q.min'", "must be > 0 on a log-spaced axis", "\"spacing\": \"linear\" to include 0"});
  s_case("linear spacing from no damping",
         [](Json& j) { j["c_q"] = {{"min", 0.0}, {"max", 0.2}, {"count", 2}, {"spacing", "linear"}}; }, Want::kRuns,
         {});
  s_case("linear spacing from negative damping",
         [](Json& j) { j["c_q"] = {{"min", -0.1}, {"max", 0.2}, {"count", 2}}; }, Want::kError,
         {"'c_q.min'", "-0.1", "must not be negative"});
  s_case("empty reference", [](Json& j) { j["reference"] = Json::object(); }, Want::kError, {"'reference.file'"});
  s_case("missing reference file", [&](Json& j) { j["reference"] = {{"file", w().dir() + "/none.csv"}}; },
         Want::kError, {"'reference.file'", "none.csv"});
  s_case("reference with a negative f", [](Json& j) { j["reference"] = {{"simulate", {{"f", -1.0}}}}; },
         Want::kError, {"'reference.simulate.f'", "-1"});
  s_case("sweep c_q a word",
         [](Json& j) { j["sweep"] = {{"f", {{"min", 1e2}, {"max", 1e4}, {"count", 3}}}, {"c_q", "x"}}; },
         Want::kError, {"'sweep.c_q'", "x"});
  s_case("sweep of two points (r^2 = 1 by construction)",
         [](Json& j) { j["sweep"] = {{"f", {{"min", 1e2}, {"max", 1e4}, {"count", 2}}}, {"c_q", 0.14}}; },
         Want::kError, {"'sweep.f.count'", "count 3 or more"});
  s_case("sweep of no points",
         [](Json& j) { j["sweep"] = {{"f", {{"min", 1e2}, {"max", 1e4}, {"count", 0}}}, {"c_q", 0.14}}; },
         Want::kError, {"'sweep.f.count'", "0"});
  s_case("f min a string", [](Json& j) { j["f"]["min"] = "1e3"; }, Want::kError, {"'f.min'", "1e3"});
  s_case("f axis a number", [](Json& j) { j["f"] = 1e3; }, Want::kError, {"'f'", "1000"});
  s_case("a single point", [](Json& j) { j["f"] = {{"min", 1e4}, {"max", 1e4}, {"count", 1}}; }, Want::kRuns, {});
  // A reference file with NUL bytes, and one with CRLF line ends and a BOM.
  const std::string nul = w().text_file("ref_nul", "t,z\n0,0.25\n0.01,0.2\0\n0.02,0.2\n" + std::string(1, '\0'), "csv");
  s_case("reference with a NUL byte", [&](Json& j) { j["reference"] = {{"file", nul}}; }, Want::kError, {nul});
  const std::string crlf = w().text_file("ref_crlf", with_bom(measured_text("\r\n")), "csv");
  s_case("reference with CRLF", [&](Json& j) { j["reference"] = {{"file", crlf}}; }, Want::kRuns, {});
  run_table(w().dir(), cases);
}

// ---- calibration study files --------------------------------------------------

TEST_F(Audit, CalibrationStudy) {
  std::vector<Case> cases;
  auto c_case = [&](const std::string& id, const std::function<void(Json&)>& edit, std::vector<std::string> mentions) {
    const std::string path = w().calibration(edit);
    mentions.insert(mentions.begin(), path);
    cases.push_back({id, study("calibrate", path), Want::kError, mentions});
  };
  c_case("fit k_g", [](Json& j) { j["fit"] = {"k_g"}; }, {"'fit'", "k_g"});
  c_case("fit nothing", [](Json& j) { j["fit"] = Json::array(); }, {"'fit'", "[]"});
  c_case("one bound", [](Json& j) { j["bounds"]["c_q"] = {0.1}; }, {"'bounds.c_q'", "expected 2 numbers, got 1"});
  c_case("initial a string", [](Json& j) { j["initial"]["c_q"] = "0.1"; }, {"'initial.c_q'", "0.1"});
  c_case("unknown algorithm", [](Json& j) { j["algorithm"] = "LN_FOO"; }, {"'algorithm'", "LN_FOO"});
  c_case("no evaluations", [](Json& j) { j["max_evaluations"] = 0; }, {"'max_evaluations'", "0"});
  c_case("negative starts", [](Json& j) { j["starts"] = -1; }, {"'starts'", "-1"});
  c_case("method gibbs", [](Json& j) { j["method"] = "gibbs"; }, {"'method'", "gibbs"});
  c_case("odd walkers", [](Json& j) { j["method"] = "mcmc"; j["mcmc"] = {{"walkers", 3}}; },
         {"'mcmc.walkers'", "3"});
  c_case("no steps", [](Json& j) { j["method"] = "mcmc"; j["mcmc"] = {{"steps", 0}}; }, {"'mcmc.steps'", "0"});
  c_case("discard beyond steps", [](Json& j) { j["method"] = "mcmc"; j["mcmc"] = {{"steps", 10}, {"discard", 20}}; },
         {"'mcmc.discard'", "20"});
  c_case("negative noise", [](Json& j) { j["method"] = "mcmc"; j["mcmc"] = {{"noise_sd", -1e-4}}; },
         {"'mcmc.noise_sd'", "-0.0001", "outside the noise sds from 1e-12 to 1000 m"});
  c_case("zero noise", [](Json& j) { j["method"] = "mcmc"; j["mcmc"] = {{"noise_sd", 0}}; },
         {"'mcmc.noise_sd'", "0 m, outside the noise sds from 1e-12 to 1000 m"});
  c_case("prior of an unknown distribution", [](Json& j) { j["priors"] = {{"c_q", {{"distribution", "beta"}}}}; },
         {"'priors.c_q.distribution'", "beta"});
  c_case("prior of an unknown parameter",
         [](Json& j) { j["priors"] = {{"k", {{"distribution", "uniform"}, {"min", 0}, {"max", 1}}}}; },
         {"'priors.k'", "unknown key"});
  c_case("no data", [](Json& j) { j["data"] = Json::array(); }, {"'data'", "[]"});
  c_case("data of a channel that is no height (pitch)",
         [](Json& j) {
           j["data"] = {{{"file", source_path("configs/data/drop_horizontal_synthetic.csv")}, {"channel", "pitch"}}};
         },
         {"'data[0].channel'", "pitch", "B_l_z"});
  const std::string header_only = w().text_file("header_only", "t,z\n", "csv");
  cases.push_back({"data of a header only", study("calibrate", w().calibration([&](Json& j) { j["data"] = header_only; })),
                   Want::kError, {header_only, "no data rows"}});
  c_case("one profile point", [](Json& j) { j["profile_points"] = 1; }, {"'profile_points'", "1"});
  run_table(w().dir(), cases);
}

// ---- design CSVs of `rover evaluate` ------------------------------------------

TEST_F(Audit, EvaluateDesign) {
  std::vector<Case> cases;
  auto evaluate = [&](const std::string& design, const std::string& extra = "") {
    return "evaluate --scenario " + w().quick() + " --design " + design + " --qoi t_min --out " + w().out("csv") +
           extra;
  };
  auto design_case = [&](const std::string& id, const std::string& text, Want want, std::vector<std::string> mentions) {
    const std::string path = w().text_file("design", text, "csv");
    if (want == Want::kError) mentions.insert(mentions.begin(), path);
    cases.push_back({id, evaluate(path), want, mentions});
  };
  design_case("a header only", "c_q,f\n", Want::kError, {"no rows"});
  design_case("CRLF line ends", "c_q,f\r\n0.1,1e4\r\n0.2,1e3\r\n", Want::kRuns, {});
  design_case("a trailing comma", "c_q,f\n0.1,1e4,\n", Want::kError, {":2", "expected 2 values, got 3"});
  design_case("an extra column", "c_q\n0.1,0.2\n", Want::kError, {":2", "expected 1 values, got 2"});
  design_case("unknown column", "c_qq\n0.1\n", Want::kError, {"c_qq"});
  design_case("a column twice", "c_q,c_q\n0.1,0.2\n", Want::kError, {"columns 1 and 2"});
  design_case("alias and name", "c_q,s_structure.c_q\n0.1,0.2\n", Want::kError, {"columns 1 and 2"});
  design_case("NaN cell", "c_q\nNaN\n", Want::kError, {":2", "NaN"});
  design_case("inf cell", "f\ninf\n", Want::kError, {":2", "inf"});
  design_case("empty cell", "c_q,f\n0.1,\n", Want::kError, {":2", "column 2"});
  design_case("NUL byte", std::string("c_q\n0.1\0\n", 9), Want::kError, {":2"});
  design_case("non-ASCII column", "ц_q\n0.1\n", Want::kError, {"ц_q"});
  design_case("negative mass", "bodies.wheel.mass\n-0.2\n", Want::kError, {":2", "-0.2", "bodies.wheel.mass"});
  design_case("a semicolon-separated file", "c_q;f\n0.1;1e4\n", Want::kError,
              {"the header 'c_q;f' is separated by semicolons ';'", "comma-separated values only"});
  design_case("a tab-separated file", "c_q\tf\n0.1\t1e4\n", Want::kError, {"separated by tabs"});
  // Flags and paths.
  const std::string good = w().text_file("design_good", "c_q\n0.1\n", "csv");
  cases.push_back({"design is a directory", "evaluate --scenario " + w().quick() + " --design " + w().dir() +
                                                " --qoi t_min --out " + w().out("csv"),
                   Want::kError, {"--design", w().dir()}});
  const std::string design_copy = w().copy_of(good);
  cases.push_back({"output over the design", "evaluate --scenario " + w().quick() + " --design " + design_copy +
                                                 " --qoi t_min --out " + design_copy,
                   Want::kError, {"--out", design_copy, "same file as --design"}});
  const std::string design_link = w().dir() + "/design_link.csv";
  fs::create_symlink(design_copy, design_link);
  cases.push_back({"output over the design by a link", "evaluate --scenario " + w().quick() + " --design " +
                                                           design_copy + " --qoi t_min --out " + design_link,
                   Want::kError, {"--out", design_link, "symbolic link"}});
  const std::string scenario_copy = w().copy_of(w().quick());
  cases.push_back({"output over the scenario", "evaluate --scenario " + scenario_copy + " --design " + good +
                                                   " --qoi t_min --out " + scenario_copy,
                   Want::kError, {"--out", scenario_copy}});
  cases.push_back({"design is unreadable", "evaluate --scenario " + w().quick() +
                                               " --design /proc/self/mem --qoi t_min --out " + w().out("csv"),
                   Want::kError, {"/proc/self/mem"}});
  cases.push_back({"output .txt", "evaluate --scenario " + w().quick() + " --design " + good + " --qoi t_min --out " +
                                      w().dir() + "/y.txt",
                   Want::kError, {"--out", "y.txt"}});
  cases.push_back({"unknown QoI", "evaluate --scenario " + w().quick() + " --design " + good + " --qoi t_max --out " +
                                      w().out("csv"),
                   Want::kError, {"--qoi", "t_max"}});
  cases.push_back({"empty QoI list", "evaluate --scenario " + w().quick() + " --design " + good + " --qoi , --out " +
                                         w().out("csv"),
                   Want::kError, {"--qoi"}});
  cases.push_back({"channels into a CSV", evaluate(good, " --channels B_l_z"), Want::kError, {"--channels"}});
  cases.push_back({"zero progress interval", evaluate(good, " --progress-interval 0"), Want::kError,
                   {"--progress-interval", "0"}});
  cases.push_back({"integrator in capitals", evaluate(good, " --integrator RK4"), Want::kError, {"--integrator", "RK4"}});
  cases.push_back({"output under /proc", "evaluate --scenario " + w().quick() + " --design " + good +
                                             " --qoi t_min --out /proc/rover_audit/y.csv",
                   Want::kError, {"/proc/rover_audit/y.csv"}});
  cases.push_back({"output under a file", "evaluate --scenario " + w().quick() + " --design " + good +
                                              " --qoi t_min --out " + good + "/y.csv",
                   Want::kError, {good + "/y.csv"}});
  run_table(w().dir(), cases);
}

// ---- measured curves (rover compare) ------------------------------------------

TEST_F(Audit, MeasuredCurve) {
  std::vector<Case> cases;
  const std::string shipped = source_path("configs/data/drop_horizontal_synthetic.csv");
  auto curve_case = [&](const std::string& id, const std::string& text, Want want, std::vector<std::string> mentions) {
    const std::string path = w().text_file("curve", text, "csv");
    if (want == Want::kError) mentions.insert(mentions.begin(), path);
    cases.push_back({id, "compare " + path + " " + shipped + " --rest-time 0.05", want, mentions});
  };
  curve_case("BOM and CRLF", with_bom(measured_text("\r\n")), Want::kRuns, {});
  curve_case("a header only", "t,z\n", Want::kError, {"no data rows"});
  curve_case("two rows", "t,z\n0,0.25\n0.01,0.25\n", Want::kError, {"at least 3"});
  curve_case("time going back", "t,z\n0,0.25\n0.02,0.25\n0.01,0.25\n0.03,0.25\n", Want::kError, {":4", "0.01"});
  curve_case("millimetres", "t,z\n0,250\n0.01,2500\n0.02,250\n", Want::kError, {":3", "2500"});
  curve_case("a trailing comma", "t,z\n0,0.25,\n0.01,0.25,\n0.02,0.25,\n", Want::kError, {":2", "got 3"});
  curve_case("an extra column in a row", "t,z\n0,0.25\n0.01,0.25,7\n0.02,0.25\n", Want::kError, {":3", "got 3"});
  curve_case("a NUL byte", std::string("t,z\n0,0.25\n0.01,0.2\0\n0.02,0.25\n", 31), Want::kError, {":3"});
  curve_case("z column missing", "t,height\n0,0.25\n0.01,0.25\n0.02,0.25\n", Want::kError, {"'z'"});
  curve_case("a repeated time", "t,z\n0,0.25\n0,0.24\n0.02,0.25\n", Want::kError, {":3"});
  const std::string good = w().text_file("curve_good", measured_text("\n"), "csv");
  cases.push_back({"curve is a directory", "compare " + w().dir() + " " + shipped, Want::kError, {w().dir()}});
  cases.push_back({"rest time nan", "compare " + good + " " + shipped + " --rest-time nan", Want::kError,
                   {"--rest-time", "nan"}});
  cases.push_back({"time offset beyond a double", "compare " + good + " " + shipped + " --time-offset 1e400",
                   Want::kError, {"--time-offset", "inf"}});
  cases.push_back({"curve is unreadable", "compare /proc/self/mem " + shipped, Want::kError, {"/proc/self/mem"}});
  const std::string fake_h5 = w().text_file("fake", "t,z\n0,1\n", "h5");
  cases.push_back({"text named .h5", "compare " + fake_h5 + " " + shipped, Want::kError, {fake_h5}});
  cases.push_back({"curve is missing", "compare " + w().dir() + "/none.csv " + shipped, Want::kError,
                   {"A", w().dir() + "/none.csv"}});
  run_table(w().dir(), cases);
}

// ---- reference curves of rms_vs QoIs ------------------------------------------

TEST_F(Audit, ReferenceCurve) {
  std::vector<Case> cases;
  auto reference_case = [&](const std::string& id, const std::string& text, Want want,
                            std::vector<std::string> mentions) {
    const std::string curve = w().text_file("reference", text, "csv");
    const std::string path = w().montecarlo([&](Json& j) {
      j["qoi"] = {{{"name", "rms_vs"}, {"reference", curve}, {"time_offset", 0.05}}};
    });
    if (want == Want::kError) mentions.insert(mentions.begin(), {path, "'qoi[0].reference'", curve});
    cases.push_back({id, study("montecarlo", path), want, mentions});
  };
  reference_case("a header only", "t,z\n", Want::kError, {});
  reference_case("CRLF and a comment", "# made by hand\r\n" + measured_text("\r\n"), Want::kRuns, {});
  reference_case("an infinite height", "t,z\n0,0.25\n0.01,inf\n0.02,0.25\n", Want::kError, {":3"});
  reference_case("millimetres", "t,z\n0,250\n0.01,2500\n0.02,250\n", Want::kError, {"2500"});
  reference_case("extra columns", "t,z,w\n0,0.25\n0.01,0.25\n0.02,0.25\n", Want::kError, {":2"});
  reference_case("a NUL byte", std::string("t,z\n0,0.25\n\0\n0.02,0.25\n", 24), Want::kError, {":3"});
  run_table(w().dir(), cases);
}

// ---- flags of every subcommand ------------------------------------------------

TEST_F(Audit, Flags) {
  std::vector<Case> cases;
  const std::string q = w().quick();
  const std::string mc = w().montecarlo([](Json&) {});
  const std::string sobol = w().sensitivity([](Json&) {});
  const std::string surface = w().surface([](Json&) {});
  const std::string calibration = w().calibration([](Json&) {});
  const std::string plain = w().text_file("plain", "x", "txt");
  const std::string state = w().json_file("state", Json{{"q", std::vector<double>(23, 0.0)}, {"u", std::vector<double>(23, 0.0)}});
  auto flag_case = [&](const std::string& id, const std::string& args, std::vector<std::string> mentions) {
    cases.push_back({id, args, Want::kError, mentions});
  };
  const std::string sim = "simulate --no-plot --scenario " + q;
  flag_case("--f beyond a double", sim + " --out " + w().out() + " --f 1e400", {"--f", "inf"});
  flag_case("--f empty", sim + " --out " + w().out() + " --f ''", {"--f was given an empty value"});
  flag_case("--cq blank", sim + " --out " + w().out() + " --cq ' '", {"--cq"});
  flag_case("--out empty", sim + " --out ''", {"--out was given an empty value"});
  flag_case("--M0 of empty values", sim + " --out " + w().out() + " --M0 ,,,,,,,", {"--M0"});
  flag_case("--M0 with a trailing comma", sim + " --out " + w().out() + " --M0 1,1,1,1,1,1,1,1,",
            {"--M0 '1,1,1,1,1,1,1,1,': ends with a comma"});
  const std::string q1 = w().copy_of(q), q2 = w().copy_of(q), q3 = w().copy_of(q);
  flag_case("--out over the scenario", "simulate --no-plot --scenario " + q1 + " --out " + q1,
            {"--out", q1, "same file as --scenario"});
  flag_case("--csv over the scenario", "simulate --no-plot --scenario " + q2 + " --out " + w().out() + " --csv " + q2,
            {"--csv", q2, "same file as --scenario"});
  flag_case("--csv over --out", sim + " --out " + w().dir() + "/same.h5 --csv " + w().dir() + "/./same.h5",
            {"--csv", "same file as --out", "same.h5"});
  flag_case("--out under a file", sim + " --out " + plain + "/x.h5", {"--out", plain + "/x.h5"});
  flag_case("--out under /proc", sim + " --out /proc/rover_audit/x.h5", {"--out", "/proc/rover_audit/x.h5"});
  const std::string synth = "synthesize --scenario " + q;
  flag_case("synthesize over its scenario", "synthesize --scenario " + q3 + " --out " + q3,
            {"--out", q3, "same file as --scenario"});
  flag_case("synthesize at 1e12 Hz", synth + " --out " + w().out("csv") + " --rate 1e12", {"--rate", "1e+12"});
  flag_case("synthesize fractional seed", synth + " --out " + w().out("csv") + " --seed 1.5", {"--seed", "1.5"});
  flag_case("synthesize nan offset", synth + " --out " + w().out("csv") + " --offset nan", {"--offset", "nan"});
  flag_case("friction --png under /proc", "friction --png /proc/rover_audit/f.png", {"--png", "/proc/rover_audit/f.png"});
  flag_case("friction huge mu_s", "friction --mu-s 1e308", {"--mu-s", "1e+308"});
  flag_case("friction v_k below v_s", "friction --v-s 0.01 --v-k 0.001", {"v_k (0.001 m/s)", "v_s (0.01 m/s)", "--v-k"});
  flag_case("friction --v-s above the config's v_k", "friction --v-s 0.005", {"v_k (0.002 m/s)", "v_s (0.005 m/s)", "--v-s"});
  flag_case("terrain spacing of 1 nm", "terrain obstacle --out " + w().out("json") + " --spacing 1e-9",
            {"--spacing", "1e-09"});
  flag_case("terrain --png over --out",
            "terrain obstacle --out " + w().dir() + "/t.json --png " + w().dir() + "/t.json", {"--png", "same file as --out"});
  flag_case("terrain height 1e300", "terrain obstacle --out " + w().out("json") + " --height 1e300",
            {"--height", "1e+300"});
  flag_case("kinematics car about its axle", "kinematics --mode car --v 0.5 --radius 0", {"--radius 0", "zero turning radius"});
  flag_case("kinematics speed of 1e308", "kinematics --mode car --v 1e308", {"--v", "1e+308"});
  flag_case("kinematics lateral nan", "kinematics --mode lateral --v nan", {"--v", "nan"});
  flag_case("eom state of 22 coordinates",
            "eom --state " + w().json_file("state22", Json{{"q", std::vector<double>(22, 0.0)},
                                                          {"u", std::vector<double>(23, 0.0)}}),
            {"'q'", "expected 23 numbers, got 22"});
  flag_case("eom preloads of strings",
            "eom --state " + w().json_file("state_m0", Json{{"q", std::vector<double>(23, 0.0)},
                                                           {"u", std::vector<double>(23, 0.0)},
                                                           {"params", {{"M0", std::vector<std::string>(8, "1")}}}}),
            {"'params.M0'", "element 0"});
  flag_case("eom unknown key",
            "eom --state " + w().json_file("state_key", Json{{"q", std::vector<double>(23, 0.0)},
                                                            {"u", std::vector<double>(23, 0.0)},
                                                            {"qdot", 1}}),
            {"'qdot'", "unknown key"});
  flag_case("eom --config a directory", "eom --state " + state + " --config " + w().dir(), {"--config", w().dir()});
  flag_case("montecarlo --samples 1e-3", study("montecarlo", mc) + " --samples 1e-3", {"--samples", "1e-3", "whole number"});
  flag_case("montecarlo --seed beyond 2^64", study("montecarlo", mc) + " --seed 18446744073709551616",
            {"--seed", "18446744073709551616"});
  flag_case("montecarlo --checkpoint-every 0", study("montecarlo", mc) + " --checkpoint-every 0",
            {"--checkpoint-every", "0"});
  const std::string mc_copy = w().copy_of(mc);
  flag_case("montecarlo --out over the study", "montecarlo --no-plot --study " + mc_copy + " --out " + mc_copy,
            {"--out", mc_copy});
  flag_case("montecarlo --out under a file", "montecarlo --no-plot --study " + mc + " --out " + plain + "/m.h5",
            {plain + "/m.h5"});
  const std::string garbage_out = w().dir() + "/garbage.h5";
  write_file(garbage_out + ".checkpoint", "this is not a checkpoint\n");
  flag_case("montecarlo --resume of a garbage checkpoint",
            "montecarlo --no-plot --study " + mc + " --resume --out " + garbage_out, {garbage_out + ".checkpoint"});
  flag_case("sensitivity --samples 1", study("sensitivity", sobol) + " --samples 1", {"--samples", "1"});
  flag_case("sensitivity --progress-interval 0", study("sensitivity", sobol) + " --progress-interval 0",
            {"--progress-interval", "0"});
  flag_case("surface --integrator euler", study("surface", surface) + " --integrator euler",
            {"--integrator", "euler"});
  flag_case("calibrate --walkers 0", study("calibrate", calibration) + " --method mcmc --walkers 0",
            {"--walkers", "got 0"});
  flag_case("calibrate --walkers 2 for 2 sampled parameters",
            study("calibrate", calibration) + " --method mcmc --walkers 2", {"--walkers: got 2", "at least 4"});
  flag_case("calibrate --fit twice", study("calibrate", calibration) + " --fit c_q,c_q", {"c_q", "twice"});
  flag_case("calibrate --data a header only",
            study("calibrate", calibration) + " --data " + w().text_file("hdr", "t,z\n", "csv"), {"hdr"});
  flag_case("calibrate --max-evaluations -5", study("calibrate", calibration) + " --max-evaluations -5",
            {"--max-evaluations must be from 1 to 100000000, got -5"});
  flag_case("calibrate --out under /proc",
            "calibrate --no-plot --study " + calibration + " --out /proc/rover_audit/c.h5", {"/proc/rover_audit/c.h5"});
  cases.push_back({"montecarlo --resume without a checkpoint",
                   "montecarlo --no-plot --study " + mc + " --resume --out " + w().out(), Want::kRuns, {}});
  run_table(w().dir(), cases);
}

// ---- class 1: files named inside a config are inputs too ------------

TEST_F(Audit, InputsNamedInConfigs) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  // A refused output leaves the input it would have replaced as it was.
  auto refused = [&](const std::string& id, const std::string& args, const std::string& input,
                     std::vector<std::string> mentions) {
    cases.push_back({id, args, Want::kError, std::move(mentions), unchanged(input)});
  };
  const std::string rover = w().copy_of(source_path("configs/rover.json"));
  const std::string scenario = w().scenario_with_rover(rover);
  refused("simulate --out over the scenario's rover", "simulate --no-plot --scenario " + scenario + " --out " + rover,
          rover, {"--out", rover, "'rover' in " + scenario});
  refused("simulate --csv over the scenario's rover",
          "simulate --no-plot --scenario " + scenario + " --out " + w().out() + " --csv " + rover, rover,
          {"--csv", "'rover' in " + scenario});
  fs::create_directories(dir + "/sub");
  refused("simulate --out over the rover, spelt with ./ and ..",
          "simulate --no-plot --scenario " + scenario + " --out " + dir + "/./sub/../" + fs::path(rover).filename().string(),
          rover, {"--out", "'rover' in"});
  const std::string hard_link = dir + "/rover_hard_link.json";
  fs::create_hard_link(rover, hard_link);
  refused("simulate --out on a hard link of the rover", "simulate --no-plot --scenario " + scenario + " --out " + hard_link,
          rover, {"--out", hard_link, "'rover' in"});
  const std::string terrain = w().json_file("terrain", Json{{"type", "flat"}, {"height", 0.0}});
  const std::string on_terrain = w().scenario_with_terrain(terrain);
  refused("simulate --csv over the scenario's terrain",
          "simulate --no-plot --scenario " + on_terrain + " --out " + w().out() + " --csv " + terrain, terrain,
          {"--csv", terrain, "'terrain' in " + on_terrain});
  // The plot <out stem>.png would be renamed onto a rover file of that name.
  const std::string rover_png = dir + "/drop.png";
  fs::copy_file(source_path("configs/rover.json"), rover_png);
  const std::string png_scenario = w().scenario_with_rover(rover_png);
  refused("simulate's plot over the scenario's rover", "simulate --scenario " + png_scenario + " --out " + dir + "/drop.h5",
          rover_png, {"--out", "plot", "'rover' in " + png_scenario});
  refused("synthesize over the scenario's terrain",
          "synthesize --scenario " + on_terrain + " --out " + terrain, terrain, {"--out", "'terrain' in"});
  const std::string rover_csv = dir + "/rover_as.csv";
  fs::copy_file(rover, rover_csv);
  const std::string csv_scenario = w().scenario_with_rover(rover_csv);
  refused("evaluate --out over the scenario's rover file",
          "evaluate --scenario " + csv_scenario + " --design " + w().text_file("design", "c_q\n0.1\n", "csv") +
              " --qoi t_min --out " + rover_csv,
          rover_csv, {"--out", "'rover' in " + csv_scenario});
  // Studies: the scenario, what the scenario names, reference curves, data.
  const std::string mc_scenario = w().copy_of(w().quick());
  const std::string mc = w().montecarlo([&](Json& j) { j["scenario"] = mc_scenario; });
  refused("montecarlo --out over the study's scenario", "montecarlo --no-plot --study " + mc + " --out " + mc_scenario,
          mc_scenario, {"--out", "'scenario' in " + mc});
  const std::string deep_rover = w().copy_of(source_path("configs/rover.json"));
  const std::string deep = w().montecarlo([&](Json& j) { j["scenario"] = w().scenario_with_rover(deep_rover); });
  refused("montecarlo --out over the rover its scenario names",
          "montecarlo --no-plot --study " + deep + " --out " + deep_rover, deep_rover, {"--out", "'rover' in"});
  const std::string curve = simulated_curve(dir + "/reference.h5");
  const std::string with_reference = w().montecarlo([&](Json& j) {
    j["qoi"] = {{{"name", "rms_vs"}, {"reference", curve}}};
  });
  refused("montecarlo --out over a reference curve", "montecarlo --no-plot --study " + with_reference + " --out " + curve,
          curve, {"--out", "'qoi[0].reference' in " + with_reference});
  const std::string surface_reference = simulated_curve(dir + "/surface_reference.h5");
  const std::string surface = w().surface([&](Json& j) { j["reference"] = {{"file", surface_reference}}; });
  refused("surface --out over its reference file", "surface --no-plot --study " + surface + " --out " + surface_reference,
          surface_reference, {"--out", "'reference.file' in " + surface});
  const std::string data = w().text_file("data", measured_text("\n"), "h5");
  const std::string calibration = w().calibration([&](Json& j) { j["data"] = data; });
  refused("calibrate --out over the study's data", "calibrate --no-plot --study " + calibration + " --out " + data, data,
          {"--out", "'data' in " + calibration});
  // A plot <out stem>_*.png would be renamed onto the study's scenario.
  const std::string scenario_png = dir + "/mc_result_summary.png";
  fs::copy_file(w().quick(), scenario_png);
  const std::string mc_named_png = w().montecarlo([&](Json& j) { j["scenario"] = scenario_png; });
  refused("montecarlo's plots over the study's scenario",
          "montecarlo --study " + mc_named_png + " --out " + dir + "/mc_result.h5", scenario_png,
          {"--out", "plot", "'scenario' in"});
  // The checkpoint <out>.checkpoint would be made over the scenario.
  const std::string checkpoint_named = dir + "/cp.h5.checkpoint";
  fs::copy_file(w().quick(), checkpoint_named);
  const std::string cp_study = w().montecarlo([&](Json& j) { j["scenario"] = checkpoint_named; });
  refused("montecarlo's checkpoint over the study's scenario",
          "montecarlo --no-plot --restart --study " + cp_study + " --out " + dir + "/cp.h5", checkpoint_named,
          {dir + "/cp.h5.checkpoint", "is no checkpoint of rover", "never removes such a file"});
  // The default --out, results/<name>.h5, is checked as well.
  fs::create_directories(dir + "/results");
  const std::string default_target = dir + "/results/named.h5";
  fs::copy_file(w().quick(), default_target);
  const std::string named = w().montecarlo([&](Json& j) {
    j["name"] = "named";
    j["scenario"] = default_target;
  });
  refused("montecarlo's default --out over its scenario", "montecarlo --no-plot --study " + named, default_target,
          {"--out (default)", "'scenario' in"});
  run_table(dir, cases);
}

// ---- class 2: what stands at an output path --------------------------

TEST_F(Audit, OutputPaths) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  const std::string q = w().quick();
  const std::string sim = "simulate --no-plot --scenario " + q;
  auto earlier_result = [&](const std::string& name, fs::perms mode) {
    const std::string path = dir + "/" + name;
    write_file(path, "an earlier result\n");
    fs::permissions(path, mode);
    return path;
  };
  const fs::perms read_only = fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read;
  const std::string ro_h5 = earlier_result("ro.h5", read_only);
  cases.push_back({"simulate --out read-only", sim + " --out " + ro_h5, Want::kError,
                   {"--out", ro_h5, "read-only", "0444"}, unchanged(ro_h5)});
  const std::string ro_csv = earlier_result("ro.csv", read_only);
  cases.push_back({"simulate --csv read-only", sim + " --out " + w().out() + " --csv " + ro_csv, Want::kError,
                   {"--csv", ro_csv, "read-only"}, unchanged(ro_csv)});
  const std::string ro_png = earlier_result("ro.png", read_only);
  cases.push_back({"terrain --png read-only", "terrain obstacle --out " + w().out("json") + " --png " + ro_png,
                   Want::kError, {"--png", ro_png, "read-only"}, unchanged(ro_png)});
  const std::string ro_terrain = earlier_result("ro_terrain.json", read_only);
  cases.push_back({"terrain --out read-only", "terrain obstacle --out " + ro_terrain, Want::kError,
                   {"--out", ro_terrain, "read-only"}, unchanged(ro_terrain)});
  const std::string ro_mc = earlier_result("ro_mc.h5", read_only);
  cases.push_back({"montecarlo --out read-only", study_args("montecarlo", w().montecarlo([](Json&) {}), ro_mc),
                   Want::kError, {"--out", ro_mc, "read-only"}, unchanged(ro_mc)});
  const std::string ro_synth = earlier_result("ro_synth.csv", read_only);
  cases.push_back({"synthesize --out read-only", "synthesize --scenario " + q + " --out " + ro_synth, Want::kError,
                   {"--out", ro_synth, "read-only"}, unchanged(ro_synth)});
  // A directory where the writer's temporary file goes is found before the runs.
  const std::string blocked = dir + "/blocked.h5";
  fs::create_directory(blocked + ".partial");
  cases.push_back({"montecarlo --out whose .partial is a directory",
                   study_args("montecarlo", w().montecarlo([](Json&) {}), blocked), Want::kError,
                   {"--out", blocked + ".partial", "a directory is there"}, absent_file(blocked)});
  // Symbolic links are refused, never replaced by a file; what they point at stays.
  const std::string target = earlier_result("target.h5", fs::perms::owner_read | fs::perms::owner_write);
  const std::string link = dir + "/link.h5";
  fs::create_symlink(target, link);
  cases.push_back({"simulate --out a link", sim + " --out " + link, Want::kError,
                   {"--out", link, "symbolic link", target}, all_of({still_a_link(link, target), unchanged(target)})});
  const std::string dangling = dir + "/dangling.csv";
  fs::create_symlink(dir + "/nowhere.csv", dangling);
  cases.push_back({"simulate --csv a dangling link", sim + " --out " + w().out() + " --csv " + dangling, Want::kError,
                   {"--csv", dangling, "symbolic link"}, still_a_link(dangling, dir + "/nowhere.csv")});
  const std::string png_link = dir + "/png_link.png";
  fs::create_symlink(target, png_link);
  cases.push_back({"friction --png a link", "friction --png " + png_link, Want::kError, {"--png", "symbolic link"},
                   still_a_link(png_link, target)});
  // Standard output and devices: CSV goes through; HDF5 and PNG are refused.
  const std::string captured = dir + "/captured.txt";
  cases.push_back({"simulate --csv /dev/stdout into a file", sim + " --out " + w().out() + " --csv /dev/stdout >> " + captured,
                   Want::kRuns, {}, [=] {
                     if (!fs::is_symlink(fs::symlink_status("/dev/stdout"))) return std::string("/dev/stdout was replaced");
                     const std::string text = file_bytes(captured);
                     return text.find("\nt,") != std::string::npos || text.rfind("t,", 0) == 0
                                ? std::string()
                                : "the CSV did not reach standard output: " + text.substr(0, 200);
                   }});
  cases.push_back({"simulate --csv /dev/null", sim + " --out " + w().out() + " --csv /dev/null", Want::kRuns, {},
                   [] { return fs::is_character_file("/dev/null") ? "" : "/dev/null was replaced"; }});
  cases.push_back({"synthesize --out /dev/null", "synthesize --scenario " + q + " --out /dev/null", Want::kRuns, {}});
  cases.push_back({"simulate --out /dev/stdout", sim + " --out /dev/stdout", Want::kError,
                   {"--out", "/dev/stdout", "not a regular file"}});
  cases.push_back({"evaluate --out /dev/stdout", "evaluate --scenario " + q + " --design " +
                                                     w().text_file("design", "c_q\n0.1\n", "csv") +
                                                     " --qoi t_min --out /dev/stdout",
                   Want::kError, {"--out", "/dev/stdout", "not a regular file"}});
  cases.push_back({"terrain --png /dev/null", "terrain obstacle --out " + w().out("json") + " --png /dev/null",
                   Want::kError, {"--png", "/dev/null", "a device"}});
  cases.push_back({"montecarlo --out /dev/null", study_args("montecarlo", w().montecarlo([](Json&) {}), "/dev/null"),
                   Want::kError, {"--out", "/dev/null"}});
  run_table(dir, cases);
}

// A pipe receives the CSV. A reader that leaves before the end (`| head`,
// the README's own example) stops the CSV as a SIGPIPE does (status 130),
// with the result file written before it kept.
TEST_F(Audit, CsvIntoAPipe) {
  std::string output;
  const int status = run_command("cd " + w().dir() + " && " + rover_binary() + " simulate --no-plot --scenario " +
                                     w().quick() + " --out " + w().out() + " --csv /dev/stdout 2>/dev/null | head -3",
                                 &output);
  EXPECT_EQ(status, 0);
  EXPECT_EQ(output.rfind("t,", 0), 0u) << output;
  // Some hundred kilobytes of rows: more than a pipe holds, so the reader
  // is gone before the last write.
  const std::string longer = w().scenario([](Json& j) {
    j["duration"] = 0.5;
    j["output_rate"] = 1000;
  });
  const std::string dir = w().dir(), out = dir + "/piped.h5", status_file = dir + "/piped.status";
  run_command("cd " + dir + " && { " + rover_binary() + " simulate --no-plot --scenario " + longer + " --out " + out +
                  " --csv /dev/stdout 2>" + dir + "/piped.log; echo \"status $?\" > " + status_file + "; } | head -3",
              &output);
  const std::string log = file_bytes(dir + "/piped.log");
  EXPECT_EQ(file_bytes(status_file), "status 130\n") << log;
  EXPECT_NE(log.find("interrupted (SIGPIPE"), std::string::npos) << log;
  EXPECT_EQ(log.find("error"), std::string::npos) << log;
  EXPECT_TRUE(fs::exists(out)) << log;
}

// ---- class 2: leftover checkpoints and failed studies ------------------

TEST_F(Audit, LeftoverCheckpoints) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  // The checkpoint of an interrupted study: past its signature its content
  // does not matter here (a checkpoint of another configuration is refused
  // by --resume).
  auto interrupted = [&](const std::string& name) {
    const std::string out = dir + "/" + name;
    write_file(out + ".checkpoint", "ROVERCKP finished runs\n");
    return out;
  };
  const std::string mc = w().montecarlo([](Json&) {});
  for (const auto& [command, study_file] : std::vector<std::pair<std::string, std::string>>{
           {"montecarlo", mc},
           {"sensitivity", w().sensitivity([](Json&) {})},
           {"surface", w().surface([](Json&) {})},
           {"calibrate", w().calibration([](Json&) {})}}) {
    const std::string out = interrupted(command + "_left.h5");
    cases.push_back({command + " beside a leftover checkpoint", study_args(command, study_file, out), Want::kError,
                     {out + ".checkpoint", "--resume", "--restart"}, unchanged(out + ".checkpoint")});
  }
  const std::string eval_out = interrupted("evaluate_left.csv");
  cases.push_back({"evaluate beside a leftover checkpoint",
                   "evaluate --scenario " + w().quick() + " --design " + w().text_file("design", "c_q\n0.1\n", "csv") +
                       " --qoi t_min --out " + eval_out,
                   Want::kError, {eval_out + ".checkpoint", "--resume", "--restart"}, unchanged(eval_out + ".checkpoint")});
  const std::string restarted = interrupted("restarted.h5");
  cases.push_back({"montecarlo --restart", study_args("montecarlo", mc, restarted) + " --restart", Want::kRuns, {}, [=] {
                     if (fs::exists(restarted + ".checkpoint")) return restarted + ".checkpoint is still there";
                     return fs::exists(restarted) ? std::string() : restarted + " was not written";
                   }});
  const std::string both = interrupted("both.h5");
  cases.push_back({"montecarlo --resume --restart", study_args("montecarlo", mc, both) + " --resume --restart",
                   Want::kError, {"--resume", "--restart"}, unchanged(both + ".checkpoint")});
  // A study whose every run failed (status 2) leaves an earlier result as it was.
  const std::string earlier = dir + "/earlier.h5";
  write_file(earlier, "an earlier result\n");
  const std::string failing = w().montecarlo([&](Json& j) {
    j["scenario"] = w().scenario([](Json& s) { s["wall_time_budget"] = 1e-9; });
  });
  cases.push_back({"montecarlo whose every run fails", study_args("montecarlo", failing, earlier), Want::kAllFailed,
                   {"every run failed", earlier + " is unchanged"}, unchanged(earlier)});
  const std::string foreign = dir + "/foreign.h5";
  write_file(foreign + ".checkpoint", "not a checkpoint\n");
  cases.push_back({"montecarlo beside a file that is no checkpoint", study_args("montecarlo", mc, foreign),
                   Want::kError, {foreign + ".checkpoint is no checkpoint of rover", "give another --out"},
                   unchanged(foreign + ".checkpoint"), {}, {"finished runs of a study", "--restart"}});
  run_table(dir, cases);
}

// ---- class 7: finite numbers beyond the model's scale ----------------

TEST_F(Audit, MeaninglessScale) {
  std::vector<Case> cases;
  auto scenario_case = [&](const std::string& id, const std::function<void(Json&)>& edit,
                           std::vector<std::string> mentions) {
    const std::string path = w().scenario(edit);
    mentions.insert(mentions.begin(), path);
    cases.push_back({id, simulate(path), Want::kError, mentions});
  };
  scenario_case("a drop from z = 1e308 m", [](Json& j) { j["initial_q"]["z"] = 1e308; },
                {"'initial_q'", "z = 1e+308 m", "+-1000000 m"});
  scenario_case("x of 1e7 m", [](Json& j) { j["initial_q"]["x"] = 1e7; }, {"'initial_q'", "x = 10000000 m"});
  scenario_case("a clearance of 1e300 m",
                [](Json& j) {
                  j.erase("initial_q");
                  j["initial_ground_clearance"] = 1e300;
                },
                {"'initial_ground_clearance'", "1e+300", "+-1000000 m"});
  auto terrain_case = [&](const std::string& id, const Json& terrain, std::vector<std::string> mentions) {
    const std::string path = w().json_file("terrain", terrain);
    mentions.insert(mentions.begin(), path);
    cases.push_back({id, simulate(w().scenario_with_terrain(path)), Want::kError, mentions});
  };
  const Json heights2x2 = {{0.0, 0.0}, {0.0, 0.0}};
  auto grid = [&](const Json& origin, const Json& spacing, const Json& counts) {
    return Json{{"type", "grid"}, {"origin", origin}, {"spacing", spacing}, {"counts", counts}, {"heights", heights2x2}};
  };
  terrain_case("grid origin at 1e300 m", grid({1e300, 0.0}, {1.0, 1.0}, {2, 2}), {"'origin'", "1e+300"});
  terrain_case("grid spacing of 1 nm", grid({-1.0, -1.0}, {1e-9, 1.0}, {2, 2}), {"'spacing'", "1e-09"});
  terrain_case("grid reaching 1e7 m", grid({-1.0, -1.0}, {1e7, 1.0}, {2, 2}), {"'spacing'", "far x edge"});
  terrain_case("flat ground at 1e300 m", Json{{"type", "flat"}, {"height", 1e300}}, {"'height'", "1e+300"});
  terrain_case("control point at 1e300 m",
               Json{{"type", "control_points"},
                    {"points", {{0, 0, 0}, {1, 0, 0}, {0, 1e300, 0}}},
                    {"grid", {{"origin", {-1.0, -1.0}}, {"spacing", {0.5, 0.5}}, {"counts", {5, 5}}}}},
               {"'points'", "point 2", "1e+300"});
  auto drive_case = [&](const std::string& id, const Json& segment, std::vector<std::string> mentions) {
    const std::string path = w().drive_scenario({{"segments", {segment}}});
    mentions.insert(mentions.begin(), path);
    cases.push_back({id, simulate(path), Want::kError, mentions});
  };
  drive_case("car at 50 m/s", {{"mode", "car"}, {"speed", 50.0}}, {"'drive.segments[0].speed'", "50 m/s", "+-10 m/s"});
  drive_case("turn radius 1e300 m", {{"mode", "ackermann"}, {"speed", 0.3}, {"radius", 1e300}},
             {"'drive.segments[0].radius'", "1e+300", "drive straight"});
  drive_case("turn radius 1 mm", {{"mode", "car"}, {"speed", 0.3}, {"radius", 1e-3}}, {"'drive.segments[0]"});
  drive_case("ICR 1e9 m away", {{"mode", "general-ackermann"}, {"speed", 0.3}, {"icr", {0.0, 1e9}}},
             {"'drive.segments[0].icr'", "1000000000 m"});
  drive_case("rotation at 100 rad/s", {{"mode", "rotation"}, {"yaw_rate", 100.0}},
             {"'drive.segments[0].yaw_rate'", "100 rad/s", "+-10 rad/s"});
  drive_case("lateral body speed 1e20 m/s", {{"mode", "lateral"}, {"lateral", 1e20}},
             {"'drive.segments[0].lateral'", "1e+20"});
  cases.push_back({"kinematics at 20 m/s", "kinematics --mode car --v 20", Want::kError, {"--v 20 m/s", "+-10 m/s"}});
  cases.push_back({"kinematics turn radius 1e300 m", "kinematics --mode car --v 0.3 --radius 1e300", Want::kError,
                   {"--radius 1e+300 m", "+-1000000 m"}});
  cases.push_back({"kinematics rotation at 100 rad/s", "kinematics --mode rotation --yaw-rate 100", Want::kError,
                   {"--yaw-rate 100 rad/s"}});
  // Outputs that their readers would refuse: a measured curve of fewer than 3 points.
  cases.push_back({"synthesize 1 point", "synthesize --scenario " + w().quick() + " --rate 10 --out " + w().out("csv"),
                   Want::kError, {"--rate 10 Hz", "1 data point", "at least 3"}});
  cases.push_back({"synthesize with the release after the end",
                   "synthesize --scenario " + w().quick() + " --offset -1 --out " + w().out("csv"), Want::kError,
                   {"--offset -1 s puts the release before the data clock's start", "no data point falls within"}});
  run_table(w().dir(), cases);
}

// ---- class 8: messages in rover's words --------------------------------

TEST_F(Audit, CommandLineMessages) {
  std::vector<Case> cases;
  const std::string q = w().quick();
  // Every subcommand, with the flags it requires.
  const std::vector<std::pair<std::string, std::string>> commands = {
      {"simulate", "simulate --no-plot --scenario " + q + " --out " + w().out()},
      {"evaluate", "evaluate --scenario " + q + " --design " + w().text_file("design", "c_q\n0.1\n", "csv") +
                       " --qoi t_min --out " + w().out("csv")},
      {"montecarlo", study("montecarlo", w().montecarlo([](Json&) {}))},
      {"sensitivity", study("sensitivity", w().sensitivity([](Json&) {}))},
      {"surface", study("surface", w().surface([](Json&) {}))},
      {"calibrate", study("calibrate", w().calibration([](Json&) {}))},
      {"synthesize", "synthesize --scenario " + q + " --out " + w().out("csv")},
      {"compare", "compare " + source_path("configs/data/drop_horizontal_synthetic.csv") + " " +
                      source_path("configs/data/drop_horizontal_synthetic.csv")},
      {"friction", "friction"},
      {"kinematics", "kinematics --mode car --v 0.3"},
      {"terrain obstacle", "terrain obstacle --out " + w().out("json")},
  };
  for (const auto& [name, args] : commands) {
    cases.push_back({name + " with an unknown flag", args + " --bogus-flag 3", Want::kError,
                     {"error: unknown option '--bogus-flag'", "--help"}});
    cases.push_back({name + " with an extra argument", args + " stray", Want::kError,
                     {"error: unexpected argument 'stray'"}});
  }
  cases.push_back({"a misspelt flag", "simulate --scenaro " + q, Want::kError,
                   {"unknown option '--scenaro'", "did you mean '--scenario'?"}});
  cases.push_back({"a flag without its value", "simulate --scenario", Want::kError,
                   {"rover simulate: error: --scenario needs a value"}});
  cases.push_back({"a required flag missing", "simulate", Want::kError, {"rover simulate: error: --scenario is required"}});
  cases.push_back({"a word for an integer", study("montecarlo", w().montecarlo([](Json&) {})) + " --samples many",
                   Want::kError, {"--samples", "many", "from 2 to"}});
  cases.push_back({"a word for a number", "simulate --no-plot --scenario " + q + " --f stiff", Want::kError,
                   {"--f", "'stiff'", "a number"}});
  cases.push_back({"a value for a flag", "simulate --no-plot=maybe --scenario " + q, Want::kError, {"--no-plot"}});
  cases.push_back({"a missing file", "simulate --scenario " + w().dir() + "/none.json", Want::kError,
                   {"--scenario '" + w().dir() + "/none.json': no such file"}});
  cases.push_back({"a directory for a file", "simulate --scenario " + w().dir(), Want::kError,
                   {"--scenario '" + w().dir() + "' is a directory"}});
  cases.push_back({"a progress interval out of range",
                   study("montecarlo", w().montecarlo([](Json&) {})) + " --progress-interval 0", Want::kError,
                   {"--progress-interval must be from 1 to 86400, got 0"}});
  cases.push_back({"an unknown kinematics mode", "kinematics --mode tank --v 0.3", Want::kError, {"--mode", "'tank'"}});
  cases.push_back({"no subcommand", "", Want::kError, {"rover: error: a subcommand is required"}});
  // The environment variable rover sets for Open MPI itself.
  for (const auto& [name, args] : std::vector<std::pair<std::string, std::string>>(commands.begin() + 1, commands.begin() + 6)) {
    cases.push_back({name + " with an unreadable eager limit", args, Want::kError,
                     {"OMPI_MCA_btl_vader_eager_limit='abc'", "32768"}, {}, "OMPI_MCA_btl_vader_eager_limit=abc"});
  }
  cases.push_back({"an eager limit of 0 bytes", commands[2].second, Want::kError,
                   {"OMPI_MCA_btl_vader_eager_limit='0'", "from 1024 to 1g"}, {}, "OMPI_MCA_btl_vader_eager_limit=0"});
  cases.push_back({"an eager limit of 2g", commands[2].second, Want::kError, {"OMPI_MCA_btl_vader_eager_limit='2g'"},
                   {}, "OMPI_MCA_btl_vader_eager_limit=2g"});
  cases.push_back({"montecarlo with an eager limit of 64k", commands[2].second, Want::kRuns, {}, {},
                   "OMPI_MCA_btl_vader_eager_limit=64k"});
  run_table(w().dir(), cases);
}

// ---- The second audit ----------------------------------------------------------

// Class 1: the inputs are the files each loader reads (the scenario's rover
// and terrain, a study's scenario and reference curves), not every string
// that happens to name a file.
TEST_F(Audit, InputsListedByLoaders) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  // Through a symbolic link named in the scenario, for evaluate's checkpoint.
  const std::string terrain = w().text_file("terrain", Json{{"type", "flat"}, {"height", 0.0}}.dump(), "csv");
  const std::string terrain_link = dir + "/terrain_link.json";
  fs::create_symlink(terrain, terrain_link);
  const std::string on_link = w().scenario_with_terrain(terrain_link);
  const std::string design = w().text_file("design", "c_q\n0.1\n", "csv");
  cases.push_back({"evaluate --out over the terrain its scenario names through a link",
                   "evaluate --no-plot --scenario " + on_link + " --design " + design + " --qoi t_min --out " + terrain,
                   Want::kError, {"--out", "'terrain' in " + on_link}, unchanged(terrain)});
  const std::string design_checkpoint = dir + "/ev.csv.checkpoint";
  fs::copy_file(design, design_checkpoint);
  cases.push_back({"evaluate's checkpoint over its design",
                   "evaluate --no-plot --restart --scenario " + w().quick() + " --design " + design_checkpoint +
                       " --qoi t_min --out " + dir + "/ev.csv",
                   Want::kError, {design_checkpoint, "is no checkpoint of rover", "never removes such a file"},
                   unchanged(design_checkpoint)});
  // The surface's reference file, named like a plot beside --out.
  const std::string reference_png = simulated_curve(dir + "/surf_summary.png");
  const std::string surface = w().surface([&](Json& j) { j["reference"] = {{"file", reference_png}}; });
  cases.push_back({"surface's plot over its reference file", "surface --study " + surface + " --out " + dir + "/surf.h5",
                   Want::kError, {"--out", "plot", "'reference.file' in " + surface}, unchanged(reference_png)});
  // A string that names a file but is no input field (a description) is no input.
  const std::string notes = w().text_file("notes", "free text\n", "h5");
  const std::string described = w().montecarlo([&](Json& j) { j["description"] = notes; });
  cases.push_back({"montecarlo --out over a file its description names", study_args("montecarlo", described, notes),
                   Want::kRuns, {}});
  run_table(dir, cases);
}

// Class 2: a plot path that may not be written is refused before any run,
// like --out, and nothing is written.
TEST_F(Audit, PlotPathsRefusedUpFront) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  const std::string target = write_file(dir + "/target.png", "an earlier figure\n");
  auto link = [&](const std::string& name) {
    fs::create_symlink(target, dir + "/" + name);
    return dir + "/" + name;
  };
  auto nothing_at = [](const std::string& path) {
    return [=] { return fs::exists(path) ? path + " was written" : std::string(); };
  };
  const std::string sim_link = link("sim.png");
  cases.push_back({"simulate's plot path is a link", "simulate --scenario " + w().quick() + " --out " + dir + "/sim.h5",
                   Want::kError, {"--out", sim_link, "symbolic link", "--no-plot"},
                   all_of({still_a_link(sim_link, target), nothing_at(dir + "/sim.h5")})});
  const std::string unplotted_link = link("unplotted.png");
  cases.push_back({"simulate --no-plot beside a plot link", "simulate --no-plot --scenario " + w().quick() + " --out " +
                                                                dir + "/unplotted.h5",
                   Want::kRuns, {}, still_a_link(unplotted_link, target)});
  const std::string mc_plot = write_file(dir + "/mc_summary.png", "an earlier figure\n");
  fs::permissions(mc_plot, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  cases.push_back({"montecarlo's summary figure is read-only",
                   "montecarlo --study " + w().montecarlo([](Json&) {}) + " --out " + dir + "/mc.h5", Want::kError,
                   {"--out", mc_plot, "read-only", "--plots none"}, all_of({unchanged(mc_plot), nothing_at(dir + "/mc.h5")})});
  const std::string ev_link = link("ev_summary.png");
  cases.push_back({"evaluate's summary figure is a link",
                   "evaluate --scenario " + w().quick() + " --design " + w().text_file("design", "c_q\n0.1\n", "csv") +
                       " --qoi t_min --out " + dir + "/ev.csv",
                   Want::kError, {"--out", ev_link, "symbolic link"}, still_a_link(ev_link, target)});
  const std::string sens_link = link("sens_s_summary.png");
  cases.push_back({"sensitivity's summary figure is a link",
                   "sensitivity --study " + w().sensitivity([](Json&) {}) + " --out " + dir + "/sens_s.h5", Want::kError,
                   {"--out", sens_link, "symbolic link"}, still_a_link(sens_link, target)});
  // Its own result: the cases run at once, and one result has one writer.
  const std::string quiet_link = link("sens_t_summary.png");
  cases.push_back({"sensitivity --plots none beside a link",
                   "sensitivity --plots none --study " + w().sensitivity([](Json&) {}) + " --out " + dir + "/sens_t.h5",
                   Want::kRuns, {}, still_a_link(quiet_link, target)});
  fs::create_directories(dir + "/results");
  fs::create_symlink(target, dir + "/results/quick.png");
  cases.push_back({"simulate's default plot path is a link", "simulate --scenario " + w().quick(), Want::kError,
                   {"--out (default)", "results/quick.png", "symbolic link"}});
  run_table(dir, cases);
}

// Class 1: the outputs of one simulate (--out, --csv, the plots beside --out)
// are different files and --out is an HDF5 name, checked before the run.
TEST_F(Audit, OutputsOfOneCommandAreDistinct) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  const std::string sim = "simulate --scenario " + w().quick();
  auto nothing_at = [](std::vector<std::string> paths) {
    return [=] {
      for (const std::string& path : paths)
        if (fs::exists(path)) return path + " was written";
      return std::string();
    };
  };
  cases.push_back({"simulate --out a .png", sim + " --out " + dir + "/r.png", Want::kError,
                   {"--out", dir + "/r.png", "must end in .h5"}, nothing_at({dir + "/r.png"})});
  cases.push_back({"simulate --out a .csv", sim + " --no-plot --out " + dir + "/k.csv", Want::kError,
                   {"--out", dir + "/k.csv", "must end in .h5"}, nothing_at({dir + "/k.csv"})});
  cases.push_back({"simulate --csv is the plot", sim + " --out " + dir + "/s.h5 --csv " + dir + "/s.png",
                   Want::kError, {"--csv", dir + "/s.png", "the plot of --out"},
                   nothing_at({dir + "/s.h5", dir + "/s.png"})});
  cases.push_back({"simulate --csv is the attitude plot",
                   sim + " --out " + dir + "/a.h5 --csv " + dir + "/a_attitude.png", Want::kError,
                   {"--csv", dir + "/a_attitude.png", "the plot of --out"},
                   nothing_at({dir + "/a.h5", dir + "/a_attitude.png"})});
  cases.push_back({"simulate --no-plot --csv beside", sim + " --no-plot --out " + dir + "/n.h5 --csv " + dir + "/n.csv",
                   Want::kRuns, {}});
  cases.push_back({"simulate --no-plot --csv named as a plot",
                   sim + " --no-plot --out " + dir + "/p.h5 --csv " + dir + "/p.png", Want::kError,
                   {"ends in .png, the name of a PNG file"}});
  run_table(dir, cases);
}

// Class 2: under mpirun with two processes (its variables set by hand here) a
// one-process subcommand is refused before it writes anything, once (rank 0
// speaks); the other ranks refuse quietly.
TEST_F(Audit, OneProcessCommandsUnderMpirun) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  const std::string rank0 = "OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=0";
  const std::string rank1 = "OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=1";
  auto nothing_at = [](const std::string& path) {
    return [=] { return fs::exists(path) ? path + " was written" : std::string(); };
  };
  const std::string sim = "simulate --no-plot --scenario " + w().quick() + " --out " + dir + "/mpi.h5";
  cases.push_back({"simulate, rank 0", sim, Want::kError, {"rover simulate: error", "one process", "mpirun started 2",
                   "montecarlo"}, nothing_at(dir + "/mpi.h5"), rank0});
  cases.push_back({"simulate, rank 1", sim, Want::kError, {}, nothing_at(dir + "/mpi.h5"), rank1,
                   {"one process"}});
  const std::string synth = "synthesize --scenario " + w().quick() + " --out " + dir + "/mpi.csv";
  cases.push_back({"synthesize, rank 0", synth, Want::kError, {"rover synthesize: error", "one process"},
                   nothing_at(dir + "/mpi.csv"), rank0});
  cases.push_back({"terrain, rank 0", "terrain obstacle --out " + dir + "/mpi.json", Want::kError,
                   {"rover terrain: error", "one process"}, nothing_at(dir + "/mpi.json"), rank0});
  cases.push_back({"simulate, a job of one process", "simulate --no-plot --scenario " + w().quick() + " --out " + w().out(), Want::kRuns, {}, {}, "OMPI_COMM_WORLD_SIZE=1 OMPI_COMM_WORLD_RANK=0"});
  run_table(dir, cases);
}

// Class 2: a refused command, or a dry run, makes no folder for --out; a run
// makes the missing ones.
TEST_F(Audit, FoldersMadeOnlyByARun) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  auto no_folder = [](const std::string& path) {
    return [=] { return fs::exists(path) ? path + " was made" : std::string(); };
  };
  cases.push_back({"montecarlo --dry-run", "montecarlo --dry-run --study " + w().montecarlo([](Json&) {}) +
                                               " --out " + dir + "/dry/sub/m.h5",
                   Want::kRuns, {"nothing was run or written"}, no_folder(dir + "/dry")});
  cases.push_back({"simulate refused", "simulate --no-plot --scenario " + w().quick() + " --f -1 --out " + dir +
                                           "/refused/x/q.h5",
                   Want::kError, {"--f"}, no_folder(dir + "/refused")});
  cases.push_back({"synthesize refused", "synthesize --scenario " + w().quick() + " --noise -1 --out " + dir +
                                             "/refused_synth/x/q.csv",
                   Want::kError, {"--noise"}, no_folder(dir + "/refused_synth")});
  cases.push_back({"simulate into new folders", "simulate --no-plot --scenario " + w().quick() + " --out " + dir +
                                                    "/made/y/q.h5",
                   Want::kRuns, {}, [=] {
                     return fs::is_regular_file(dir + "/made/y/q.h5") ? std::string() : std::string("no result");
                   }});
  cases.push_back({"synthesize into new folders", "synthesize --scenario " + w().quick() + " --out " + dir +
                                                      "/made_synth/y/q.csv",
                   Want::kRuns, {}, [=] {
                     return fs::is_regular_file(dir + "/made_synth/y/q.csv") ? std::string() : std::string("no curve");
                   }});
  cases.push_back({"montecarlo into new folders", "montecarlo --no-plot --study " + w().montecarlo([](Json&) {}) +
                                                     " --out " + dir + "/made_mc/z/m.h5",
                   Want::kRunsOrFails, {}, [=] {
                     return fs::is_regular_file(dir + "/made_mc/z/m.h5") ? std::string() : std::string("no result");
                   }});
  cases.push_back({"terrain into new folders", "terrain obstacle --out " + dir + "/made_terrain/t.json --png " + dir +
                                                   "/made_png/t.png",
                   Want::kRuns, {}, [=] {
                     return fs::is_regular_file(dir + "/made_terrain/t.json") && fs::is_regular_file(dir + "/made_png/t.png")
                                ? std::string()
                                : std::string("no terrain or no plot");
                   }});
  const std::string blocker = write_file(dir + "/blocker", "a file\n");
  cases.push_back({"folder under a file", "simulate --no-plot --scenario " + w().quick() + " --out " + blocker +
                                              "/q.h5",
                   Want::kError, {"--out", "cannot create the directory", "is a file"}});
  run_table(dir, cases);
}

// Class 2: the temporary files written beside an output (<out>.partial, the
// checkpoint's) are made anew, never written through a link standing there.
TEST_F(Audit, TemporaryFilesNeverWrittenThroughLinks) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  auto precious = [&](const std::string& name) { return write_file(dir + "/" + name, "precious\n"); };
  auto a_regular_file = [](const std::string& path) {
    return [=] { return fs::is_regular_file(fs::symlink_status(path)) ? std::string() : path + " is not a regular file"; };
  };
  const std::string kept_h5 = precious("kept_h5.txt"), kept_csv = precious("kept_csv.txt"),
                    kept_mc = precious("kept_mc.txt");
  fs::create_symlink(kept_h5, dir + "/sim.h5.partial");
  fs::create_symlink(kept_csv, dir + "/sim.csv.partial");
  cases.push_back({"simulate beside links at <out>.partial",
                   "simulate --no-plot --scenario " + w().quick() + " --out " + dir + "/sim.h5 --csv " + dir + "/sim.csv",
                   Want::kRuns, {},
                   all_of({unchanged(kept_h5), unchanged(kept_csv), a_regular_file(dir + "/sim.h5"),
                           a_regular_file(dir + "/sim.csv")})});
  fs::create_symlink(kept_mc, dir + "/mc.h5.checkpoint.partial");
  cases.push_back({"montecarlo beside a link at its checkpoint's temporary file",
                   study_args("montecarlo", w().montecarlo([](Json&) {}), dir + "/mc.h5"), Want::kRuns, {},
                   all_of({unchanged(kept_mc), a_regular_file(dir + "/mc.h5")})});
  run_table(dir, cases);
}

// Class 3: a reference curve the run cannot be compared with is refused
// before any run: its span (times in milliseconds, an offset beyond it) and a
// constant curve of heights.
TEST_F(Audit, ReferenceCurvesAgainstTheRun) {
  std::vector<Case> cases;
  // The shipped synthetic drop's first rows, times scaled and heights replaced.
  auto curve = [&](double time_scale, std::optional<double> constant) {
    std::ifstream in(source_path("configs/data/drop_horizontal_synthetic.csv"));
    std::string text = "t,z\n", line;
    for (int rows = 0; std::getline(in, line) && rows < 40;) {
      if (line.empty() || line[0] == '#' || line[0] == 't') continue;
      const std::size_t comma = line.find(',');
      text += std::to_string(std::stod(line.substr(0, comma)) * time_scale) + "," +
              (constant ? std::to_string(*constant) : line.substr(comma + 1)) + "\n";
      ++rows;
    }
    return w().text_file("curve", text, "csv");
  };
  const std::string in_ms = curve(1000.0, std::nullopt), constant = curve(1.0, 0.2), good = curve(1.0, std::nullopt);
  auto rms_vs = [&](const std::string& reference, double offset, const std::string& channel) {
    return w().montecarlo([&](Json& j) {
      j["qoi"] = {{{"name", "rms_vs"}, {"reference", reference}, {"time_offset", offset}, {"channel", channel}}};
    });
  };
  cases.push_back({"rms_vs against a curve in milliseconds", study("montecarlo", rms_vs(in_ms, 0.0, "B_l_z")),
                   Want::kError, {"'qoi[0].reference'", in_ms, "spans 0 .. 78 s", "hold 1 of its samples"}});
  cases.push_back({"rms_vs with an offset beyond the curve", study("montecarlo", rms_vs(good, 100.0, "B_l_z")),
                   Want::kError, {"'qoi[0].reference'", "time_offset 100 s", "hold 0 of its samples"}});
  cases.push_back({"rms_vs against constant heights", study("montecarlo", rms_vs(constant, 0.0, "B_l_z")),
                   Want::kError, {"'qoi[0].reference'", constant, "0.2 m", "constant"}});
  cases.push_back({"rms_vs of the roll against a constant curve", study("montecarlo", rms_vs(constant, 0.0, "roll")),
                   Want::kRuns, {}});
  auto surface = [&](const std::string& reference, double offset) {
    return w().surface([&](Json& j) { j["reference"] = {{"file", reference}, {"time_offset", offset}}; });
  };
  cases.push_back({"surface against a curve in milliseconds", study("surface", surface(in_ms, 0.0)), Want::kError,
                   {"'reference.file'", in_ms, "hold 1 of its samples"}});
  cases.push_back({"surface with an offset of 1e6 s", study("surface", surface(good, 1e6)), Want::kError,
                   {"'reference.file'", "time_offset 1000000 s"}});
  cases.push_back({"surface against constant heights", study("surface", surface(constant, 0.0)), Want::kError,
                   {"'reference.file'", "constant"}});
  run_table(w().dir(), cases);
}

// Classes 5 and 7: numbers without meaning are refused up front or marked
// undefined, never printed as nan; S-structure values far beyond the rover's.
TEST_F(Audit, ResultsWithoutMeaning) {
  std::vector<Case> cases;
  const std::string q = w().quick();
  cases.push_back({"a one-sample Monte Carlo",
                   study("montecarlo", w().montecarlo([](Json& j) { j["design"]["samples"] = 1; })), Want::kError,
                   {"'design'", "at least 2 samples", "got 1"}});
  cases.push_back({"a zero-sample Monte Carlo names the Monte Carlo's range",
                   study("montecarlo", w().montecarlo([](Json& j) { j["design"]["samples"] = 0; })), Want::kError,
                   {"'design.samples'", "from 2 to 1e8"}});
  cases.push_back({"montecarlo --samples 1", study("montecarlo", w().montecarlo([](Json&) {})) + " --samples 1",
                   Want::kError, {"--samples", "from 2"}});
  // On the quick drop nothing touches the ground: B_l_z does not depend on f or c_q.
  auto quick_sensitivity = [&](const std::string& method, const Json& design) {
    return w().sensitivity([&](Json& j) {
      j.erase("model");
      j["method"] = method;
      j["scenario"] = q;
      j["parameters"] = {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}},
                         {"f", {{"distribution", "uniform"}, {"min", 1e3}, {"max", 1e4}}}};
      j["design"] = design;
      j["qoi"] = {"B_l_z_min"};
      if (method == "morris") j.erase("bootstrap");  // and Morris screens no channel
      else j["channels"] = {"B_l_z"};
    });
  };
  cases.push_back({"Sobol' indices of a channel that does not vary",
                   study("sensitivity", quick_sensitivity("sobol", {{"type", "sobol"}, {"samples", 4}, {"seed", 1}})),
                   Want::kRuns, {"B_l_z: indices along time undefined", "B_l_z_min: indices undefined"}, {}, {},
                   {"S1 nan"}});
  cases.push_back({"Morris effects of a QoI constant up to rounding",
                   study("sensitivity", quick_sensitivity("morris", {{"trajectories", 3}, {"levels", 4}, {"seed", 1}})),
                   Want::kRuns, {"B_l_z_min: indices undefined", "constant"}, {}, {}, {"mu*"}});
  const std::string sim = "simulate --no-plot --scenario " + q + " --out " + w().out();
  cases.push_back({"--f 1e300", sim + " --f 1e300", Want::kError, {"--f 1e+300 1/rad", "+-100000000 1/rad"}});
  cases.push_back({"--cq 1e8", sim + " --cq 1e8", Want::kError, {"--cq 100000000 N m s/rad", "+-1000"}});
  cases.push_back({"--M0 1e6", sim + " --M0 1e6,0,0,0,0,0,0,0", Want::kError, {"--M0: value 1", "1000000 N m"}});
  const std::string stiff_rover = w().rover([](Json& j) { j["s_structure"]["f"] = 1e12; });
  cases.push_back({"rover.json f = 1e12", simulate(w().scenario_with_rover(stiff_rover)), Want::kError,
                   {stiff_rover, "'s_structure.f'", "1e+12"}});
  const std::string negative_preload = w().scenario([](Json& j) { j["inputs"] = {{"M0", {-1, 0, 0, 0, 0, 0, 0, 0}}}; });
  cases.push_back({"a scenario's negative preload", simulate(negative_preload), Want::kError,
                   {negative_preload, "'inputs.M0'", "must not be negative"}});
  cases.push_back({"montecarlo of f up to 1e9", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"] = {{"f", {{"distribution", "uniform"}, {"min", 1e3}, {"max", 1e9}}}};
                   })),
                   Want::kError, {"'parameters'", "'f'", "reaches 1000000000", "narrow"}});
  cases.push_back({"a surface up to f = 1e9", study("surface", w().surface([](Json& j) { j["f"]["max"] = 1e9; })),
                   Want::kError, {"'f'", "f = 1000000000", "refused"}});
  run_table(w().dir(), cases);
}

// Classes 2 and 6: a sensitivity study refused after its runs (too many
// failed) writes nothing, keeps an earlier result and says where the runs are.
TEST_F(Audit, RefusedAfterTheRuns) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  const std::string earlier = write_file(dir + "/earlier.h5", "an earlier result\n");
  const std::string failing = w().sensitivity([&](Json& j) {
    j.erase("model");
    j["scenario"] = w().scenario([](Json& s) { s["wall_time_budget"] = 1e-9; });
    j["parameters"] = {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}},
                       {"f", {{"distribution", "uniform"}, {"min", 1e3}, {"max", 1e4}}}};
    j["design"] = {{"type", "sobol"}, {"samples", 2}, {"seed", 1}};
    j["qoi"] = {"t_min"};
  });
  Case c{"sensitivity whose every run fails", study_args("sensitivity", failing, earlier), Want::kError,
         {"pick-freeze groups have a failed run", "max_failed_fraction", "Nothing was written", earlier + ".checkpoint", "--restart"},
         unchanged(earlier)};
  cases.push_back(c);
  run_table(dir, cases);
}

// Class 8: under mpirun every rank finds the same bad input; the message is
// printed once, on a line of its own.
TEST_F(Audit, OneMessageUnderMpirun) {
  std::string output;
  const int status = run_command(testing::mpiexec() + " -np 2 " + rover_binary() + " montecarlo --study " +
                                     w().montecarlo([](Json&) {}) + " --samples 0 2>&1",
                                 &output);
  EXPECT_NE(status, 0);
  const std::string message = "rover montecarlo: error: --samples must be from 2";
  const std::size_t first = output.find(message);
  ASSERT_NE(first, std::string::npos) << output;
  EXPECT_EQ(output.find(message, first + 1), std::string::npos) << "printed twice:\n" << output;
  EXPECT_TRUE(first == 0 || output[first - 1] == '\n') << output;
}

// A design row the model refuses is refused on every rank under mpirun, once,
// with its line: a refusal on rank 0 alone would leave rank 1 waiting for it.
TEST_F(Audit, RefusedDesignRowEndsEveryRank) {
  std::string output;
  const std::string design = w().text_file("design", "c_q,f\n0.2,1e4\n2000,1e4\n", "csv");
  const int status = run_command("timeout -k 5 60 " + testing::mpiexec() + " -np 2 " + rover_binary() +
                                     " evaluate --scenario " + w().quick() + " --design " + design +
                                     " --qoi B_l_z_min --out " + w().out("csv") + " 2>&1",
                                 &output);
  EXPECT_NE(status, 124) << "hung:\n" << output;
  EXPECT_NE(status, 0) << output;
  const std::string message = design + ":3: this row's values (c_q = 2000, f = 10000) are not a valid configuration";
  const std::size_t first = output.find(message);
  ASSERT_NE(first, std::string::npos) << output;
  EXPECT_EQ(output.find(message, first + 1), std::string::npos) << "printed twice:\n" << output;
}

// A design row whose geometry puts the wheels below the ground is refused
// with the row's own values, not only the scenario field they upset.
TEST_F(Audit, ARefusedDesignRowNamesItsValues) {
  const std::string design = w().text_file("wheels", "geometry.wheel_radius\n0.3\n", "csv");
  run_table(w().dir(), {{"a wheel radius that sinks the wheels",
                         "evaluate --scenario " + w().quick() + " --design " + design + " --qoi t_min --out " +
                             w().out("csv"),
                         Want::kError, {design + ":2: this row's values (geometry.wheel_radius = 0.3)"}}});
}

// ---- The third audit -----------------------------------------------------------

// Classes 5 and 7: inputs that could only fail after the runs, or give
// numbers without meaning, are refused before any work, naming the flag or
// the file and field, the value and what is accepted; nothing is written.
TEST_F(Audit, ThirdAuditRefusedUpFront) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  auto nothing_at = [](const std::string& path) {
    return [=] { return fs::exists(path) ? path + " was written" : std::string(); };
  };
  // The offset scan over bounds of 1e300 s never ended.
  cases.push_back({"time offset bounds of 1e300 s",
                   study("calibrate", w().calibration([](Json& j) { j["bounds"]["time_offset"] = {-1e300, 1e300}; })),
                   Want::kError, {"'bounds.time_offset'", "1e+300", "give bounds within"}});
  cases.push_back({"a known noise sd of 1e300 m", study("calibrate", w().calibration([](Json& j) {
                     j["method"] = "mcmc";
                     j["mcmc"] = {{"noise_sd", 1e300}};
                   })),
                   Want::kError, {"'mcmc.noise_sd'", "1e+300", "from 1e-12 to 1000 m"}});
  cases.push_back({"a noise sd prior up to 1e30 m", study("calibrate", w().calibration([](Json& j) {
                     j["method"] = "mcmc";
                     j["mcmc"] = {{"noise_sd", {{"distribution", "log_uniform"}, {"min", 1e-6}, {"max", 1e30}}}};
                   })),
                   Want::kError, {"'mcmc.noise_sd'", "the prior reaches 1e+30 m"}});
  const std::string escaping = w().scenario([](Json& j) { j["name"] = "../escaped"; });
  cases.push_back({"a scenario name that leaves results/", "simulate --no-plot --scenario " + escaping, Want::kError,
                   {escaping, "'name'", "../escaped", "plain file name"}, nothing_at(dir + "/escaped.h5")});
  cases.push_back({"kinematics: a 1 mm Ackermann turn", "kinematics --mode ackermann --v 0.3 --radius 0.001",
                   Want::kError, {"--radius 0.001", "yaw rate", "300 rad/s", "+-10 rad/s"}});
  const std::string late = w().out("csv"), noisy = w().out("csv");
  cases.push_back({"synthesize: the release after the last data point",
                   "synthesize --scenario " + w().quick() + " --offset 1 --out " + late, Want::kError,
                   {"--offset 1 s", "leaves 0 data point(s) at or after the release"}, nothing_at(late)});
  cases.push_back({"synthesize: noise of 1000 km", "synthesize --scenario " + w().quick() + " --noise 1e6 --out " + noisy,
                   Want::kError, {"--noise 1000000 m is more than 10 times the curve's own travel"},
                   nothing_at(noisy)});
  const std::string noise_in_mm = w().out("csv");
  cases.push_back({"synthesize: 100 m of noise on a 1 cm fall (a sd in millimetres)",
                   "synthesize --scenario " + w().quick() + " --noise 100 --out " + noise_in_mm, Want::kError,
                   {"--noise 100 m is more than 10 times", "in millimetres?", "nothing was written"},
                   nothing_at(noise_in_mm)});
  // A path ending in '/' names a directory: refused, and none is made.
  for (const auto& [command, args] : std::vector<std::pair<std::string, std::string>>{
           {"simulate", "simulate --no-plot --scenario " + w().quick() + " --out "},
           {"montecarlo", "montecarlo --no-plot --study " + w().montecarlo([](Json&) {}) + " --out "},
           {"terrain", "terrain obstacle --out "},
           {"synthesize", "synthesize --scenario " + w().quick() + " --out "}}) {
    const std::string named_dir = dir + "/new_" + command + "/";
    cases.push_back({command + " --out a new directory", args + named_dir, Want::kError, {"--out", "names a directory"},
                     nothing_at(named_dir)});
  }
  const std::string curve = simulated_curve(dir + "/curve.h5");
  cases.push_back({"compare --column the file does not hold", "compare " + curve + " " + curve + " --column Fn_9",
                   Want::kError, {"no column 'Fn_9'", "B_l_z"}});
  // A rank variable set by hand (no job size beside it) does not silence rover.
  cases.push_back({"a lone rover with PMIX_RANK=1", "simulate --scenario " + dir + "/none.json", Want::kError,
                   {"--scenario", "none.json"}, {}, "PMIX_RANK=1 OMPI_COMM_WORLD_RANK=1"});
  cases.push_back({"friction: mu_k of 1e300", "friction --mu-k 1e300", Want::kError, {"--mu-k 1e+300", "+-10,"}});
  // Heights in millimetres are within the readers' bound, but no fit meets them.
  std::string millimetres = "t,z\n";
  for (int k = 0; k <= 25; ++k) millimetres += std::to_string(0.002 * k) + "," + std::to_string(281.0 - 2.0 * k) + "\n";
  const std::string mm_data = w().text_file("mm", millimetres, "csv");
  cases.push_back({"calibrate against heights in millimetres",
                   study("calibrate", w().calibration([&](Json& j) { j["data"] = mm_data; })), Want::kAllFailed,
                   {"NOT VALID", "misses the data", "millimetres"}});
  // Fourteen runs of the Ishigami function for a 12-term expansion: most
  // bootstrap resamples are singular (an analytic model, so the basis does not
  // move with the integrator's last bits).
  const std::string few_runs = w().text_file("pce", R"({"type": "sensitivity", "method": "pce", "name": "p",
      "model": "ishigami", "design": {"type": "lhs", "samples": 14, "seed": 1}})");
  // Those 14 runs select 12 terms, a selection cross-validation rejects: exit 2.
  cases.push_back({"PCE intervals from a few bootstrap refits", study("sensitivity", few_runs), Want::kAllFailed,
                   {"y: ", "bootstrap resamples could be refitted", "no intervals", "cross-validated Q2"}, {}, {},
                   {"% bootstrap intervals, "}});
  // The quick drop is still falling at its end: no run settles.
  cases.push_back({"montecarlo of a settling time that never comes", study("montecarlo", w().montecarlo([](Json& j) {
                     j["qoi"] = {"settling_time"};
                   })),
                   Want::kRuns, {"warning: settling_time: 2 of 2 runs had not settled within the run's 0.05 s"}});
  cases.push_back({"sensitivity of a settling time that never comes", study("sensitivity", w().sensitivity([&](Json& j) {
                     j.erase("model");
                     j["method"] = "morris";
                     j["scenario"] = w().quick();
                     j["parameters"] = {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}},
                                        {"f", {{"distribution", "uniform"}, {"min", 1e3}, {"max", 1e4}}}};
                     j["design"] = {{"trajectories", 2}, {"levels", 4}, {"seed", 1}};
                     j["qoi"] = {"settling_time"};
                     j.erase("bootstrap");
                   })),
                   Want::kRuns, {"settling_time: 6 of 6 runs had not settled"}});
  // A scenario key the scenario leaves out (initial_q.x) varies like any other.
  cases.push_back({"montecarlo of an unset scenario key", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"] = {{"scenario.initial_q.x", {{"distribution", "uniform"}, {"min", 0.0}, {"max", 0.1}}}};
                   })),
                   Want::kRuns, {}});
  run_table(dir, cases);
}

// Classes 2 and 8: a surrogate whose runs all failed says why and that its
// runs are kept; a checkpoint of another configuration names --restart.
TEST_F(Audit, ThirdAuditKeptRuns) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  const std::string failing = w().scenario([](Json& s) { s["wall_time_budget"] = 1e-9; });
  const std::string surrogate = w().json_file(
      "surrogate", Json{{"type", "surrogate"},
                        {"name", "u"},
                        {"scenario", failing},
                        {"parameters", {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}}}},
                        {"design", {{"type", "lhs"}, {"samples", 6}, {"seed", 1}}},
                        {"pce", {{"max_degree", 1}}},
                        {"qoi", {"t_min"}}});
  cases.push_back({"surrogate whose every run fails", study_args("surrogate", surrogate, dir + "/u.h5"),
                   Want::kAllFailed, {"every run failed", "wall-time budget", "the results are in", "u.h5"}});
  cases.push_back({"posterior whose every run fails", study("calibrate", w().calibration([&](Json& j) {
                     j["scenario"] = failing;
                     j["method"] = "mcmc";
                     j["mcmc"] = {{"walkers", 4}, {"steps", 10}, {"target_ess", 0}};
                   })),
                   Want::kAllFailed, {"no posterior: every one of the fit's", "wall-time budget", "every run failed"}});
  // Every run of a study failing beside an earlier result leaves its checkpoint.
  const std::string earlier = write_file(dir + "/kept.h5", "an earlier result\n");
  std::string output;
  ASSERT_EQ(run_command("cd " + dir + " && OMPI_MCA_ess_singleton_isolated=1 " + rover_binary() + " " +
                            study_args("montecarlo", w().montecarlo([&](Json& j) { j["scenario"] = failing; }), earlier),
                        &output),
            2)
      << output;
  ASSERT_TRUE(fs::exists(earlier + ".checkpoint")) << output;
  cases.push_back({"--resume of another configuration's checkpoint",
                   study_args("montecarlo", w().montecarlo([](Json&) {}), earlier) + " --resume", Want::kError,
                   {earlier + ".checkpoint", "different study configuration", "--restart"},
                   [=] { return fs::exists(earlier + ".checkpoint") ? std::string() : "the checkpoint was deleted"; }});
  // The same for a posterior: refused before the fit, not after it.
  const std::string posterior = dir + "/posterior.h5";
  write_file(posterior + ".checkpoint", "not a checkpoint\n");
  cases.push_back({"a posterior's --resume of a foreign checkpoint", study_args("calibrate", w().calibration([](Json& j) {
                     j["method"] = "mcmc";
                   }), posterior) + " --resume",
                   Want::kError, {posterior + ".checkpoint", "not a rover checkpoint"}, {}, {}, {"Jacobian"}});
  run_table(dir, cases);
}

// Class 2: CSV into a pipe that no process reads is refused at once; it used
// to wait forever.
TEST_F(Audit, ThirdAuditPipeWithoutReader) {
  const std::string dir = w().dir(), pipe = dir + "/unread.csv";
  ASSERT_EQ(run_command("mkfifo " + pipe), 0);
  std::string output;
  const int status = run_command("cd " + dir + " && OMPI_MCA_ess_singleton_isolated=1 timeout -k 2 20 " +
                                     rover_binary() + " simulate --no-plot --scenario " + w().quick() + " --out " +
                                     w().out() + " --csv " + pipe,
                                 &output);
  EXPECT_EQ(status, 1) << output;
  EXPECT_NE(output.find("no process reads"), std::string::npos) << output;
}

// Class 4: a signal while a calibration computes its profiles (work after
// the fit, outside the study's checkpointed runs) ends it with status 130
// and writes nothing: the profiles it would write are incomplete.
TEST_F(Audit, ThirdAuditInterruptedProfiles) {
  const std::string dir = w().dir();
  const std::string calibration = w().calibration([](Json& j) {
    j["profile"] = true;
    j["profile_points"] = 5000;
  });
  const std::string out = dir + "/profiled.h5", log = dir + "/profiled.log";
  // The probe's progress line comes when the probe is done; the profiles follow.
  std::string output;
  run_command("cd " + dir + " && (OMPI_MCA_ess_singleton_isolated=1 timeout -k 2 60 " + rover_binary() + " " +
                  study_args("calibrate", calibration, out) + " > " + log + " 2>&1 & pid=$!; " +
                  "for i in $(seq 600); do grep -q 'profile probe' " + log + " && break; sleep 0.05; done; " +
                  "kill -TERM $pid; wait $pid; echo \"status $?\"; cat " + log + ")",
              &output);
  EXPECT_NE(output.find("status 130"), std::string::npos) << output;
  EXPECT_NE(output.find("interrupted"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(out)) << output;
}

// Numbers that are finite but say nothing: tolerances that allow any answer,
// a rest time beyond the curves, a reference in millimetres.
TEST_F(Audit, MeaninglessSettingsAreRefusedOrNamed) {
  std::vector<Case> cases;
  const std::string loose = w().scenario([](Json& j) { j["integrator"] = {{"method", "rosenbrock"}, {"rtol", 1.0}}; });
  cases.push_back({"an integrator rtol of 1", "simulate --no-plot --scenario " + loose + " --out " + w().out(),
                   Want::kError, {"rtol", "[1e-14, 0.1]", "got 1"}});
  const std::string wide = w().scenario([](Json& j) { j["integrator"] = {{"method", "dopri5"}, {"atol", 0.5}}; });
  cases.push_back({"an integrator atol of 0.5 m", "simulate --no-plot --scenario " + wide + " --out " + w().out(),
                   Want::kError, {"atol", "[1e-18, 0.01]", "got 0.5"}});
  const std::string data = source_path("configs/data/drop_horizontal_synthetic.csv");
  cases.push_back({"compare: a rest time beyond both curves", "compare " + data + " " + data + " --rest-time 50",
                   Want::kError, {"--rest-time 50 s", "curve A [", "curve B [", "times both curves cover"}});
  cases.push_back({"compare: a rest time beyond one curve",
                   "compare " + data + " " + data + " --time-offset 0.5 --rest-time 0.8", Want::kError,
                   {"--rest-time 0.8 s lies outside the times both curves cover", "curve B [-0.5",
                    "give a rest time within"}});
  cases.push_back({"compare: an offset that leaves no common interval",
                   "compare " + data + " " + data + " --time-offset 10", Want::kError,
                   {"curve A [", "--time-offset 10 s", "no common time interval"}});
  cases.push_back({"kinematics: a crab angle of a million degrees",
                   "kinematics --mode parallel --v 0.5 --crab-deg 1e6", Want::kError, {"--crab-deg", "[-180, 180]", "got 1000000"}});
  cases.push_back({"surface: four points on an axis of one value", study("surface", w().surface([](Json& j) {
                     j["c_q"] = {{"min", 0.14}, {"max", 0.14}, {"count", 4}};
                   })),
                   Want::kError, {"'c_q.count'", "identical runs"}});
  std::string millimetres = "t,z\n";
  for (int i = 0; i <= 10; ++i) millimetres += std::to_string(0.005 * i) + "," + std::to_string(281.0 - i) + "\n";
  const std::string reference = w().text_file("reference_mm", millimetres, "csv");
  cases.push_back({"montecarlo: rms_vs a reference in millimetres", study("montecarlo", w().montecarlo([&](Json& j) {
                     j["qoi"] = {{{"name", "rms_vs"}, {"reference", reference}}};
                   })),
                   Want::kRuns, {"every run misses the reference", "not millimetres"}});
  run_table(w().dir(), cases);
}

// A Unix socket bound at `path` (it stays after the descriptor is closed).
void bind_unix_socket(const std::string& path) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  ASSERT_LT(path.size(), sizeof address.sun_path);
  std::strcpy(address.sun_path, path.c_str());
  ASSERT_EQ(::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0) << path;
  ::close(fd);
}

// A reference in millimetres against `compare` and `surface`, the record of a
// failed run read as a curve, a surrogate asked beyond where it was trained
// (a lognormal's lower end), and a held-out set too small for a Q2.
TEST_F(Audit, SuspectReferencesAndSurrogateValidityLimits) {
  std::vector<Case> cases;
  // The synthetic drop's first 150 rows (0.3 s) with heights in millimetres.
  std::string millimetres;
  std::istringstream rows(measured_text("\n", 150));
  for (std::string line; std::getline(rows, line);) {
    const std::size_t comma = line.find(',');
    if (line.starts_with("t,")) millimetres += line + "\n";
    else millimetres += line.substr(0, comma) + "," + std::to_string(1000.0 * std::stod(line.substr(comma + 1))) + "\n";
  }
  const std::string mm = w().text_file("reference_mm", millimetres, "csv");
  const std::string run = simulated_curve(w().dir() + "/run.h5");
  cases.push_back({"compare against a reference in millimetres",
                   "compare " + run + " " + mm + " --time-offset 0.05 --rest-time 0.04", Want::kRuns,
                   {"warning", "misses (RMS", "millimetres"}});
  const std::string surface_out = w().out();
  const std::string surface_mm = w().surface([&](Json& j) {
    j["reference"] = {{"file", mm}, {"time_offset", 0.05}};
  });
  cases.push_back({"surface against a reference in millimetres", study_args("surface", surface_mm, surface_out),
                   Want::kRuns, {"warning: rms: every run misses the reference", "millimetres"},
                   [surface_out] {
                     const io::Hdf5Reader h5(surface_out);
                     return h5.has_attribute("/", "reference_warning") ? std::string()
                                                                       : surface_out + " has no reference_warning";
                   }});
  // A run that blows up at 0.15 s (rk4 at 5 ms steps): its record holds
  // finite heights up to 1e60 m before the failure.
  const std::string failed = w().dir() + "/failed.h5";
  const std::string blows_up = w().scenario([](Json& j) {
    j["duration"] = 0.2;
    j["integrator"] = {{"method", "rk4"}, {"fixed_step", 0.005}};
  });
  std::string output;
  ASSERT_EQ(run_command(rover_binary() + " simulate --no-plot --scenario " + blows_up + " --out " + failed, &output), 2)
      << output;
  const std::vector<std::string> failed_words = {failed, "the record of a failed run", "non-finite state"};
  cases.push_back({"compare with the record of a failed run", "compare " + run + " " + failed, Want::kError,
                   failed_words});
  const std::string mc_failed = w().montecarlo([&](Json& j) {
    j["qoi"] = {{{"name", "rms_vs"}, {"reference", failed}, {"channel", "B_l_z"}}};
  });
  std::vector<std::string> mc_words = failed_words;
  mc_words.push_back("'qoi[0].reference'");
  cases.push_back({"rms_vs against the record of a failed run", study("montecarlo", mc_failed), Want::kError, mc_words});
  // A PCE of the linear model with x1 lognormal: trained on x1 near 1, never
  // near the lognormal's lower end 0.
  const Json surrogate{{"type", "surrogate"},
                       {"name", "lin"},
                       {"model", "linear"},
                       {"parameters", {{"x1", {{"distribution", "lognormal"}, {"mean", 1.0}, {"sd", 0.2}}}}},
                       {"design", {{"samples", 20}, {"seed", 1}}},
                       {"pce", {{"max_degree", 1}, {"bootstrap", 0}}}};
  const std::string trained = w().out();
  ASSERT_EQ(run_command(rover_binary() + " " + study_args("surrogate", w().json_file("lin", surrogate), trained), &output), 0)
      << output;
  const std::string near_zero = w().text_file("near_zero", "x1,x2,x3,x4\n1e-6,0,0,0\n", "csv");
  cases.push_back({"surrogate predicted at a lognormal's lower end",
                   "surrogate --predict " + trained + " --design " + near_zero + " --csv " + w().out("csv"),
                   Want::kError, {near_zero, "x1 = 1e-06 lies outside the training support"}});
  Json one_held_out = surrogate;
  one_held_out["design"]["samples"] = 10;
  one_held_out["held_out"] = {{"fraction", 0.1}};
  cases.push_back({"a held-out set of one run", study("surrogate", w().json_file("held1", one_held_out)), Want::kError,
                   {"held_out.fraction", "holds out 1 run", "needs at least 2"}});
  Json two_held_out = surrogate;
  two_held_out["held_out"] = {{"fraction", 0.1}};
  cases.push_back({"--samples leaving one held-out run",
                   study("surrogate", w().json_file("held2", two_held_out)) + " --samples 10", Want::kError,
                   {"--samples 10", "held_out.fraction", "needs at least 2"}});
  run_table(w().dir(), cases);
}

// Every number of the rover file within its scale (a unit mistake named),
// a flag's error blamed on the flag, a study whose every run failed saying
// why and what it kept, degenerate inputs refused, unreadable HDF5 files and
// integer flags in rover's words, and confidences the resamples resolve.
TEST_F(Audit, UnitMistakesFlagsAndFailuresInRoversWords) {
  std::vector<Case> cases;
  auto rover_case = [&](const std::string& id, const std::function<void(Json&)>& edit,
                        std::vector<std::string> mentions) {
    const std::string path = w().rover(edit);
    mentions.insert(mentions.begin(), path);
    mentions.push_back("a unit mistake");
    cases.push_back({id, simulate(w().scenario_with_rover(path)), Want::kError, mentions});
  };
  rover_case("an inertia in kg mm^2",
             [](Json& j) { j["bodies"]["chassis"]["inertia"] = {{6630, 0, -150}, {0, 11020, 0}, {-150, 0, 14610}}; },
             {"'bodies.chassis.inertia'", "6630", "+-1 kg m^2"});
  rover_case("a centre of mass 20 m away", [](Json& j) { j["bodies"]["module2"]["com"] = {0.1, 0.04, 20}; },
             {"'bodies.module2.com'", "20 m", "+-10 m"});
  rover_case("a wheel radius in millimetres", [](Json& j) { j["geometry"]["wheel_radius"] = 85; },
             {"'geometry.wheel_radius'", "85 m", "+-10 m"});
  rover_case("a hip in millimetres", [](Json& j) { j["geometry"]["hip"] = {107.8, 0, -26.5}; },
             {"'geometry.hip'", "107.8 m", "+-10 m"});
  rover_case("friction in percent", [](Json& j) { j["friction"]["mu_s"] = 30; }, {"'friction.mu_s'", "30", "+-10,"});
  rover_case("a kinetic friction in percent", [](Json& j) { j["friction"]["mu_k"] = 20; },
             {"'friction.mu_k'", "20", "+-10,"});
  rover_case("Stribeck speeds in mm/s", [](Json& j) { j["friction"]["v_k"] = 2.0; },
             {"'friction.v_k'", "2 m/s", "+-0.1 m/s"});
  rover_case("a steering limit in degrees", [](Json& j) { j["steering"]["limit"] = 100; },
             {"'steering.limit'", "100 rad", "+-6.28"});
  rover_case("k_q a thousand times the paper's", [](Json& j) { j["s_structure"]["k_q"] = 9910; },
             {"'s_structure.k_q'", "9910 N m/rad", "+-1000 N m/rad"});
  rover_case("a steering gain beyond scale", [](Json& j) { j["steering"]["K_d"] = 2e4; },
             {"'steering.K_d'", "20000 N m/rad", "+-10000 N m/rad"});
  rover_case("a drive torque in mN m", [](Json& j) { j["drive"]["tau_max"] = 4100; },
             {"'drive.tau_max'", "4100 N m", "+-100 N m"});
  rover_case("a drive gain beyond scale", [](Json& j) { j["drive"]["K_w"] = 3000; },
             {"'drive.K_w'", "3000 N m s/rad", "+-1000 N m s/rad"});
  rover_case("a ground stiffness beyond scale", [](Json& j) { j["contact"]["k_g"] = 1e9; },
             {"'contact.k_g'", "1000000000 N/m^sigma", "+-100000000"});
  rover_case("a contact exponent of 180", [](Json& j) { j["contact"]["sigma"] = 180; },
             {"'contact.sigma'", "180", "+-10,"});
  cases.push_back({"rover friction: mu_s in percent", "friction --mu-s 30", Want::kError,
                   {"--mu-s 30", "+-10,", "a unit mistake (percent)?"}});
  cases.push_back({"a Morris study over sensible ranges of the rover's parameters",
                   "sensitivity --dry-run --study " + source_path("configs/studies/morris_obstacle.json") +
                       " --out " + w().out(),
                   Want::kRuns, {"dry run"}});
  // A flag's error names the flag, not the study file's field.
  const std::string calibration = w().calibration([](Json&) {});
  cases.push_back({"calibrate --walkers 2", study("calibrate", calibration) + " --dry-run --method mcmc --walkers 2", Want::kError,
                   {"--walkers: got 2", "at least 4"}, {}, {}, {"mcmc.walkers"}});
  cases.push_back({"calibrate --steps 2 --discard 0", study("calibrate", calibration) + " --dry-run --method mcmc --steps 2 --discard 0",
                   Want::kError, {"--steps 2 with --discard 0", "leaves 2 step(s)", "need at least 4"}, {}, {}, {"mcmc."}});
  cases.push_back({"calibrate --steps 3", study("calibrate", calibration) + " --dry-run --method mcmc --steps 3", Want::kError,
                   {"--steps 3", "leaves 2 step(s) after a burn-in of 1", "need at least 4"}, {}, {}, {"mcmc."}});
  cases.push_back({"calibrate --algorithm with gradients", study("calibrate", calibration) + " --dry-run --algorithm LD_MMA",
                   Want::kError, {"--algorithm: 'LD_MMA' needs gradients"}, {}, {}, {"field 'algorithm'"}});
  // Every run failed: the reason is given, and a checkpoint named only if kept.
  const std::string failing = w().scenario([](Json& j) { j["wall_time_budget"] = 1e-6; });
  const std::string earlier = simulated_curve(w().dir() + "/earlier_fit.h5");
  cases.push_back({"a calibration whose every run fails, over an earlier result",
                   study_args("calibrate", w().calibration([&](Json& j) { j["scenario"] = failing; }), earlier),
                   Want::kAllFailed, {"every run failed (first: ", "is unchanged", "no run was kept"},
                   unchanged(earlier), {}, {".checkpoint"}});
  cases.push_back({"a kriged surface whose every run fails",
                   study("surface", w().surface([&](Json& j) {
                     j["scenario"] = failing;
                     j["surrogate"] = "gp";
                     j["runs"] = 5;
                     j["reference"] = {{"file", source_path("configs/data/drop_horizontal_synthetic.csv")}};
                     j["c_q"] = {{"min", 0.1}, {"max", 0.2}, {"count", 2}};
                   })),
                   Want::kAllFailed, {"every run failed (first: time budget exceeded"}, {}, {}, {"(first: )"}});
  // An HDF5 input cut short or damaged, in rover's words.
  const std::string whole = simulated_curve(w().dir() + "/whole.h5");
  const std::string bytes = file_bytes(whole);
  const std::string cut = w().text_file("cut", bytes.substr(0, 3000), "h5");
  std::string damaged_bytes = bytes;
  damaged_bytes.replace(1000, 2000, std::string(2000, '\xff'));
  const std::string damaged = w().text_file("damaged", damaged_bytes, "h5");
  cases.push_back({"compare: an HDF5 file cut short", "compare " + cut + " " + whole, Want::kError,
                   {cut + " is not a complete HDF5 file", "ends after 3000 of its"}, {}, {}, {"HDF5:", "eof"}});
  cases.push_back({"compare: a damaged HDF5 file", "compare " + damaged + " " + whole, Want::kError,
                   {damaged + " is not a readable HDF5 file"}, {}, {}, {"HDF5:"}});
  cases.push_back({"calibrate --data an HDF5 file", study("calibrate", calibration) + " --data " + cut,
                   Want::kError, {cut + ": an HDF5 file; a measured curve is read as CSV"}, {}, {}, {"columns:"}});
  // Degenerate inputs: refused, naming the field.
  cases.push_back({"surface: one point on an axis from 0.1 to 0.4", study("surface", w().surface([](Json& j) {
                     j["c_q"] = {{"min", 0.1}, {"max", 0.4}, {"count", 1}};
                   })),
                   Want::kError, {"'c_q.count'", "max = 0.4 would be ignored"}});
  const std::string late = w().drive_scenario(
      {{"segments", {{{"start", 0.0}, {"mode", "parallel"}, {"speed", 0.1}},
                     {{"start", 0.1}, {"mode", "parallel"}, {"speed", 0.2}}}}});
  cases.push_back({"a drive segment after the scenario's end", simulate(late), Want::kError,
                   {late, "'drive.segments[1].start'", "0.1 s", "duration 0.05 s"}});
  const std::string two_samples = w().scenario([](Json& j) {
    j["duration"] = 0.015;
    j["output_rate"] = 100;
  });
  cases.push_back({"a scenario recording 2 samples", simulate(two_samples), Want::kError,
                   {two_samples, "'duration'", "2 sample(s)", "at least 2 output periods (0.02 s)"}});
  const std::string slow = w().json_file(
      "candidates", Json{{"candidates", {{{"scenario", w().quick()}, {"rate_hz", 0.5}, {"noise_sd", 1e-4}}}}});
  cases.push_back({"next experiment: a rate giving one sample",
                   study("calibrate", calibration) + " --dry-run --next-experiment " + slow, Want::kError,
                   {slow, "'candidates[0].rate_hz'", "0.5 Hz", "1 sample(s)", "at least 3"}});
  // Integer flags read as the study files read counts.
  const std::string mc = w().montecarlo([](Json&) {});
  cases.push_back({"--samples 1e3", study("montecarlo", mc) + " --dry-run --samples 1e3", Want::kRuns, {"1000 runs"}});
  cases.push_back({"--samples 2.5", study("montecarlo", mc) + " --dry-run --samples 2.5", Want::kError,
                   {"--samples", "must be a whole number, from ", ", got 2.5"}});
  cases.push_back({"--walkers 3 on a least-squares fit",
                   study("calibrate", w().calibration([](Json&) {})) + " --dry-run --walkers 3", Want::kError,
                   {"--walkers 3 applies to --method mcmc only"}, {}, {}, {"must be even"}});
  const std::string tiny_max_step = w().scenario([](Json& j) {
    j["integrator"] = {{"method", "dopri5"}, {"max_step", 1e-15}};
  });
  cases.push_back({"max_step below min_step", simulate(tiny_max_step), Want::kError,
                   {"'integrator.max_step'", "1e-15"}, {}, {}, {"integrator.min_step"}});
  // A confidence the bootstrap resolves, printed with its digits.
  auto pce = [&](double confidence, int resamples) {
    return w().sensitivity([&](Json& j) {
      j["method"] = "pce";
      j.erase("bootstrap");
      j["design"] = {{"type", "lhs"}, {"samples", 100}, {"seed", 1}};
      j["confidence"] = confidence;
      j["pce"] = {{"max_degree", 10}, {"bootstrap", resamples}};
    });
  };
  cases.push_back({"PCE: confidence 0.999999 from 100 resamples", study("sensitivity", pce(0.999999, 100)),
                   Want::kError, {"'confidence'", "0.999999", "'pce.bootstrap' 100", "at least 1000000 resamples"}});
  cases.push_back({"PCE: confidence 0.996 printed as it is", study("sensitivity", pce(0.996, 300)), Want::kRuns,
                   {"99.6 % bootstrap intervals"}});
  run_table(w().dir(), cases);
}

// Unit mistakes in the rover's gravity and masses, a distribution tail the
// model refuses, a failed simulate over an earlier result, a socket or a
// dangling link as an output, and non-finite results traced to their input.
TEST_F(Audit, UnitMistakesTailsAndSpecialOutputs) {
  std::vector<Case> cases;
  cases.push_back({"gravity in cm/s^2", simulate(w().scenario_with_rover(w().rover([](Json& j) { j["gravity"] = 981; }))),
                   Want::kError, {"'gravity'", "981", "a unit mistake?"}});
  cases.push_back({"a body mass in grams",
                   simulate(w().scenario_with_rover(w().rover([](Json& j) { j["bodies"]["chassis"]["mass"] = 1267; }))),
                   Want::kError, {"'bodies.chassis.mass'", "1267", "a unit mistake?"}});
  cases.push_back({"a normal c_q whose lower tail is negative", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"]["c_q"] = {{"distribution", "normal"}, {"mean", 0.05}, {"sd", 0.1}};
                   })),
                   Want::kRuns, {"warning: 'c_q': about 30.9 % of its normal", "lower tail", "truncate"}});
  cases.push_back({"a normal c_q far from zero", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"]["c_q"] = {{"distribution", "normal"}, {"mean", 0.15}, {"sd", 0.01}};
                   })),
                   Want::kRuns, {}, {}, {}, {"lower tail", "upper tail"}});
  const std::string good = simulated_curve(w().dir() + "/earlier_result.h5");
  const std::string failing = w().scenario([](Json& j) { j["wall_time_budget"] = 1e-6; });
  cases.push_back({"a failed simulate over an earlier result",
                   "simulate --no-plot --scenario " + failing + " --out " + good, Want::kAllFailed,
                   {"the earlier result", "was kept"}, unchanged(good)});
  const std::string socket = w().dir() + "/sock";
  bind_unix_socket(socket);
  cases.push_back({"--csv at a socket", simulate(w().quick()) + " --csv " + socket, Want::kError,
                   {"--csv", "is a socket"}});
  const std::string dangling = w().dir() + "/dangling.h5";
  fs::create_symlink("/nonexistent-target-dir/x.h5", dangling);
  cases.push_back({"--out at a dangling link", "simulate --no-plot --scenario " + w().quick() + " --out " + dangling,
                   Want::kError, {"to '/nonexistent-target-dir/x.h5', which does not exist"},
                   still_a_link(dangling, "/nonexistent-target-dir/x.h5")});
  Json state{{"q", std::vector<double>(23, 0.0)}, {"u", std::vector<double>(23, 1e300)}};
  state["q"][2] = 0.281;
  cases.push_back({"eom at an overflowing state", "eom --state " + w().json_file("state", state), Want::kError,
                   {"field 'u'", "1e+300 m/s is beyond +-10 m/s"}});
  std::string flat = "t,z\n";
  for (int i = 0; i <= 20; ++i) flat += std::to_string(0.05 * i) + ",0.2\n";
  cases.push_back({"compare against a reference that never rebounds",
                   "compare " + source_path("configs/data/drop_horizontal_synthetic.csv") + " " +
                       w().text_file("flat", flat, "csv"),
                   Want::kError, {"deflection_error (eq. 10) is undefined", "curve B", "--rest-time 1 s"}});
  cases.push_back({"evaluate: settling times of runs that never settled",
                   "evaluate --scenario " + w().quick() + " --design " + w().text_file("design", "c_q\n0.1\n0.2\n", "csv") +
                       " --qoi settling_time --out " + w().out("csv"),
                   Want::kRuns, {"warning: settling_time: 2 of 2 runs had not settled"}});
  run_table(w().dir(), cases);
}

// Every shipped study file passes every check of its command (a dry run).
TEST_F(Audit, ShippedStudiesPassTheirChecks) {
  const std::map<std::string, std::string> command_of_type = {{"montecarlo", "montecarlo"},
                                                              {"sensitivity", "sensitivity"},
                                                              {"surface", "surface"},
                                                              {"calibration", "calibrate"},
                                                              {"surrogate", "surrogate"}};
  std::vector<Case> cases;
  for (const auto& entry : fs::directory_iterator(source_path("configs/studies"))) {
    if (entry.path().extension() != ".json") continue;
    const Json study_file = io::read_json_file(entry.path().string());
    const std::string type = study_file.at("type").get<std::string>();
    ASSERT_TRUE(command_of_type.count(type)) << entry.path() << ": type " << type;
    const std::string args = study_args(command_of_type.at(type), entry.path().string(), w().out()) + " --dry-run";
    // A surrogate trained on another study's results (made by scripts/main.sh)
    // is refused, naming that file, until they exist.
    if (study_file.contains("training") && study_file["training"].contains("file")) {
      const fs::path training = entry.path().parent_path() / study_file["training"]["file"].get<std::string>();
      if (!fs::exists(training)) {
        cases.push_back({entry.path().filename().string(), args, Want::kError, {training.filename().string()}});
        continue;
      }
    }
    cases.push_back({entry.path().filename().string(), args, Want::kRuns, {"dry run"}});
  }
  ASSERT_GE(cases.size(), 10u);
  run_table(w().dir(), cases);
}

// Half-bounded distributions, the console and a CSV sharing one file, a
// failed run beside an earlier CSV, tails beyond max_failed_fraction, and
// evaluate rows whose settling time is none.
TEST_F(Audit, FifthAuditCases) {
  std::vector<Case> cases;
  cases.push_back({"a lognormal c_q", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"]["c_q"] = {{"distribution", "lognormal"}, {"mean", 0.1}, {"sd", 0.05}};
                   })),
                   Want::kRuns, {"2 runs (0 failed)"}, {}, {}, {"lower tail", "upper tail"}});
  cases.push_back({"a normal c_q truncated below only", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"]["c_q"] = {{"distribution", "normal"}, {"mean", 0.1}, {"sd", 0.05},
                                               {"truncate", {0.02, nullptr}}};
                   })),
                   Want::kRuns, {"2 runs (0 failed)"}, {}, {}, {"lower tail", "upper tail"}});
  const std::string both = w().dir() + "/both.csv";
  cases.push_back({"--csv /dev/stdout with stdout and stderr in one file",
                   simulate(w().quick()) + " --csv /dev/stdout > " + both + " 2>&1", Want::kRuns, {},
                   [both] {
                     const std::string text = file_bytes(both);
                     if (text.find("\nt,B_l_z,") == std::string::npos) return both + " lost the CSV header:\n" + text.substr(0, 400);
                     if (text.find("wrote /dev/stdout") == std::string::npos) return both + " lost the console lines";
                     return std::string();
                   }});
  const std::string earlier_csv = w().text_file("earlier", "t,B_l_z\n0,0.281\n", "csv");
  const std::string failing = w().scenario([](Json& j) { j["wall_time_budget"] = 1e-6; });
  cases.push_back({"a failed simulate beside an earlier CSV",
                   "simulate --no-plot --scenario " + failing + " --out " + w().out() + " --csv " + earlier_csv,
                   Want::kAllFailed, {"the run failed", "no CSV or plot of a failed run"}, unchanged(earlier_csv)});
  cases.push_back({"sensitivity: tails the model refuses beyond max_failed_fraction",
                   study("sensitivity", w().sensitivity([&](Json& j) {
                     j.erase("model");
                     j["scenario"] = w().quick();
                     j["qoi"] = {"t_min"};
                     j["parameters"] = {{"c_q", {{"distribution", "normal"}, {"mean", 0.05}, {"sd", 0.05}}},
                                        {"f", {{"distribution", "uniform"}, {"min", 1e3}, {"max", 1e4}}}};
                   })),
                   Want::kError, {"'max_failed_fraction'", "is 0.05", "about 29.2 % of the pick-freeze groups", "15.9 % of the samples", "'c_q'", "truncate"}});
  const std::string socket_out = w().dir() + "/sk.h5";
  bind_unix_socket(socket_out + ".checkpoint");
  cases.push_back({"--restart with a socket where the checkpoint goes",
                   study_args("montecarlo", w().montecarlo([](Json&) {}), socket_out) + " --restart", Want::kError,
                   {"sk.h5.checkpoint is no checkpoint"}, [socket_out] {
                     return fs::is_socket(fs::symlink_status(socket_out + ".checkpoint"))
                                ? std::string()
                                : "the socket at " + socket_out + ".checkpoint was removed";
                   }});
  const std::string rows = w().out("csv");
  cases.push_back({"evaluate: a row whose settling time is none",
                   "evaluate --scenario " + w().quick() + " --design " + w().text_file("design", "c_q\n0.1\n", "csv") +
                       " --qoi settling_time --out " + rows,
                   Want::kRuns, {"had not settled"}, [rows] {
                     return file_bytes(rows).find("settling_time is no settling time") == std::string::npos
                                ? rows + " does not say the settling time is none"
                                : std::string();
                   }});
  run_table(w().dir(), cases);
}

// Flags named as typed, terrains no reader takes, unscaled states and speeds,
// a prediction under mpirun, permissions and unwritable folders, misspelt
// keys, looping links, SIGTERM, calibrate flags that do not apply, an
// unreachable grid and a hard link of an input at a plot's path.
TEST_F(Audit, EighthAuditDriverCases) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  const std::string q = w().quick();
  const std::string sim = "simulate --no-plot --scenario " + q;
  auto nothing_at = [](const std::string& path) {
    return [=] { return fs::exists(path) ? path + " was written" : std::string(); };
  };
  cases.push_back({"a flag given twice", sim + " --out " + w().out() + " --f 1e4 --f 2e4", Want::kError,
                   {"--f was given 2 times ('1e4', '2e4')", "give it once"}, {}, {}, {"needs a value"}});
  cases.push_back({"--out after '--'", sim + " -- --out " + w().out(), Want::kError,
                   {"'--out' follows '--'"}, {}, {}, {"did you mean '--out'"}});
  cases.push_back({"--seed= with nothing after '='",
                   "montecarlo --study " + w().montecarlo([](Json&) {}) + " --out " + w().out() + " --seed= --dry-run",
                   Want::kError, {"--seed was given an empty value", "'--seed='"}, {}, {}, {"'--dry-run'"}});
  cases.push_back({"--out followed by another option", "simulate --scenario " + q + " --out --no-plot", Want::kError,
                   {"--out was given no value", "'--no-plot', is an option"}, nothing_at(dir + "/--no-plot")});
  cases.push_back({"--seed followed by another option",
                   "montecarlo --study " + w().montecarlo([](Json&) {}) + " --out " + w().out() + " --seed --dry-run",
                   Want::kError, {"--seed was given no value", "'--dry-run', is an option"}});
  cases.push_back({"an em dash for --", "simulate --no-plot \xE2\x80\x94scenario " + q + " --out " + w().out(),
                   Want::kError, {"starts with an em dash (U+2014)", "type '--scenario'"}});
  cases.push_back({"terrain obstacle --foot-x 1e7", "terrain obstacle --out " + dir + "/far.json --foot-x 1e7",
                   Want::kError, {"--foot-x 10000000 m is beyond +-1000000 m", "terrain readers refuse"},
                   nothing_at(dir + "/far.json")});
  cases.push_back({"terrain obstacle --spacing 0.5", "terrain obstacle --out " + dir + "/tent.json --spacing 0.5",
                   Want::kError, {"--spacing 0.5 m does not resolve the obstacle", "at most 0.2747"},
                   nothing_at(dir + "/tent.json")});
  std::vector<double> far(23, 0.0);
  far[0] = 1e7;
  far[2] = 0.3;
  cases.push_back({"eom: a state 1e7 m away",
                   "eom --state " + w().json_file("state", Json{{"q", far}, {"u", std::vector<double>(23, 0.0)}}),
                   Want::kError, {"field 'q'", "entry 0 (x) = 10000000 m is beyond"}});
  std::vector<double> level(23, 0.0);
  level[2] = 0.3;
  cases.push_back({"eom: a wheel speed reference of 1e6 rad/s",
                   "eom --state " + w().json_file("state", Json{{"q", level},
                                                                {"u", std::vector<double>(23, 0.0)},
                                                                {"params", {{"w_ref", {1e6, 0, 0, 0}}}}}),
                   Want::kError, {"field 'params.w_ref'", "1000000 rad/s is beyond"}});
  cases.push_back({"surrogate --predict under mpirun",
                   "surrogate --predict " + q + " --design " + w().text_file("design", "c_q\n0.1\n", "csv") +
                       " --csv " + dir + "/predicted.csv",
                   Want::kError, {"--predict runs on one process", "mpirun started 2"},
                   nothing_at(dir + "/predicted.csv"), "OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=0"});
  const std::string private_csv = w().text_file("private", "t\n", "csv");
  fs::permissions(private_csv, fs::perms::owner_read | fs::perms::owner_write);
  cases.push_back({"a 0600 CSV replaced", sim + " --out " + w().out() + " --csv " + private_csv, Want::kRuns, {},
                   [private_csv] {
                     const fs::perms mode = fs::status(private_csv).permissions();
                     return mode == (fs::perms::owner_read | fs::perms::owner_write)
                                ? std::string()
                                : private_csv + " lost its 0600 permissions";
                   }});
  const std::string kept_out = dir + "/not_written.h5";
  cases.push_back({"--csv where no file can be created", sim + " --out " + kept_out + " --csv /sys/rover_audit.csv",
                   Want::kError, {"--csv '/sys/rover_audit.csv'", "no file can be created in '/sys'"},
                   nothing_at(kept_out)});
  cases.push_back({"synthesize --out where no file can be created",
                   "synthesize --scenario " + q + " --out /sys/rover_audit.csv", Want::kError,
                   {"--out '/sys/rover_audit.csv'", "no file can be created in '/sys'"}});
  cases.push_back({"a misspelt distribution key", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"]["c_q"] = {{"distribuion", "uniform"}, {"min", 0.1}, {"max", 0.2}};
                   })) + " --dry-run",
                   Want::kError, {"'parameters.c_q.distribution'", "'distribuion'", "misspelling of 'distribution'"}});
  cases.push_back({"a misspelt duration", simulate(w().scenario([](Json& j) {
                     j["duraton"] = j["duration"];
                     j.erase("duration");
                   })),
                   Want::kError, {"'duraton'", "misspelling of 'duration'"}});
  cases.push_back({"initial_u z of -1000 m/s", simulate(w().scenario([](Json& j) { j["initial_u"] = {{"z", -1000}}; })),
                   Want::kError, {"'initial_u'", "z = -1000 m/s is beyond +-10 m/s"}});
  cases.push_back({"initial_u phi of 1e6 rad/s",
                   simulate(w().scenario([](Json& j) { j["initial_u"] = {{"phi", 1e6}}; })), Want::kError,
                   {"'initial_u'", "phi = 1000000 rad/s is beyond"}});
  cases.push_back({"wheel_speed_ref of 1e4 rad/s",
                   simulate(w().scenario([](Json& j) { j["wheel_speed_ref"] = {1e4, 0, 0, 0}; })), Want::kError,
                   {"'wheel_speed_ref'", "10000 rad/s is beyond", "wheel radius 0.085 m"}});
  cases.push_back({"a drive ramp of 300 s in a 0.05 s run",
                   simulate(w().drive_scenario(Json{{"ramp_time", 300},
                                                    {"segments", {{{"start", 0}, {"mode", "car"}, {"speed", 0.0}},
                                                                  {{"start", 0.01}, {"mode", "car"}, {"speed", 0.3}}}}})),
                   Want::kError, {"'drive.ramp_time'", "300 s is longer than the run"}});
  cases.push_back({"an obstacle run that never reaches the grid", simulate(w().scenario([](Json& j) {
                     j["terrain"] = source_path("configs/terrains/obstacle.json");
                     j["forward_speed"] = 1;
                     j["initial_q"]["x"] = 1360;
                   })),
                   Want::kError, {"'initial_q'", "the rover starts at x = 1360 m", "never reaches the grid"}});
  fs::create_symlink("loop.json", dir + "/loop.json");
  cases.push_back({"a terrain through a looping link", simulate(w().scenario_with_terrain(dir + "/loop.json")),
                   Want::kError, {"field 'terrain'", "Too many levels of symbolic links"}, {}, {}, {"filesystem error"}});
  const std::string long_run = w().scenario([](Json& j) {
    j["duration"] = 20;
    j["integrator"] = {{"method", "rk4"}};
  });
  // An outer timeout sends SIGTERM after 2 s (the inner one passes it on);
  // the status is echoed, as run_table takes 0, 1 or 2 only.
  cases.push_back({"SIGTERM during simulate",
                   "simulate --no-plot --scenario " + long_run + " --out " + dir + "/term.h5 2>&1; echo exit status $?",
                   Want::kRuns, {"rover simulate: interrupted", "nothing written", "exit status 130"},
                   nothing_at(dir + "/term.h5"), "timeout -s TERM --preserve-status 2"});
  const std::string calibration = w().calibration([](Json&) {});
  const std::string candidates = w().json_file("candidates", Json::object());
  cases.push_back({"calibrate --method mcmc --next-experiment",
                   study("calibrate", calibration) + " --method mcmc --next-experiment " + candidates + " --dry-run",
                   Want::kError, {"--next-experiment", "does not go with --method mcmc"}});
  cases.push_back({"calibrate --method mcmc --profile",
                   study("calibrate", calibration) + " --method mcmc --profile --dry-run", Want::kError,
                   {"--profile: profile likelihoods follow a least-squares fit"}});
  cases.push_back({"calibrate --walkers without mcmc", study("calibrate", calibration) + " --walkers 8 --dry-run",
                   Want::kError, {"--walkers 8 applies to --method mcmc only"}});
  const std::string plot_out = dir + "/hp.h5";
  fs::create_hard_link(q, dir + "/hp_summary.png");
  cases.push_back({"a hard link of an input at a plot's path",
                   "montecarlo --study " + w().montecarlo([](Json&) {}) + " --out " + plot_out, Want::kError,
                   {"hp_summary.png", "a plot written beside it"}, all_of({unchanged(q), nothing_at(plot_out)})});
  run_table(dir, cases);
}

// A descriptor open for reading, group failures beyond max_failed_fraction,
// a clearance beside a height, unit mistakes in a band and a speed, a
// distribution centred in refused values, temporary-file names as outputs,
// runs still falling at their end, and --resume through a link.
TEST_F(Audit, SixthAuditCases) {
  std::vector<Case> cases;
  const std::string input = w().text_file("input", "keep me\n", "txt");
  cases.push_back({"--csv at a descriptor open for reading", simulate(w().quick()) + " --csv /dev/fd/3 3<" + input,
                   Want::kError, {"--csv '/dev/fd/3'", "open for reading only"}, unchanged(input)});
  cases.push_back({"--csv /dev/stdin", simulate(w().quick()) + " --csv /dev/stdin < " + input, Want::kError,
                   {"--csv '/dev/stdin'", "open for reading only"}, unchanged(input)});
  const auto morris = [&](double mean, double sd) {
    return study("sensitivity", w().sensitivity([&](Json& j) {
      j.erase("model");
      j.erase("bootstrap");
      j["method"] = "morris";
      j["scenario"] = w().quick();
      j["qoi"] = {"B_l_z_min"};
      j["design"] = {{"trajectories", 4}, {"levels", 4}, {"seed", 1}};
      j["parameters"] = {{"c_q", {{"distribution", "normal"}, {"mean", mean}, {"sd", sd}}},
                         {"f", {{"distribution", "uniform"}, {"min", 1e3}, {"max", 1e4}}}};
    }));
  };
  // Levels at the 1/8, 3/8, 5/8 and 7/8 quantiles: the lowest is -0.0075 here,
  // so every trajectory that jumps between it and 5/8 fails.
  cases.push_back({"Morris: the lowest level where the model refuses c_q", morris(0.05, 0.05), Want::kError,
                   {"'max_failed_fraction'", "of the trajectories would draw a value the model refuses", "set up from this design"}});
  // A 3 % tail below 0 that no level reaches: nothing fails.
  cases.push_back({"Morris: a refused tail that no level reaches", morris(0.1, 0.053), Want::kRuns,
                   {"12 runs (0 failed)"}});
  cases.push_back({"initial_q.z beside initial_ground_clearance", simulate(w().scenario([](Json& j) {
                     j["initial_ground_clearance"] = 0.01;
                   })),
                   Want::kError, {"'initial_ground_clearance'", "initial_q.z is given too", "0.281"}});
  cases.push_back({"a settling band in millimetres", study("montecarlo", w().montecarlo([](Json& j) {
                     j["qoi"] = {{{"name", "settling_time"}, {"band", 0.5}}};
                   })),
                   Want::kError, {"'qoi[0].band'", "0.5 m is beyond 0.05 m"}});
  cases.push_back({"a forward speed of 50 m/s", simulate(w().scenario([](Json& j) { j["forward_speed"] = 50; })),
                   Want::kError, {"'forward_speed'", "50 m/s is beyond"}});
  cases.push_back({"c_q centred on negative values", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"]["c_q"] = {{"distribution", "normal"}, {"mean", -1.0}, {"sd", 0.1}};
                   })),
                   Want::kError, {"'c_q': the median of its normal", "-1", "refused by the model"}});
  cases.push_back({"a lognormal whose median overflows", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"]["c_q"] = {{"distribution", "lognormal"}, {"log_mean", 800}, {"log_sd", 0.1}};
                   })),
                   Want::kError, {"'c_q': the median of its lognormal", "no finite number"}, {}, {}, {"null"}});
  cases.push_back({"a normal c_q of sd 1e-20", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"]["c_q"] = {{"distribution", "normal"}, {"mean", 0.1}, {"sd", 1e-20}};
                   })),
                   Want::kError, {"'parameters.c_q", "has sd 1e-20", "use a fixed value"}});
  cases.push_back({"a uniform c_q of relative width 1e-15", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"]["c_q"] = {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.1 * (1 + 1e-15)}};
                   })),
                   Want::kError, {"'parameters.c_q", "not above 1e-12 of its mean's size"}});
  cases.push_back({"calibrate --fit naming a parameter twice",
                   study("calibrate", w().calibration([](Json&) {})) + " --fit c_q,c_q --dry-run", Want::kError,
                   {"--fit: parameter 'c_q' is listed twice"}, {}, {}, {"field 'fit'"}});
  // The shell holds descriptor 3 on a file; rover gets the shell's name for it.
  const std::string shells_file = w().text_file("shell", "", "csv");
  cases.push_back({"--csv at another process's descriptor of a file", simulate(w().quick()) + " --csv /proc/$$/fd/3",
                   Want::kError, {"names another process's descriptor of the file", "give that file's path"},
                   unchanged(shells_file), "exec 3>>" + shells_file + ";"});
  const std::string earlier = w().out();
  cases.push_back({"--csv at another output's temporary name",
                   simulate(w().quick()) + " --csv " + earlier + ".partial", Want::kError,
                   {".partial", "temporary file"}});
  cases.push_back({"t_min of runs still falling at their end", study("montecarlo", w().montecarlo([](Json&) {})),
                   Want::kRuns, {"t_min: 2 of 2 runs reach their lowest B_l z at the run's end"}});
  const std::string linked_out = w().dir() + "/linked.h5";
  fs::create_symlink(w().dir() + "/missing.checkpoint", linked_out + ".checkpoint");
  cases.push_back({"--resume with a dangling link as the checkpoint",
                   study_args("montecarlo", w().montecarlo([](Json&) {}), linked_out) + " --resume", Want::kError,
                   {"--resume: ", "linked.h5.checkpoint is a symbolic link", "--restart"},
                   still_a_link(linked_out + ".checkpoint", w().dir() + "/missing.checkpoint")});
  run_table(w().dir(), cases);
}

// --restart through a dangling link, f below its scale, and --resume
// without a checkpoint.
TEST_F(Audit, SeventhAuditCases) {
  std::vector<Case> cases;
  const std::string restarted = w().dir() + "/restarted.h5";
  fs::create_symlink("/nonexistent-target-dir/ck", restarted + ".checkpoint");
  cases.push_back({"--restart with a dangling link as the checkpoint",
                   study_args("montecarlo", w().montecarlo([](Json&) {}), restarted) + " --restart", Want::kRuns,
                   {"the old checkpoint", "is deleted", "wrote"}});
  cases.push_back({"--f 1e-300", simulate(w().quick()) + " --f 1e-300", Want::kError,
                   {"--f 1e-300 1/rad is below 1 1/rad", "a unit mistake?"}});
  cases.push_back({"an inertia no body can have", simulate(w().scenario_with_rover(w().rover([](Json& j) {
                     j["bodies"]["chassis"]["inertia"] = {{1e-3, 0, 0}, {0, 1e-3, 0}, {0, 0, 5e-3}};
                   }))),
                   Want::kError, {"'bodies.chassis.inertia'", "the largest exceeds the sum of the other two"}});
  cases.push_back({"a rover f of 1e-3", simulate(w().scenario_with_rover(w().rover([](Json& j) {
                     j["s_structure"]["f"] = 1e-3;
                   }))),
                   Want::kError, {"'s_structure.f'", "0.001 1/rad is below 1 1/rad"}});
  cases.push_back({"--resume without a checkpoint", study("montecarlo", w().montecarlo([](Json&) {})) + " --resume",
                   Want::kRuns, {"--resume found no checkpoint"}, {}, {}, {"resuming, 0 of"}});
  // A finished result of another study at --out: --resume has nothing to
  // resume, and must not replace it with a whole new study.
  const std::string finished = w().out();
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " " + study_args("montecarlo", w().montecarlo([](Json&) {}), finished), &log),
            0) << log;
  const std::string finished_bytes = testing::read_file(finished);
  cases.push_back({"--resume without a checkpoint over a finished result",
                   study_args("montecarlo", w().montecarlo([](Json& j) { j["design"]["seed"] = 2; }), finished) +
                       " --resume",
                   Want::kError, {"--resume: there is no checkpoint", finished, "holds a finished result"}, [=] {
                     return testing::read_file(finished) == finished_bytes ? std::string() : "the result was replaced";
                   }});
  run_table(w().dir(), cases);
}

// A fit that does not follow its data, runs in which no wheel touches, and
// surrogates validated on their own training runs or on another scenario's.
TEST_F(Audit, MisfitsUntouchedGroundAndBorrowedRuns) {
  std::vector<Case> cases;
  // Both synthetic drops' first 150 rows (0.3 s at 500 Hz) against a 0.3 s
  // horizontal drop: the skewed drop's curve is not the horizontal one's.
  auto first_rows = [&](const std::string& shipped, const std::string& stem) {
    std::ifstream in(source_path(shipped));
    std::string text;
    int rows = 0;
    for (std::string line; std::getline(in, line) && rows < 151;) {
      text += line + "\n";
      rows += line.starts_with("#") ? 0 : 1;
    }
    return w().text_file(stem, text, "csv");
  };
  const std::string horizontal_0_3s = w().scenario([](Json& j) { j["duration"] = 0.3; });
  auto fit_to = [&](const std::string& data) {
    return study("calibrate", w().calibration([&](Json& j) {
      j["scenario"] = horizontal_0_3s;
      j["data"] = data;
      j["max_evaluations"] = 40;
    }));
  };
  cases.push_back({"a fit to the skewed drop's data on the horizontal drop",
                   fit_to(first_rows("configs/data/drop_skewed_synthetic.csv", "skewed")), Want::kAllFailed,
                   {"NOT VALID", "the residuals are correlated", "lag-1 autocorrelation 0.9"}});
  cases.push_back({"a fit to the horizontal drop's own data",
                   fit_to(first_rows("configs/data/drop_horizontal_synthetic.csv", "horizontal")), Want::kRuns,
                   {"residual lag-1 autocorrelation"}, {}, {}, {"NOT VALID"}});
  // The same for a posterior, and a posterior told a noise sd the residuals contradict.
  auto posterior_of = [&](const std::string& data, const Json& mcmc) {
    return study("calibrate", w().calibration([&](Json& j) {
      j["scenario"] = horizontal_0_3s;
      j["data"] = data;
      j["max_evaluations"] = 40;
      j["method"] = "mcmc";
      j["mcmc"] = mcmc;
    }));
  };
  const Json short_chain = {{"walkers", 8}, {"steps", 6}, {"discard", 0}, {"target_ess", 0}, {"predictive_draws", 0}};
  Json told_too_little = short_chain;
  told_too_little["noise_sd"] = 1e-5;  // the data's noise is 1e-4 m
  cases.push_back({"a posterior of the skewed drop's data on the horizontal drop",
                   posterior_of(first_rows("configs/data/drop_skewed_synthetic.csv", "skewed"), short_chain),
                   Want::kAllFailed, {"posterior is NOT VALID", "the residuals are correlated", "lack_of_fit"}});
  cases.push_back({"a posterior told a tenth of the data's noise sd",
                   posterior_of(first_rows("configs/data/drop_horizontal_synthetic.csv", "horizontal"), told_too_little),
                   Want::kAllFailed, {"posterior is NOT VALID", "the residuals contradict mcmc.noise_sd 1e-05 m"}});
  cases.push_back({"a posterior of the horizontal drop's own data",
                   posterior_of(first_rows("configs/data/drop_horizontal_synthetic.csv", "horizontal"), short_chain),
                   Want::kRunsOrFails, {"residual lag-1 autocorrelation"}, {}, {},
                   {"the residuals are correlated", "the residuals contradict", "lack_of_fit"}});
  const std::string gravity_0 = w().text_file("gravity_0", "gravity\n0\n", "csv");
  cases.push_back({"evaluate without gravity",
                   "evaluate --no-plot --scenario " + horizontal_0_3s + " --design " + gravity_0 + " --out " +
                       w().out("csv") + " --qoi B_l_z_min,max_wheel_load",
                   Want::kRuns, {"WARNING: 1 of 1 runs finished, but no wheel touched the ground: within the run's 0.3 s"}});
  const std::string z_in_mm = w().scenario([](Json& j) { j["initial_q"]["z"] = 281; });
  cases.push_back({"simulate a drop height in millimetres", simulate(z_in_mm), Want::kError,
                   {z_in_mm, "'initial_q'", "lands at 74.2", "a height in millimetres?"}});
  cases.push_back({"a Monte Carlo of max_wheel_load on a drop too short to land",
                   study("montecarlo", w().montecarlo([](Json& j) { j["qoi"] = {"max_wheel_load"}; })), Want::kRuns,
                   {"WARNING: 2 of 2 runs finished, but no wheel touched the ground"}});
  cases.push_back({"a drop that lands", simulate(horizontal_0_3s), Want::kRuns, {"simulate: ok"}, {}, {},
                   {"no wheel touched"}});
  // Surrogates trained on the runs of a Monte Carlo of c_q on the quick drop.
  const Json parameters = {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.3}}}};
  auto runs_of = [&](const std::string& scenario, int samples) {
    const std::string out = w().out();
    std::string log;
    EXPECT_EQ(run_command(rover_binary() + " " + study_args("montecarlo", w().montecarlo([&](Json& j) {
                j["scenario"] = scenario;
                j["parameters"] = parameters;
                j["design"] = {{"type", "latin_hypercube"}, {"samples", samples}, {"seed", samples}};
                j["qoi"] = {"B_l_z_min"};
              }), out), &log), 0) << log;
    return out;
  };
  const std::string trained = runs_of(w().quick(), 12);
  auto surrogate = [&](const std::string& scenario, const std::string& held_out) {
    Json j{{"type", "surrogate"}, {"name", "gp"}, {"surrogate", "gp"}, {"scenario", scenario},
           {"training", {{"file", trained}}}, {"parameters", parameters}, {"qoi", {"B_l_z_min"}}};
    if (!held_out.empty()) j["held_out"] = {{"file", held_out}};
    return study("surrogate", w().json_file("surrogate", j));
  };
  cases.push_back({"held-out runs in the training file itself", surrogate(w().quick(), trained), Want::kError,
                   {"'held_out.file'", "is the training file"}});
  cases.push_back({"held-out runs in a copy of the training file", surrogate(w().quick(), w().copy_of(trained)),
                   Want::kError, {"'held_out.file'", "12 of the 12 held-out runs", "are training runs too"}});
  const std::string shorter = w().scenario([](Json& j) { j["duration"] = 0.04; });
  cases.push_back({"held-out runs of another scenario", surrogate(w().quick(), runs_of(shorter, 4)), Want::kError,
                   {"held-out runs: were made on another scenario", "field 'duration' (0.04 against 0.05)"}});
  cases.push_back({"training runs of another scenario", surrogate(shorter, ""), Want::kError,
                   {"training runs: were made on another scenario", "field 'duration' (0.05 against 0.04)"}});
  // Designs that say nothing new: repeated Morris paths, a surface axis
  // narrower than a double resolves, a truncation far in a tail.
  cases.push_back({"more Morris trajectories than distinct steps", study("sensitivity", w().sensitivity([](Json& j) {
                     j["method"] = "morris";
                     j["design"] = {{"trajectories", 25}, {"levels", 2}, {"seed", 1}};  // Ishigami's 3 inputs
                   })),
                   Want::kError, {"'design.trajectories'", "give each input only 4 distinct steps"}});
  cases.push_back({"a surface axis narrower than a double resolves", study("surface", w().surface([](Json& j) {
                     j["f"] = {{"min", 1000.0}, {"max", 1000.0 * (1 + 1e-15)}, {"count", 3}};
                   })),
                   Want::kError, {"'f.count'", "closer than 1e-12 of their size"}});
  cases.push_back({"a normal truncated 36 sd above its mean",
                   study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"]["c_q"] = {{"distribution", "normal"}, {"mean", 0.14}, {"sd", 0.01},
                                               {"truncate", {0.5, nullptr}}};
                   })) + " --dry-run",
                   Want::kRuns, {"warning: 'c_q': its truncation keeps 4.18e-284", "mistyped"}});
  cases.push_back({"--f 1e400", simulate(w().quick()) + " --f 1e400", Want::kError,
                   {"--f must be a positive finite number, got inf (a number beyond 1.8e308"}});
  const std::string linked = w().dir() + "/linked_rover.h5";
  const std::string rover_copy = w().copy_of(source_path("configs/rover.json"));
  fs::create_hard_link(rover_copy, linked + ".checkpoint");
  cases.push_back({"a hard link of an input at <out>.checkpoint",
                   study_args("montecarlo", w().montecarlo([](Json&) {}), linked), Want::kError,
                   {"is one of several names of a file (a hard link)"}, unchanged(rover_copy),
                   {}, {"finished runs of a study"}});
  run_table(w().dir(), cases);
}

// One writer per result: while a process holds the lock of an --out (here
// the test itself), a study aimed there is refused with or without --resume
// or --restart, and the running study's checkpoint is left alone.
TEST_F(Audit, EighthAuditStudyCases) {
  std::vector<Case> cases;
  const std::string running = w().dir() + "/running.h5";
  write_file(running + ".checkpoint", "ROVERCKP the running study's runs\n");
  const io::OutputLock lock(running);
  for (const std::string flag : {"", " --resume", " --restart", " --dry-run"})
    cases.push_back({"a study aimed at a result being written" + flag,
                     study_args("montecarlo", w().montecarlo([](Json&) {}), running) + flag, Want::kError,
                     {"another rover process is writing " + running}, unchanged(running + ".checkpoint")});
  // Commands that are no study, aimed at a running study's files.
  cases.push_back({"simulate --csv at a study's checkpoint", simulate(w().quick()) + " --csv " + running + ".checkpoint",
                   Want::kError, {"ends in .checkpoint"}, unchanged(running + ".checkpoint")});
  const std::string leftover = w().dir() + "/leftover.h5";
  write_file(leftover + ".checkpoint", "ROVERCKP an interrupted study's runs\n");
  cases.push_back({"synthesize --out at an interrupted study's checkpoint",
                   "synthesize --scenario " + w().quick() + " --out " + leftover + ".checkpoint", Want::kError,
                   {"ends in .checkpoint"}, unchanged(leftover + ".checkpoint")});
  // What stands at <out>.lock: a FIFO (never opened blocking) and a link.
  const std::string fifo_out = w().dir() + "/fifo.h5", link_out = w().dir() + "/link.h5";
  ASSERT_EQ(::mkfifo((fifo_out + ".lock").c_str(), 0644), 0);
  fs::create_symlink(w().dir() + "/elsewhere", link_out + ".lock");
  cases.push_back({"a FIFO at <out>.lock", study_args("montecarlo", w().montecarlo([](Json&) {}), fifo_out),
                   Want::kError, {"is in the way of the result's lock"}});
  cases.push_back({"a symbolic link at <out>.lock", study_args("montecarlo", w().montecarlo([](Json&) {}), link_out),
                   Want::kError, {"is a symbolic link, which no lock file of rover is"}});
  // Training runs that repeat: an evaluate of 4 (c_q, f) rows, each listed three times.
  std::string rows = "c_q,f\n";
  for (int copy = 0; copy < 3; ++copy) rows += "0.12,1500\n0.16,3000\n0.2,6000\n0.28,9000\n";
  const std::string repeated = w().out();
  const std::string landing = w().scenario([](Json& j) { j["duration"] = 0.3; });
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " evaluate --no-plot --scenario " + landing + " --design " +
                            w().text_file("repeated", rows, "csv") + " --qoi B_l_z_min --out " + repeated, &log), 0)
      << log;
  auto gp_on_repeats = [&](const Json& gp) {
    const Json j{{"type", "surrogate"}, {"name", "gp"}, {"surrogate", "gp"}, {"scenario", landing},
                 {"training", {{"file", repeated}}}, {"gp", gp}, {"qoi", {"B_l_z_min"}},
                 {"parameters", {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.3}}},
                                 {"f", {{"distribution", "log_uniform"}, {"min", 1e3}, {"max", 1e4}}}}}};
    return w().json_file("gp", j);
  };
  cases.push_back({"a surrogate trained on repeated runs", study("surrogate", gp_on_repeats(Json::object())),
                   Want::kRuns, {"8 of 12 training runs repeat the inputs of another", "overstates the accuracy"}});
  const std::string unfitted = w().out();
  cases.push_back({"a surrogate study that fits no model",
                   study_args("surrogate", gp_on_repeats({{"nugget", 0.0}}), unfitted), Want::kAllFailed,
                   {"B_l_z_min: no surrogate"}});
  // QoIs whose value is not what their name says: a 0.12 s drop ends mid-compression.
  const std::string cut = w().scenario([](Json& j) { j["duration"] = 0.12; });
  cases.push_back({"at_rest and rebound_peak of a run that ends mid-compression",
                   "evaluate --no-plot --scenario " + cut + " --design " + w().text_file("c_q", "c_q\n0.2\n", "csv") +
                       " --qoi at_rest,rebound_peak --out " + w().out("csv"),
                   Want::kRuns, {"at_rest is no rest height", "rebound_peak is the run's last sample"}});
  cases.push_back({"at_rest of a drop that settles", "evaluate --no-plot --scenario " + source_path("configs/scenarios/drop_horizontal.json") +
                       " --design " + w().text_file("c_q", "c_q\n0.2\n", "csv") + " --qoi at_rest,rebound_peak --out " + w().out("csv"),
                   Want::kRuns, {"1 runs (0 failed)"}, {}, {}, {"no rest height", "had not peaked"}});
  // compare against a curve whose times are in milliseconds: one common sample.
  std::string milliseconds;
  std::istringstream measured(measured_text("\n", 150));
  for (std::string line; std::getline(measured, line);) {
    const std::size_t comma = line.find(',');
    if (line.starts_with("t,")) milliseconds += line + "\n";
    else milliseconds += std::to_string(1000.0 * std::stod(line.substr(0, comma))) + line.substr(comma) + "\n";
  }
  const std::string ms = w().text_file("times_ms", milliseconds, "csv");
  cases.push_back({"compare against a curve in milliseconds", "compare " + ms + " " + simulated_curve(w().dir() + "/run03.h5"),
                   Want::kError, {"only 1 of curve A's samples", "milliseconds"}});
  cases.push_back({"a Monte Carlo of mu_k reaching above mu_s", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"] = {{"friction.mu_k", {{"distribution", "uniform"}, {"min", 0.45}, {"max", 0.6}}}};
                     j["qoi"] = {"B_l_z_min"};
                   })),
                   Want::kRuns, {"WARNING: 2 of 2 runs finished, but the friction law misses its parameters", "mu_k above mu_s"}});
  // A kriged surface checked against a grid made against another reference.
  const std::string grid = w().out();
  ASSERT_EQ(run_command(rover_binary() + " " + study_args("surface", w().surface([](Json& j) {
              j["c_q"] = {{"min", 0.1}, {"max", 0.2}, {"count", 2}};
            }), grid), &log), 0) << log;
  auto kriged_against_grid = [&](double reference_f) {
    return study("surface", w().surface([&](Json& j) {
      j["reference"] = {{"simulate", {{"f", reference_f}, {"c_q", 0.14}}}};
      j["c_q"] = {{"min", 0.1}, {"max", 0.2}, {"count", 2}};
      j["surrogate"] = "gp";
      j["runs"] = 5;
      j["check"] = {{"file", grid}};
    }));
  };
  cases.push_back({"a surface checked against a grid of another reference", kriged_against_grid(2e3), Want::kError,
                   {"'check'", "its runs were made against another reference"}});
  // The quick drop is a free fall: f and c_q leave its maps flat to rounding,
  // which 5 runs cannot tell from a shape they fail to predict.
  cases.push_back({"a surface checked against its own grid", kriged_against_grid(1e4), Want::kNotTrusted,
                   {"against " + grid, "not to be trusted between the runs"}});
  run_table(w().dir(), cases);
  const std::string point = w().text_file("point", "c_q,f\n0.2,2000\n", "csv");
  ASSERT_EQ(run_command(rover_binary() + " surrogate --predict " + unfitted + " --design " + point + " --csv " +
                            w().out("csv"), &log), 1) << log;
  EXPECT_NE(log.find("holds no fitted model"), std::string::npos) << log;
}

// One writer per file for the commands that are no study: while another
// process holds the lock of a file (here the test, as a running study or
// command would), simulate, synthesize, terrain and friction refuse to write
// it, naming the flag, and leave it alone; once the lock is gone they write.
TEST_F(Audit, OneProcessWritersTakeTheLock) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  const std::string study_out = dir + "/running.h5", csv = dir + "/written.csv", json = dir + "/grid.json",
                    png = dir + "/mu.png";
  write_file(study_out, "the running study's earlier result\n");
  const io::OutputLock study_lock(study_out), csv_lock(csv), json_lock(json), png_lock(png);
  cases.push_back({"simulate --out at a running study's result",
                   "simulate --no-plot --scenario " + w().quick() + " --out " + study_out, Want::kError,
                   {"--out '" + study_out + "'", "another rover process is writing"}, unchanged(study_out)});
  cases.push_back({"simulate --csv at a running study's result", simulate(w().quick()) + " --csv " + study_out,
                   Want::kError, {"--csv '" + study_out + "'", "the name of an HDF5 file"}, unchanged(study_out)});
  cases.push_back({"synthesize --out at a file being written",
                   "synthesize --scenario " + w().quick() + " --out " + csv, Want::kError,
                   {"--out '" + csv + "'", "another rover process is writing"}, absent_file(csv)});
  cases.push_back({"terrain obstacle --out at a file being written", "terrain obstacle --out " + json,
                   Want::kError, {"--out '" + json + "'", "another rover process is writing"}, absent_file(json)});
  cases.push_back({"friction --png at a file being written", "friction --png " + png, Want::kError,
                   {"--png '" + png + "'", "another rover process is writing"}, absent_file(png)});
  cases.push_back({"synthesize beside the locks", "synthesize --scenario " + w().quick() + " --out " + dir +
                       "/free.csv", Want::kRuns, {}, [=] {
                     return fs::exists(dir + "/free.csv.lock") ? "its lock file was left behind" : std::string();
                   }});
  run_table(dir, cases);
}

// A joint fit whose second curve's scenario fails every run says which
// curve, which file and which scenario, and why its runs failed.
TEST_F(Audit, JointFitNamesTheCurveWhoseRunsFail) {
  std::vector<Case> cases;
  const std::string failing = w().scenario([](Json& j) { j["wall_time_budget"] = 1e-6; });
  const std::string data = w().dir() + "/quick_data.csv";  // the quick drop's own curve
  // Another curve: the same drop measured again, 10 um higher (a copy is refused as the same curve twice).
  std::istringstream rows(measured_text("\n"));
  std::string again, line;
  std::getline(rows, line);
  again += line + "\n";
  while (std::getline(rows, line)) {
    const std::size_t comma = line.find(',');
    again += line.substr(0, comma + 1) + std::to_string(std::stod(line.substr(comma + 1)) + 1e-5) + "\n";
  }
  const std::string second = w().text_file("second_drop", again, "csv");
  cases.push_back({"a joint fit whose second curve cannot run",
                   study("calibrate", w().calibration([&](Json& j) {
                     j["data"] = {{{"file", data}, {"channel", "B_l_z"}},
                                  {{"file", second}, {"channel", "B_l_z"}, {"scenario", failing}}};
                   })),
                   Want::kAllFailed, {"the run of curve 2 (" + second + " on " + failing + ")", "wall-time budget",
                                      "lag-1 autocorrelation"},
                   {}, {}, {" nan"}});
  run_table(w().dir(), cases);
}

// A fit just inside a bound, whose 95 % interval reaches past it, is not to
// be trusted any more than one on the bound: the bound may hold the value.
// And a curve whose header declares another channel than the one it is
// compared or fitted as is refused.
TEST_F(Audit, IntervalsReachingPastABoundAreNotValid) {
  std::vector<Case> cases;
  auto shipped_fit = [&](double upper) {
    Json j = Json::parse(file_bytes(source_path("configs/studies/calibration.json")), nullptr, true, true);
    j["scenario"] = source_path("configs/scenarios/drop_horizontal.json");
    j["data"] = source_path("configs/data/drop_horizontal_synthetic.csv");
    j["bounds"]["c_q"] = {0.02, upper};
    return study("calibrate", w().json_file("bounded", j));
  };
  cases.push_back({"c_q 0.25 +- 0.001 under a bound of 0.2504", shipped_fit(0.2504), Want::kAllFailed,
                   {"c_q's 95 % interval [", "reaches past its bound 0.2504 (widen bounds.c_q)"}});
  cases.push_back({"c_q 0.25 +- 0.001 well inside its bounds", shipped_fit(1.0), Want::kRuns, {}, {}, {},
                   {"reaches past its bound", "NOT VALID"}});
  // A curve that declares another channel than the one it is compared or fitted as.
  const std::string g_z = w().out("csv");
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " synthesize --scenario " + w().quick() + " --channel G_z --out " + g_z, &log),
            0) << log;
  cases.push_back({"compare a G_z curve as B_l_z", "compare " + g_z + " " + g_z, Want::kError,
                   {"declares its z to be G_z, but --column is B_l_z", "give --column G_z"}});
  cases.push_back({"fit a G_z curve as B_l_z", study("calibrate", w().calibration([&](Json& j) { j["data"] = g_z; })),
                   Want::kError, {g_z + ": declares its z to be G_z", "\"channel\": \"G_z\""}});
  run_table(w().dir(), cases);
}

// A name inside a config means what the system makes of it: "lnk/../x"
// through a linked folder names the x beside the link's target, which is
// then read, and protected as an input.
TEST_F(Audit, NamesInsideConfigsMeanWhatTheSystemMakesOfThem) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  fs::create_directories(dir + "/elsewhere/sub");
  fs::create_directory_symlink(dir + "/elsewhere/sub", dir + "/lnk");
  const std::string shipped = file_bytes(source_path("configs/rover.json"));
  write_file(dir + "/elsewhere/rover.json", shipped);
  write_file(dir + "/rover.json", shipped);
  const std::string scenario = w().scenario_with_rover("lnk/../rover.json");
  cases.push_back({"--csv at the rover a config names through a linked folder",
                   simulate(scenario) + " --csv " + dir + "/elsewhere/rover.json", Want::kError,
                   {"named by 'rover'", "writing it would destroy it"}, unchanged(dir + "/elsewhere/rover.json")});
  fs::create_symlink("loop", dir + "/loop");
  cases.push_back({"--scenario through a link that leads back to itself",
                   "simulate --no-plot --scenario " + dir + "/loop/s.json --out " + w().out(), Want::kError,
                   {"--scenario '" + dir + "/loop/s.json': cannot be reached", "leads back to itself"}});
  run_table(dir, cases);
}

// Synthetic data are a known truth: their integration error stays below a
// tenth of their noise (else a fit recovers the integrator's error, not the
// parameters), whatever integrator was asked for; the header says which ran.
TEST_F(Audit, SyntheticDataOutrunTheirNoise) {
  std::vector<Case> cases;
  const std::string fine = w().out("csv"), coarse = w().out("csv");
  auto header_lacks = [](const std::string& path, const std::string& text) {
    return [=] { return file_bytes(path).find(text) == std::string::npos ? std::string() : path + " says " + text; };
  };
  cases.push_back({"the stiff default against 0.01 mm of noise",
                   "synthesize --scenario " + w().quick() + " --integrator rosenbrock --noise 1e-5 --out " + fine,
                   Want::kRuns, {"errs by up to", "below 1e-06 m (a tenth of the noise sd)", "so they are made with"},
                   header_lacks(fine, "atol 0.0002")});
  cases.push_back({"the stiff default against 1 mm of noise",
                   "synthesize --scenario " + w().quick() + " --integrator rosenbrock --noise 1e-3 --out " + coarse,
                   Want::kRuns, {"wrote"}, header_lacks(coarse, "atol 1e-"), {}, {"so they are made with"}});
  // A release before the data clock by more than the run: no point within it.
  cases.push_back({"synthesize --offset -5 on a 0.05 s run",
                   "synthesize --scenario " + w().quick() + " --offset -5 --out " + w().out("csv"), Want::kError,
                   {"--offset -5 s puts the release before the data clock's start", "give an offset above -0.05 s"},
                   {}, {}, {"raise --rate"}});
  // A failed run is a failed run, as simulate's: status 2, nothing written.
  const std::string unwritten = w().out("csv");
  cases.push_back({"synthesize of a run that fails",
                   "synthesize --scenario " + w().scenario([](Json& j) { j["wall_time_budget"] = 1e-6; }) + " --out " +
                       unwritten,
                   Want::kAllFailed, {"the run failed", "nothing was written"}, absent_file(unwritten)});
  run_table(w().dir(), cases);
}

// A copy of the runs of result `from` (inputs times `input_factor`, QoI
// B_l_z_min, statuses) at `to`, with the scenario and rover configs the
// result records or, as a file of an earlier version, without them.
void copy_runs(const std::string& from, const std::string& to, double input_factor, bool with_configs) {
  const io::Hdf5Reader in(from);
  io::Hdf5Writer out(to);
  out.write("/inputs/names", in.read_strings("/inputs/names"));
  out.write("/inputs/values", Eigen::MatrixXd(input_factor * in.read_matrix("/inputs/values")));
  out.write("/qoi/B_l_z_min", in.read_doubles("/qoi/B_l_z_min"));
  out.write("/samples/status", in.read_ints("/samples/status"));
  for (const char* config : {"scenario_json", "rover_json", "terrain_digest"})
    if (with_configs) out.attribute("/", config, in.attribute_string("/", config));
  out.commit();
}

// Surrogates on runs whose origin or novelty cannot be shown: a training
// file that records no scenario is named in a warning; held-out runs a
// rounding away from training runs are training runs.
TEST_F(Audit, SurrogateRunsOfUnknownOriginOrNoNovelty) {
  std::vector<Case> cases;
  const Json parameters = {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.3}}}};
  const std::string landing = w().scenario([](Json& j) { j["duration"] = 0.3; });
  const std::string trained = w().out();
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " " + study_args("montecarlo", w().montecarlo([&](Json& j) {
              j["scenario"] = landing;
              j["parameters"] = parameters;
              j["design"] = {{"type", "latin_hypercube"}, {"samples", 8}, {"seed", 3}};
              j["qoi"] = {"B_l_z_min"};
            }), trained), &log), 0) << log;
  const std::string dopri_runs = w().out();
  ASSERT_EQ(run_command(rover_binary() + " " + study_args("montecarlo", w().montecarlo([&](Json& j) {
              j["scenario"] = landing;
              j["integrator"] = {{"method", "dopri5"}};
              j["parameters"] = parameters;
              j["design"] = {{"type", "latin_hypercube"}, {"samples", 4}, {"seed", 5}};
              j["qoi"] = {"B_l_z_min"};
            }), dopri_runs), &log), 0) << log;
  auto surrogate = [&](const std::string& training, const std::string& held_out) {
    Json j{{"type", "surrogate"}, {"name", "gp"}, {"surrogate", "gp"}, {"scenario", landing},
           {"training", {{"file", training}}}, {"parameters", parameters}, {"qoi", {"B_l_z_min"}}};
    if (!held_out.empty()) j["held_out"] = {{"file", held_out}};
    return study("surrogate", w().json_file("surrogate", j));
  };
  const std::string older = w().out(), nudged = w().out();
  copy_runs(trained, older, 1.0, /*with_configs=*/false);
  copy_runs(trained, nudged, 1.0 + 1e-9, /*with_configs=*/true);
  cases.push_back({"training runs that record no scenario", surrogate(older, ""), Want::kRuns,
                   {"warning: training runs: " + older + " records no scenario config, rover config, terrain digest",
                    "cannot be checked"}});
  cases.push_back({"training runs that record their scenario", surrogate(trained, ""), Want::kRuns, {}, {}, {},
                   {"records no"}});
  cases.push_back({"held-out runs at the training inputs times 1 + 1e-9", surrogate(trained, nudged), Want::kError,
                   {"'held_out.file'", "8 of the 8 held-out runs", "are training runs too"}});
  // Training runs of one integrator under a study that names another: the
  // result records the integrator that made the runs, and says so.
  const std::string labelled = w().out();
  cases.push_back({"training runs of rosenbrock under a study saying dopri5",
                   study_args("surrogate", w().json_file("surrogate", Json{
                       {"type", "surrogate"}, {"name", "gp"}, {"surrogate", "gp"}, {"scenario", landing},
                       {"integrator", {{"method", "dopri5"}}}, {"training", {{"file", trained}}},
                       {"parameters", parameters}, {"qoi", {"B_l_z_min"}}}), labelled),
                   Want::kRuns, {"the training runs were made with rosenbrock", "not the study's dopri5"}, [=] {
                     const std::string made_with = io::Hdf5Reader(trained).attribute_string("/", "integrator");
                     const std::string recorded = io::Hdf5Reader(labelled).attribute_string("/", "integrator");
                     return recorded == made_with ? std::string() : "the result records " + recorded;
                   }});
  cases.push_back({"held-out runs of dopri5 beside training runs of rosenbrock", surrogate(trained, dopri_runs),
                   Want::kRuns, {"the held-out runs were made with dopri5", "the held-out Q2 includes"}});
  // evaluate --integrator records the integrator it ran, as the studies do.
  const std::string evaluated = w().out();
  ASSERT_EQ(run_command(rover_binary() + " evaluate --no-plot --scenario " + landing + " --integrator dopri5 --design " +
                            w().text_file("held", "c_q\n0.13\n0.19\n0.27\n", "csv") + " --qoi B_l_z_min --out " +
                            evaluated, &log), 0) << log;
  cases.push_back({"held-out runs of evaluate --integrator dopri5", surrogate(trained, evaluated), Want::kRuns,
                   {"the held-out runs were made with dopri5"}});
  run_table(w().dir(), cases);
}

// Runs made on a terrain whose heights changed since (its file rewritten in
// place) are runs of other ground: refused, whatever the file is called;
// the same ground under another file and layout is the same.
TEST_F(Audit, TrainingRunsOnChangedGroundAreRefused) {
  const Json parameters = {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.3}}}};
  const Json grid{{"type", "grid"}, {"origin", {-5.0, -5.0}}, {"spacing", {10.0, 10.0}}, {"counts", {2, 2}},
                  {"heights", {{0.0, 0.0}, {0.0, 0.0}}}};
  const std::string terrain = w().json_file("terrain", grid);
  // A 0.3 s drop (the wheels land), on the terrain named, or on none.
  const auto drop_on = [&](const std::string& terrain_path) {
    return w().scenario([&](Json& j) {
      j["duration"] = 0.3;
      if (terrain_path.empty()) j.erase("terrain");
      else j["terrain"] = terrain_path;
    });
  };
  const std::string landing = drop_on(terrain);
  const std::string trained = w().out();
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " " + study_args("montecarlo", w().montecarlo([&](Json& j) {
              j["scenario"] = landing;
              j["parameters"] = parameters;
              j["design"] = {{"type", "latin_hypercube"}, {"samples", 6}, {"seed", 3}};
              j["qoi"] = {"B_l_z_min"};
            }), trained), &log), 0) << log;
  auto surrogate = [&](const std::string& scenario) {
    return study("surrogate", w().json_file("surrogate", Json{{"type", "surrogate"}, {"name", "gp"},
                                                             {"surrogate", "gp"}, {"scenario", scenario},
                                                             {"training", {{"file", trained}}},
                                                             {"parameters", parameters}, {"qoi", {"B_l_z_min"}}}));
  };
  const std::string same_ground = w().text_file("terrain_relaid", grid.dump(4));
  std::vector<Case> cases;
  cases.push_back({"training runs on the same terrain file", surrogate(landing), Want::kRuns, {}, {}, {},
                   {"another terrain", "records no"}});
  cases.push_back({"training runs on the same ground in another file",
                   surrogate(drop_on(same_ground)), Want::kRuns, {}, {}, {},
                   {"another terrain"}});
  cases.push_back({"training runs on flat ground named by no terrain",
                   surrogate(drop_on("")), Want::kRuns, {}, {}, {},
                   {"another terrain"}});
  run_table(w().dir(), cases);

  Json raised = grid;
  raised["heights"][1][1] = 1e-4;  // one node 0.1 mm higher
  std::ofstream(terrain, std::ios::trunc) << raised.dump(1);
  cases = {{"training runs on a terrain file changed since", surrogate(landing), Want::kError,
            {"training runs: were made on another terrain than the study's (" + terrain + ")",
             "changed since the runs"}}};
  cases.push_back({"training runs on another terrain's ground",
                   surrogate(drop_on(w().json_file("terrain", Json{{"type", "flat"}, {"height", 0.01}}))),
                   Want::kError, {"were made on another terrain"}});
  run_table(w().dir(), cases);
}

// How many elementary-effect steps of a Morris result repeat an earlier one
// (the same input between the same two points), read from its /inputs/values.
std::string repeated_morris_steps(const std::string& results) {
  const Eigen::MatrixXd x = io::Hdf5Reader(results).read_matrix("/inputs/values");
  const Eigen::Index d = x.cols(), trajectories = x.rows() / (d + 1);
  std::set<std::vector<double>> seen;
  int repeats = 0;
  for (Eigen::Index t = 0; t < trajectories; ++t)
    for (Eigen::Index k = 0; k < d; ++k) {
      const Eigen::VectorXd a = x.row(t * (d + 1) + k), b = x.row(t * (d + 1) + k + 1);
      std::vector<double> step;
      for (Eigen::Index i = 0; i < d; ++i) step.push_back(a[i] != b[i] ? -1.0 - static_cast<double>(i) : a[i]);
      for (Eigen::Index i = 0; i < d; ++i) step.push_back(std::min(a[i], b[i]));
      repeats += !seen.insert(step).second;
    }
  return repeats == 0 ? "" : results + ": " + std::to_string(repeats) + " repeated elementary-effect steps";
}

// A curve recorded at 60 kHz for 0.1 s with its times in milliseconds: 4 of
// its 6001 samples lie within the quick drop's 0.05 s.
std::string curve_in_milliseconds() {
  std::string text = "t,z\n";
  for (int k = 0; k <= 6000; ++k) {
    const double t_s = k / 60000.0;
    text += std::to_string(1000.0 * t_s) + "," + std::to_string(0.281 - 0.5 * 9.81 * t_s * t_s) + "\n";
  }
  return text;
}

TEST_F(Audit, NinthAuditCases) {
  std::vector<Case> cases;
  // Morris steps: Ishigami's 3 inputs on 2 levels have 4 steps each; 4 trajectories take every one once.
  const std::string morris_out = w().out();
  auto morris = [&](int trajectories) {
    return w().sensitivity([&](Json& j) {
      j["method"] = "morris";
      j["design"] = {{"trajectories", trajectories}, {"levels", 2}, {"seed", 1}};
    });
  };
  cases.push_back({"Morris trajectories as many as the distinct steps", study_args("sensitivity", morris(4), morris_out),
                   Want::kRuns, {"Morris, 4 trajectories"}, [morris_out] { return repeated_morris_steps(morris_out); }});
  cases.push_back({"one Morris trajectory more than the distinct steps", study("sensitivity", morris(5)), Want::kError,
                   {"'design.trajectories'", "(value 5)", "give each input only 4 distinct steps",
                    "at most 4 trajectories"}});
  // A curve in milliseconds recorded fast enough to put 3 samples in the run.
  const std::string ms = w().text_file("ms_60k", curve_in_milliseconds(), "csv");
  cases.push_back({"compare against a 60 kHz curve in milliseconds",
                   "compare " + ms + " " + simulated_curve(w().dir() + "/run9.h5"), Want::kError,
                   {"curve A ('" + ms + "')", "only 0.05 % of its time span", "t runs to 100, milliseconds?"}});
  cases.push_back({"a study reference of 60 kHz in milliseconds", study("montecarlo", w().montecarlo([&](Json& j) {
                     j["qoi"] = {{{"name", "rms_vs"}, {"reference", ms}}};
                   })),
                   Want::kError, {"'qoi[0].reference'", "only 0.05 % of its time span", "milliseconds?"}});
  cases.push_back({"a surface reference of 60 kHz in milliseconds", study("surface", w().surface([&](Json& j) {
                     j["reference"] = {{"file", ms}};
                   })),
                   Want::kError, {"'reference.file'", "only 0.05 % of its time span", "milliseconds?"}});
  // A median the model refuses, on a key the scenario does not set.
  cases.push_back({"a distribution whose median the model refuses", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"] = {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}},
                                        {"scenario.initial_u.z", {{"distribution", "uniform"}, {"min", -2000}, {"max", 0}}}};
                   })),
                   Want::kError,
                   {"'scenario.initial_u.z' at -1000, the median of its uniform", "z = -1000 m/s is beyond +-10 m/s"},
                   {}, {}, {"cannot vary alone", "'c_q'"}});
  // Notes of two kinds: the quick drop never lands, and mu_k above mu_s misses the friction law.
  cases.push_back({"runs with two kinds of note", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"] = {{"friction.mu_k", {{"distribution", "uniform"}, {"min", 0.45}, {"max", 0.6}}}};
                   })),
                   Want::kRuns,
                   {"WARNING: 2 of 2 runs finished, but the friction law misses its parameters: Makkar fit RMS",
                    "WARNING: 2 of 2 runs finished, but no wheel touched the ground: within the run's 0.05 s"}});
  // The chassis turning faster than the rover's size allows.
  for (const std::string rate : {"theta", "chi", "psi"})
    cases.push_back({"initial_u." + rate + " 110 rad/s", simulate(w().scenario([&](Json& j) {
                       j["initial_u"] = {{rate, 110.0}};
                     })),
                     Want::kError, {"'initial_u'", rate + " = 110 rad/s is beyond +-", "the rover's farthest point"}});
  cases.push_back({"a wheel spinning at 110 rad/s", simulate(w().scenario([](Json& j) { j["initial_u"] = {{"z1", 110.0}}; })),
                   Want::kRuns, {"simulate: ok"}});
  cases.push_back({"an eom state of a chassis at 110 rad/s",
                   "eom --state " + w().json_file("state_chi", Json{{"q", std::vector<double>(23, 0.0)},
                                                                    {"u", [] {
                                                                       std::vector<double> u(23, 0.0);
                                                                       u[4] = 110.0;
                                                                       return u;
                                                                     }()}}),
                   Want::kError, {"'u'", "entry 4 (chi) = 110 rad/s is beyond", "the rover's farthest point"}});
  cases.push_back({"a turn radius whose yaw rate is beyond the scale",
                   simulate(w().drive_scenario({{"segments", {{{"mode", "car"}, {"speed", 0.3}, {"radius", 1e-3}}}}})),
                   Want::kError, {"'drive.segments[0].radius'", "gives a yaw rate beyond the rover's scale: 300 rad/s is beyond"},
                   {}, {}, {"gives a yaw rate of"}});
  run_table(w().dir(), cases);
}

// A candidate's "set" values the model refuses are blamed on the candidates
// file, scales below the rover's are unit mistakes, a CSV is no result of
// runs, and a signal while an input pipe waits for its writer ends with 130.
TEST_F(Audit, TenthAuditLeftovers) {
  std::vector<Case> cases;
  const std::string buried = w().json_file(
      "buried", Json{{"candidates",
                      {{{"scenario", w().quick()}, {"rate_hz", 1000}, {"noise_sd", 1e-4},
                        {"set", {{"scenario.initial_q.z", 0.1}}}}}}});
  cases.push_back({"a candidate set into the ground",
                   study("calibrate", w().calibration([](Json&) {})) + " --dry-run --next-experiment " + buried,
                   Want::kError, {buried + ": field 'candidates[0].set'", "the model refuses the scenario", "below the ground"}});
  auto rover_case = [&](const std::string& id, const std::function<void(Json&)>& edit,
                        std::vector<std::string> mentions) {
    const std::string path = w().rover(edit);
    mentions.insert(mentions.begin(), path);
    cases.push_back({id, simulate(w().scenario_with_rover(path)), Want::kError, mentions});
  };
  rover_case("a chassis in tonnes", [](Json& j) { j["bodies"]["chassis"]["mass"] = 0.001267; },
             {"'bodies.chassis.mass'", "0.001267 kg is below 0.01 kg", "tonnes?"});
  rover_case("a wheel radius in kilometres", [](Json& j) { j["geometry"]["wheel_radius"] = 8.5e-5; },
             {"'geometry.wheel_radius'", "8.5e-05 m is below 0.001 m", "kilometres"});
  rover_case("Stribeck speeds of 1e-300 m/s", [](Json& j) {
    j["friction"]["v_s"] = 1e-300;
    j["friction"]["v_k"] = 2e-300;
  }, {"'friction.v_s'", "1e-300 m/s is below 1e-06 m/s", "km/s"});
  cases.push_back({"rover friction --v-s 1e-9", "friction --v-s 1e-9 --v-k 1e-8", Want::kError,
                   {"--v-s 1e-09 m/s is below 1e-06 m/s", "--v-k 1e-08 m/s is below"}});
  const Json parameters = {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.3}}}};
  const std::string csv_runs = w().text_file("runs", "c_q,B_l_z_min\n0.1,0.16\n0.2,0.17\n", "csv");
  cases.push_back({"a CSV as a surrogate's training file",
                   study("surrogate", w().json_file("csv_training", Json{{"type", "surrogate"}, {"name", "gp"},
                                                                         {"surrogate", "gp"}, {"scenario", w().quick()},
                                                                         {"training", {{"file", csv_runs}}},
                                                                         {"parameters", parameters},
                                                                         {"qoi", {"B_l_z_min"}}})),
                   Want::kError, {"'training.file'", csv_runs + " is not an HDF5 file", "rover montecarlo, evaluate"}});
  // The quick drop ends before any wheel lands: its curve says nothing of c_q.
  cases.push_back({"a fit of a curve before any contact", study("calibrate", w().calibration([](Json&) {})),
                   Want::kAllFailed, {"c_q = 0.1, no interval (not identifiable from these data)", "none"}, {}, {},
                   {"inf", "nan"}});
  cases.push_back({"5 cm of noise on a 1 cm fall",
                   "synthesize --scenario " + w().quick() + " --noise 0.05 --out " + w().out("csv"), Want::kRuns,
                   {"--noise 0.05 m is larger than the curve's own travel", "millimetres?"}});
  // Degenerate studies: nothing varied; a kriged map that cannot predict its own runs.
  cases.push_back({"a Monte Carlo whose only parameter is fixed", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"] = {{"c_q", {{"distribution", "fixed"}, {"value", 0.2}}}};
                   })),
                   Want::kError, {"'parameters'", "every parameter is fixed"}});
  Json kriged = Json::parse(file_bytes(source_path("configs/studies/surface_gp.json")), nullptr, true, true);
  kriged["scenario"] = source_path("configs/scenarios/drop_horizontal.json");
  kriged["reference"]["file"] = source_path("configs/data/drop_horizontal_synthetic.csv");
  kriged["runs"] = 5;
  kriged.erase("check");
  cases.push_back({"a kriged surface of 5 runs", study("surface", w().json_file("kriged5", kriged)),
                   Want::kNotTrusted,
                   {"WARNING: rms's process predicts its own left-out runs with Q2", "below 0.95", "exit status 2"}});
  // Messages that say what was given.
  const std::string run = simulated_curve(w().dir() + "/tenth_curve.h5");
  for (const std::string column : {"Fn", "pitch", "t"})
    cases.push_back({"compare --column " + column, "compare " + run + " " + run + " --column " + column, Want::kError,
                     {"--column " + column + " is ", "not a height"}});
  cases.push_back({"rover friction --config a scenario", "friction --config " + w().quick(), Want::kError,
                   {w().quick(), "field 'rover'", "a scenario file", "not a rover file"}});
  cases.push_back({"synthesize --noise 1e-20", "synthesize --scenario " + w().quick() + " --noise 1e-20 --out " +
                                                   w().out("csv"),
                   Want::kRuns, {"the tightest the integrators are measured to reach", "would be 1e-21 m"}, {}, {},
                   {"(a tenth of the noise sd)"}});
  run_table(w().dir(), cases);
}

// Impacts beyond the rover: a drop from 100 m is refused before the run; a
// landing inside the speed bound whose wheels still give way is noted, by
// simulate and in a study's count of runs.
TEST_F(Audit, ImpactsBeyondTheContactModel) {
  std::vector<Case> cases;
  const std::string high = w().scenario([](Json& j) { j["initial_q"] = {{"z", 100.0}}; });
  cases.push_back({"a drop from 100 m", simulate(high), Want::kError,
                   {high, "'initial_q'", "lands at 44.2", "beyond +-10 m/s", "go through the ground"}});
  auto landing_at = [&](double speed_mps) {
    return w().scenario([&](Json& j) {
      j["duration"] = 0.12;
      j["initial_u"] = {{"z", speed_mps}};
    });
  };
  const std::string hard = landing_at(-9.5), soft = landing_at(-0.5);
  cases.push_back({"a landing at 9.5 m/s", simulate(hard), Want::kRuns,
                   {"warning: the chassis went through the ground: its origin G reached"}});
  cases.push_back({"a landing at 0.5 m/s", simulate(soft), Want::kRuns, {}, {}, {}, {"through the ground"}});
  cases.push_back({"a study of landings at 9.5 m/s", study("montecarlo", w().montecarlo([&](Json& j) {
                     j["scenario"] = hard;
                   })),
                   Want::kRuns, {"runs finished, but the chassis went through the ground"}});
  run_table(w().dir(), cases);
}

// A file no program may replace (chattr +i, +a) at an output path is
// refused before the run by what it is, not after it at the rename.
TEST_F(Audit, ImmutableAndAppendOnlyOutputs) {
  for (const std::string attribute : {"i", "a"}) {
    const std::string out = w().out();
    write_file(out, "an earlier result");
    if (run_command("chattr +" + attribute + " " + out + " 2>/dev/null") != 0)
      GTEST_SKIP() << "chattr does not work here (needs root and a file system with attributes)";
    std::string log;
    const int status = run_command(rover_binary() + " simulate --no-plot --scenario " + w().quick() + " --out " + out, &log);
    run_command("chattr -" + attribute + " " + out);
    EXPECT_EQ(status, 1) << log;
    EXPECT_NE(log.find(attribute == "i" ? "is immutable" : "is append-only"), std::string::npos) << log;
    EXPECT_EQ(log.find("chmod"), std::string::npos) << log;
    EXPECT_EQ(file_bytes(out), "an earlier result");
  }
}

// An input that is a pipe (a FIFO, /dev/fd/N of `<(...)`, a device) is
// refused before it is opened: rover reads an input more than once (every MPI
// rank, the fingerprint), and opening a pipe waits for its writer.
TEST_F(Audit, InputPipesRefusedUnopened) {
  const std::string dir = w().dir(), pipe = dir + "/unwritten.csv", out = dir + "/piped.h5";
  ASSERT_EQ(run_command("mkfifo " + pipe), 0);
  const std::string json_pipe = dir + "/scenario_pipe.json";
  ASSERT_EQ(run_command("mkfifo " + json_pipe), 0);
  const std::string named_pipe = w().montecarlo([&](Json& j) { j["scenario"] = json_pipe; });
  std::vector<Case> cases;
  cases.push_back({"--data a FIFO", study_args("calibrate", w().calibration([](Json&) {}), out) + " --data " + pipe,
                   Want::kError, {pipe + ": is a pipe, not a CSV file", "save it to a file"}, absent_file(out)});
  cases.push_back({"a scenario FIFO named in a study", study_args("montecarlo", named_pipe, out), Want::kError,
                   {"field 'scenario'", "is a pipe, not a JSON file"}, absent_file(out)});
  cases.push_back({"--study /dev/null", study_args("montecarlo", "/dev/null", out), Want::kError,
                   {"/dev/null", "is a device"}, absent_file(out)});
  run_table(dir, cases);

  std::string output;
  const int status = run_command("cd " + dir + " && OMPI_MCA_ess_singleton_isolated=1 timeout -k 2 30 bash -c '" +
                                     rover_binary() + " montecarlo --no-plot --out " + out + " --study <(cat " +
                                     w().montecarlo([](Json&) {}) + ")'",
                                 &output);
  EXPECT_EQ(status, 1) << output;
  EXPECT_NE(output.find("/dev/fd/"), std::string::npos) << output;
  EXPECT_NE(output.find("is a pipe, not a JSON file"), std::string::npos) << output;
}

// A 0.3 s horizontal drop (it lands) and its synthetic B_l z curve at
// c_q = 0.25 (0.1 mm noise, or `noise`), for the calibration cases below.
struct LandingDrop {
  std::string scenario, data;
};
LandingDrop landing_drop(Workshop& w, const std::string& noise = "") {
  LandingDrop d{w.scenario([](Json& j) { j["duration"] = 0.3; }), w.out("csv")};
  std::string log;
  EXPECT_EQ(run_command(rover_binary() + " synthesize --scenario " + d.scenario + " --cq 0.25 " +
                            (noise.empty() ? "" : "--noise " + noise + " ") + "--out " + d.data, &log),
            0) << log;
  return d;
}

// A fit of c_q to `drop` within [0.02, c_q_upper].
std::string landing_fit(Workshop& w, const LandingDrop& drop, double c_q_upper) {
  return w.calibration([&](Json& j) {
    j["scenario"] = drop.scenario;
    j["data"] = drop.data;
    j["bounds"]["c_q"] = {0.02, c_q_upper};
    j["max_evaluations"] = 40;
  });
}

// An aftermath: /next_experiment of `path` has ranking_valid = `valid`.
std::function<std::string()> ranking_valid_is(const std::string& path, long long valid) {
  return [=] {
    if (!fs::exists(path)) return path + " was not written";
    const io::Hdf5Reader h5(path);
    if (!h5.has_attribute("/next_experiment", "ranking_valid")) return path + " has no ranking_valid";
    const long long got = h5.attribute_integer("/next_experiment", "ranking_valid");
    return got == valid ? std::string() : path + ": ranking_valid " + std::to_string(got);
  };
}

// A ranking computed at a fit the fit alone calls NOT VALID (c_q held by its
// bound 0.2, truth 0.25) says so, is written flagged and exits 2, as the fit
// does, alone and under mpirun; at a trusted fit it ranks with status 0. A
// ranking of nothing (its one candidate's run fails) leaves an earlier file
// at --out as it was.
TEST_F(Audit, NextExperimentAtAFitNotToBeTrusted) {
  std::vector<Case> cases;
  const LandingDrop drop = landing_drop(w());
  const std::string candidates = w().json_file(
      "candidates", Json{{"candidates", {{{"name", "repeat"}, {"scenario", drop.scenario}, {"rate_hz", 500},
                                          {"noise_sd", 1e-4}}}}});
  const std::string bounded = landing_fit(w(), drop, 0.2), free = landing_fit(w(), drop, 1.0);
  const std::string flagged = w().out(), ranked = w().out();
  cases.push_back({"next experiment at a fit held by its bound",
                   study_args("calibrate", bounded, flagged) + " --next-experiment " + candidates, Want::kAllFailed,
                   {"WARNING: the ranking below is NOT VALID: the fit it is computed at is NOT VALID",
                    "c_q = 0.2 is on its bound", "ranking_valid = 0"},
                   ranking_valid_is(flagged, 0)});
  cases.push_back({"next experiment at a trusted fit",
                   study_args("calibrate", free, ranked) + " --next-experiment " + candidates, Want::kRuns,
                   {"ranked by the expected 95 % half-width"}, ranking_valid_is(ranked, 1), {}, {"NOT VALID"}});
  const std::string failing = w().json_file(
      "failing", Json{{"candidates", {{{"name", "fail"},
                                       {"scenario", w().scenario([](Json& j) {
                                          j["duration"] = 0.3;
                                          j["wall_time_budget"] = 1e-6;
                                        })},
                                       {"rate_hz", 500},
                                       {"noise_sd", 1e-4}}}}});
  const std::string earlier = w().out();
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " simulate --no-plot --scenario " + w().quick() + " --out " + earlier, &log),
            0) << log;
  cases.push_back({"next experiment whose one candidate fails, over an earlier file",
                   study_args("calibrate", free, earlier) + " --next-experiment " + failing, Want::kAllFailed,
                   {"no ranking: the candidate 'fail' could not be simulated", "nothing was written, " + earlier +
                    " is unchanged"},
                   unchanged(earlier), {}, {"wrote " + earlier}});
  run_table(w().dir(), cases);
  // Under mpirun: rank 0 decides; one warning, status 2.
  const std::string mpi_out = w().out();
  const int status = run_command("timeout -k 5 120 " + testing::mpiexec() + " -np 2 " + rover_binary() + " " +
                                     study_args("calibrate", bounded, mpi_out) + " --next-experiment " + candidates +
                                     " 2>&1",
                                 &log);
  EXPECT_EQ(status, 2) << log;
  const std::string warning = "WARNING: the ranking below is NOT VALID";
  ASSERT_NE(log.find(warning), std::string::npos) << log;
  EXPECT_EQ(log.find(warning, log.find(warning) + 1), std::string::npos) << "printed twice:\n" << log;
  EXPECT_TRUE(ranking_valid_is(mpi_out, 0)().empty()) << log;
}

// A posterior told a noise sd 100 times the data's (1e-2 m against 1e-4 m) is
// NOT VALID, naming mcmc.noise_sd, its value and the residual RMS: its
// intervals are far too wide. On noise-free data the integration check ends
// on the reference integrator and says it cannot be checked against a
// tighter one; it never reports a setting's shift against itself.
TEST_F(Audit, NoiseFarAboveTheResidualsAndTheReferenceUnchecked) {
  std::vector<Case> cases;
  const LandingDrop drop = landing_drop(w());
  const std::string told_too_much = w().calibration([&](Json& j) {
    j["scenario"] = drop.scenario;
    j["data"] = drop.data;
    j["max_evaluations"] = 40;
    j["method"] = "mcmc";
    j["mcmc"] = {{"walkers", 8}, {"steps", 6}, {"discard", 0}, {"target_ess", 0}, {"predictive_draws", 0},
                 {"noise_sd", 1e-2}};
  });
  cases.push_back({"a posterior told 100 times the data's noise sd", study("calibrate", told_too_much),
                   Want::kAllFailed,
                   {"posterior is NOT VALID", "the residuals contradict mcmc.noise_sd 0.01 m from below",
                    "residual RMS", "too wide"}});
  const LandingDrop exact = landing_drop(w(), "0");
  cases.push_back({"a fit to noise-free data", study("calibrate", landing_fit(w(), exact, 1.0)), Want::kRunsOrFails,
                   {"integration check: the fit runs on the reference integrator (dopri5",
                    "there is no tighter one to check it against"},
                   {}, {}, {"against dopri5 at rtol 1e-08, atol 1e-11): shifts"}});
  run_table(w().dir(), cases);
}

// A curve whose header declares its channel (as rover synthesize writes it,
// and as every shipped curve does) is refused wherever it is read as another
// channel: a study's rms_vs reference, a surface's reference file, compare,
// a calibration's data.
TEST_F(Audit, CurvesAreReadAsTheChannelTheyDeclare) {
  for (const auto& entry : fs::directory_iterator(source_path("configs/data"))) {
    if (entry.path().extension() != ".csv") continue;
    EXPECT_NE(io::declared_channel(entry.path().string()), "") << entry.path() << " declares no channel";
  }
  std::vector<Case> cases;
  const std::string g_z = w().out("csv");
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " synthesize --scenario " + w().quick() + " --channel G_z --out " + g_z, &log),
            0) << log;
  auto rms_vs = [&](const Json& qoi) { return w().montecarlo([&](Json& j) { j["qoi"] = {qoi}; }); };
  cases.push_back({"a G_z curve as an rms_vs reference of B_l z",
                   study("montecarlo", rms_vs({{"name", "rms_vs"}, {"reference", g_z}})), Want::kError,
                   {"'qoi[0].reference'", g_z + ": declares its z to be G_z (its header), but rms_vs compares B_l_z",
                    "give \"channel\": \"G_z\" in qoi[0]"}});
  cases.push_back({"a G_z curve as an rms_vs reference of G_z",
                   study("montecarlo", rms_vs({{"name", "rms_vs"}, {"reference", g_z}, {"channel", "G_z"}})),
                   Want::kRuns, {}, {}, {}, {"declares its z"}});
  cases.push_back({"a G_z curve as a surface's reference",
                   study("surface", w().surface([&](Json& j) { j["reference"] = {{"file", g_z}}; })), Want::kError,
                   {"'reference.file'", g_z + ": declares its z to be G_z (its header), but is read as B_l_z",
                    "give a curve of B_l_z"}});
  const std::string shipped = source_path("configs/data/drop_horizontal_synthetic.csv");
  cases.push_back({"the shipped B_l z curve compared as G_z",
                   "compare " + simulated_curve(w().dir() + "/quick_run.h5") + " " + shipped + " --column G_z",
                   Want::kError, {"declares its z to be B_l_z, but --column is G_z"}});
  cases.push_back({"the shipped skewed B_l z curve fitted as G_z",
                   study("calibrate", w().calibration([&](Json& j) {
                     j["data"] = {{{"file", source_path("configs/data/drop_skewed_synthetic.csv")}, {"channel", "G_z"}}};
                   })) + " --dry-run",
                   Want::kError, {"declares its z to be B_l_z", "\"channel\": \"B_l_z\""}});
  run_table(w().dir(), cases);
}

// A file at <out>.checkpoint that does not begin as a checkpoint (the
// command's own data, or any file rover never wrote) is never offered for
// removal nor removed, not even by --restart: "give another --out".
TEST_F(Audit, FilesThatAreNoCheckpointAreNeverRemoved) {
  std::vector<Case> cases;
  const std::string dir = w().dir(), fit = dir + "/fit.h5", data = fit + ".checkpoint";
  std::ofstream(data) << measured_text("\n");
  const std::string calibration = w().calibration([&](Json& j) { j["data"] = data; });
  for (const std::string flags : {"", " --restart"})
    cases.push_back({"a calibration's data at <out>.checkpoint" + flags, study_args("calibrate", calibration, fit) + flags,
                     Want::kError, {data}, unchanged(data), {}, {"--restart removes", "discard them"}});
  const std::string runs = dir + "/runs.h5", foreign = runs + ".checkpoint";
  write_file(foreign, "a user's notes\n");
  for (const std::string flags : {"", " --restart"})
    cases.push_back({"a file of the user's at <out>.checkpoint" + flags,
                     study_args("montecarlo", w().montecarlo([](Json&) {}), runs) + flags, Want::kError,
                     {foreign + " is no checkpoint of rover", "give another --out"}, unchanged(foreign), {},
                     {"--restart removes"}});
  run_table(dir, cases);
}

// Two runs: a bootstrap of the sd gives [0, s], which cannot hold it. Below
// the bootstrap's minimum the sd's interval is the chi-square one of normal
// values, which holds the estimate, and the report and the file say so.
TEST_F(Audit, SmallMonteCarloSdIntervalsHoldTheSd) {
  const std::string out = w().dir() + "/two.h5";
  const std::string mc = w().montecarlo([](Json& j) {
    j["parameters"] = {{"scenario.initial_q.z", {{"distribution", "uniform"}, {"min", 0.28}, {"max", 0.3}}}};
    j["qoi"] = {"B_l_z_min"};
  });
  const auto sd_interval = [out] {
    const io::Hdf5Reader h5(out);
    const std::vector<double> sd = h5.read_doubles("/summary/B_l_z_min/sd");
    if (!(sd.at(1) > 0.0 && sd.at(1) < sd.at(0) && sd.at(0) < sd.at(2)))
      return "the sd's interval [" + std::to_string(sd.at(1)) + ", " + std::to_string(sd.at(2)) + "] misses " +
             std::to_string(sd.at(0));
    if (h5.attribute_string("/summary/B_l_z_min/sd", "columns").find("chi-square") == std::string::npos)
      return std::string("/sd does not name its chi-square interval");
    return std::string();
  };
  run_table(w().dir(), {{"montecarlo of 2 runs", study_args("montecarlo", mc, out), Want::kRuns,
                         {"the sd's interval is the chi-square one of normal values, as the mean's Student t is",
                          "2 runs are too few for a bootstrap of the sd (it needs 30)"},
                         sd_interval}});
}

// What a study can know before its runs it checks before them: a held-out
// file without a QoI or an input the surrogate needs, a "compare" file
// without the indices compared, and gnuplot on PATH for the figures asked
// for. Nothing is run, no checkpoint left.
TEST_F(Audit, FilesAndThePlotterAreCheckedBeforeAnyRun) {
  const std::string dir = w().dir(), runs = dir + "/held.h5";
  std::string log;
  ASSERT_EQ(run_command("cd " + dir + " && " + rover_binary() + " " +
                            study_args("montecarlo", w().montecarlo([](Json& j) { j["design"]["samples"] = 3; }), runs),
                        &log),
            0) << log;  // c_q, QoI t_min
  const Json c_q = {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}}};
  auto surrogate = [&](const Json& qoi, const Json& inputs, const std::string& key, const Json& value) {
    Json j{{"type", "surrogate"}, {"name", "sg"}, {"scenario", w().quick()}, {"parameters", inputs}, {"qoi", qoi},
           {"design", {{"type", "latin_hypercube"}, {"samples", 8}, {"seed", 1}}}};
    j[key] = value;
    return w().json_file("sg", j);
  };
  std::vector<Case> cases;
  const std::string no_qoi = dir + "/no_qoi.h5", no_input = dir + "/no_input.h5", no_indices = dir + "/no_indices.h5";
  cases.push_back({"a held-out file without the QoI",
                   study_args("surrogate", surrogate({"B_l_z_min"}, c_q, "held_out", {{"file", runs}}), no_qoi),
                   Want::kError, {"'held_out.file'", runs + ": held-out runs: no QoI 'B_l_z_min'"},
                   all_of({absent_file(no_qoi + ".checkpoint"), absent_file(no_qoi)})});
  const Json f_and_c_q = {{"f", {{"distribution", "log_uniform"}, {"min", 1e3}, {"max", 1e4}}},
                          {"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}}};
  cases.push_back({"a held-out file without an input",
                   study_args("surrogate", surrogate({"t_min"}, f_and_c_q, "held_out", {{"file", runs}}), no_input),
                   Want::kError, {"'held_out.file'", runs + ": held-out runs: no input 'f'"},
                   all_of({absent_file(no_input + ".checkpoint"), absent_file(no_input)})});
  cases.push_back({"a compare file without indices",
                   study_args("surrogate", surrogate({"t_min"}, c_q, "compare", {{"file", runs}}), no_indices),
                   Want::kError, {"'compare.file'", runs + " has no total indices of t_min over the study's inputs (c_q)"},
                   all_of({absent_file(no_indices + ".checkpoint"), absent_file(no_indices)})});
  // A PATH with `timeout` and no gnuplot.
  const std::string bin = dir + "/bin";
  fs::create_directory(bin);
  std::string timeout;
  ASSERT_EQ(run_command("command -v timeout", &timeout), 0) << timeout;
  timeout.erase(timeout.find_last_not_of(" \n") + 1);
  fs::create_symlink(timeout, bin + "/timeout");
  const std::string no_gnuplot = "PATH=" + bin;
  const std::string unplotted = dir + "/unplotted.h5", simulated = dir + "/simulated.h5";
  cases.push_back({"a study's figures without gnuplot",
                   "montecarlo --study " + w().montecarlo([](Json&) {}) + " --out " + unplotted, Want::kError,
                   {"no gnuplot on PATH (" + bin + ")", "--no-plot"}, all_of({absent_file(unplotted + ".checkpoint"),
                                                                      absent_file(unplotted)}),
                   no_gnuplot});
  cases.push_back({"simulate's plot without gnuplot", "simulate --scenario " + w().quick() + " --out " + simulated,
                   Want::kError, {"no gnuplot on PATH (" + bin + ")", "--no-plot"}, absent_file(simulated), no_gnuplot});
  cases.push_back({"friction --png without gnuplot", "friction --png " + dir + "/mu.png", Want::kError,
                   {"--png needs gnuplot", "no gnuplot on PATH", "give no --png"}, absent_file(dir + "/mu.png"), no_gnuplot});
  cases.push_back({"a study without figures needs no gnuplot",
                   study_args("montecarlo", w().montecarlo([](Json&) {}), dir + "/no_figures.h5"), Want::kRuns, {},
                   {}, no_gnuplot});
  run_table(dir, cases);
}

// Runs `rover <args>` in `dir` in the background (log in `log`), waits until
// the shell condition `ready` holds and `settle_s` more, sends SIGTERM (or
// SIG`signal`) and waits for the end; the output ends with "status N" and the log, and holds
// "still running" if rover outlived the signal by kSignalGrace_s (`timeout`,
// which forwards the signal, then kills it).
constexpr int kSignalGrace_s = 8;
std::string signalled_run(const std::string& dir, const std::string& args, const std::string& log,
                          const std::string& ready, double settle_s = 0.0, const std::string& signal = "TERM") {
  std::string output;
  run_command("cd " + dir + " && (OMPI_MCA_ess_singleton_isolated=1 timeout -k " + std::to_string(kSignalGrace_s + 2) +
                  " 60 " + rover_binary() + " " + args +
                  " > " + log + " 2>&1 & pid=$!; for i in $(seq 3000); do " + ready +
                  " && break; sleep 0.01; done; sleep " + std::to_string(settle_s) + "; kill -" + signal + " $pid; for i in $(seq " +
                  std::to_string(10 * kSignalGrace_s) +
                  "); do kill -0 $pid 2>/dev/null || break; sleep 0.1; done; "
                  "kill -0 $pid 2>/dev/null && echo 'still running after the grace'; wait $pid; echo \"status $?\"; cat " +
                  log + ")",
              &output);
  return output;
}
std::string log_holds(const std::string& log, const std::string& line) { return "grep -q '" + line + "' " + log; }
std::string file_exists(const std::string& path) { return "test -e " + path; }

// What an interrupted command must show: status 130, a word, no result, no
// temporary and no lock; with `checkpoint_kept`, the checkpoint and the
// --resume line (a study that finished no run may write no checkpoint).
void expect_clean_interrupt(const std::string& output, const std::string& out, bool checkpoint_kept) {
  EXPECT_EQ(output.find("still running"), std::string::npos) << output;
  EXPECT_NE(output.find("status 130"), std::string::npos) << output;
  EXPECT_NE(output.find("interrupted"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(out)) << output;
  EXPECT_FALSE(fs::exists(out + ".partial")) << output;
  EXPECT_FALSE(fs::exists(out + ".lock")) << output;
  if (!checkpoint_kept) return;
  EXPECT_TRUE(fs::exists(out + ".checkpoint")) << output;
  EXPECT_NE(output.find("--resume"), std::string::npos) << output;
}

// Class 4: a signal in the analysis after the runs (a bootstrap of minutes)
// ends the study at once; the checkpoint holds every run for --resume.
TEST_F(Audit, ASignalEndsTheBootstrapAfterTheRuns) {
  const std::string dir = w().dir();
  const std::string sobol = w().sensitivity([](Json& j) {
    j["design"]["samples"] = 16384;
    j["bootstrap"] = 100000;
  });
  const std::string sobol_out = dir + "/boot_sobol.h5";
  const std::string sobol_log = dir + "/boot_sobol.log";
  expect_clean_interrupt(
      signalled_run(dir, study_args("sensitivity", sobol, sobol_out), sobol_log, log_holds(sobol_log, "done (0 failed) in")),
      sobol_out, true);
  const std::string mc = w().montecarlo([](Json& j) {
    j.erase("scenario");
    j["model"] = "ishigami";
    j.erase("parameters");
    j.erase("qoi");
    j["design"]["samples"] = 100000;
    j["bootstrap"] = 100000;
  });
  const std::string mc_out = dir + "/boot_mc.h5";
  const std::string mc_log = dir + "/boot_mc.log";
  expect_clean_interrupt(
      signalled_run(dir, study_args("montecarlo", mc, mc_out), mc_log, log_holds(mc_log, "done (0 failed) in")), mc_out,
      true);
}

// Class 4: a signal ends the run in progress at its next step, not when it
// is done; the run is not recorded (--resume computes it), never as failed.
TEST_F(Audit, ASignalEndsTheRunInProgress) {
  const std::string dir = w().dir();
  const std::string slow = w().scenario([](Json& j) {
    j["duration"] = 60.0;
    j["integrator"] = {{"method", "dopri5"}, {"rtol", 1e-9}, {"atol", 1e-12}};
  });
  const std::string design = w().text_file("slow_design", "c_q\n0.14\n", "csv");
  const std::string out = dir + "/slow.h5";
  // The lock is taken just before the run; a second later the run is under way.
  const std::string output = signalled_run(
      dir, "evaluate --scenario " + slow + " --design " + design + " --out " + out + " --qoi t_min",
      dir + "/slow.log", file_exists(out + ".lock"), 1.0);
  expect_clean_interrupt(output, out, false);
  // No run finished: nothing is saved, and no checkpoint is claimed.
  EXPECT_NE(output.find("none of the 1 runs had finished, so nothing is saved"), std::string::npos) << output;
  EXPECT_NE(output.find("Run the same command again"), std::string::npos) << output;
  EXPECT_EQ(output.find("0 of 1 runs"), std::string::npos) << output;
  EXPECT_EQ(output.find("1 failed"), std::string::npos) << output;
}

// Class 4: a calibration's NLopt global search of many evaluations is one
// task; a signal ends it at its next evaluation.
TEST_F(Audit, ASignalEndsAGlobalSearch) {
  const std::string dir = w().dir();
  const std::string calibration = w().calibration([](Json& j) { j["max_evaluations"] = 100000; });
  const std::string out = dir + "/direct.h5";
  const std::string output = signalled_run(dir, study_args("calibrate", calibration, out) + " --algorithm GN_DIRECT_L",
                                           dir + "/direct.log", file_exists(out + ".lock"), 1.0);
  expect_clean_interrupt(output, out, false);
  EXPECT_NE(output.find("none of the 1 runs had finished"), std::string::npos) << output;
}

// Class 4: `surrogate --predict` interrupted while it writes its table: 130,
// a word, nothing written, neither temporary nor lock left.
TEST_F(Audit, ASignalEndsAPredictionWithNothingWritten) {
  const std::string dir = w().dir();
  const std::string study = w().json_file(
      "sg", Json{{"type", "surrogate"}, {"surrogate", "pce"}, {"name", "sg"}, {"model", "ishigami"},
                 {"design", {{"type", "lhs"}, {"samples", 100}, {"seed", 1}}}, {"pce", {{"max_degree", 10}}}});
  const std::string model = dir + "/sg.h5";
  std::string output;
  ASSERT_EQ(run_command("cd " + dir + " && OMPI_MCA_ess_singleton_isolated=1 " + rover_binary() + " " +
                            study_args("surrogate", study, model),
                        &output),
            0)
      << output;
  const std::string design = dir + "/many_points.csv";
  ASSERT_EQ(run_command("awk 'BEGIN { print \"x1,x2,x3\"; for (i = 0; i < 800000; ++i) "
                        "printf \"%.6f,%.6f,%.6f\\n\", -3 + 6 * (i % 997) / 997, -3 + 6 * (i % 991) / 991, "
                        "-3 + 6 * (i % 983) / 983 }' > " + design),
            0);
  const std::string out = dir + "/many_predictions.csv";
  output = signalled_run(dir, "surrogate --predict " + model + " --design " + design + " --csv " + out,
                         dir + "/predict.log", file_exists(out + ".partial"));
  expect_clean_interrupt(output, out, false);
  EXPECT_NE(output.find("nothing written"), std::string::npos) << output;
}

// A degree-1 PCE of the linear test model in x1, trained: its study file
// and its model file (for --predict).
struct LinearSurrogate {
  std::string study, model;
};
LinearSurrogate linear_surrogate(Workshop& w) {
  LinearSurrogate out;
  out.study = w.json_file(
      "linear_surrogate", Json{{"type", "surrogate"},
                               {"name", "lin"},
                               {"model", "linear"},
                               {"parameters", {{"x1", {{"distribution", "uniform"}, {"min", 0.0}, {"max", 1.0}}}}},
                               {"design", {{"samples", 20}, {"seed", 1}}},
                               {"pce", {{"max_degree", 1}, {"bootstrap", 0}}}});
  out.model = w.out();
  std::string log;
  EXPECT_EQ(run_command(rover_binary() + " surrogate --no-plot --study " + out.study + " --out " + out.model, &log), 0)
      << log;
  return out;
}

// A next-experiment noise sd below what the likelihood resolves, integrator
// keys the method does not use, --profile with --next-experiment and a buried
// eom state are refused by name; a prediction's CSV never replaces a file the
// surrogate was trained on; a posterior that starts from a fit held by its
// bound says so; an interrupt before any run finished claims no saved runs.
TEST_F(Audit, EleventhAuditLeftovers) {
  std::vector<Case> cases;
  const LandingDrop drop = landing_drop(w());
  const std::string bounded = landing_fit(w(), drop, 0.2);
  const std::string tiny_noise = w().json_file(
      "tiny_noise", Json{{"candidates", {{{"scenario", drop.scenario}, {"rate_hz", 500}, {"noise_sd", 1e-13}}}}});
  cases.push_back({"a candidate's noise sd of 1e-13 m",
                   study("calibrate", bounded) + " --dry-run --next-experiment " + tiny_noise, Want::kError,
                   {tiny_noise, "'candidates[0].noise_sd'", "1e-13 m, outside the noise sds from 1e-12 to 1000 m"}});
  const std::string good = w().json_file(
      "good", Json{{"candidates", {{{"scenario", drop.scenario}, {"rate_hz", 500}, {"noise_sd", 1e-4}}}}});
  cases.push_back({"--profile with --next-experiment",
                   study("calibrate", bounded) + " --dry-run --profile --next-experiment " + good, Want::kError,
                   {"--profile", "computes no profile likelihoods"}});
  cases.push_back({"slip_tol on dopri5",
                   simulate(w().scenario([](Json& j) { j["integrator"] = {{"method", "dopri5"}, {"slip_tol", 0.01}}; })),
                   Want::kError, {"'integrator.slip_tol'", "only rosenbrock and rodas4 use slip_tol"}});
  cases.push_back({"rtol on rk4",
                   simulate(w().scenario([](Json& j) {
                     j["integrator"] = {{"method", "rk4"}, {"fixed_step", 1e-4}, {"rtol", 1e-8}};
                   })),
                   Want::kError, {"'integrator.rtol'", "rk4 takes fixed steps"}});
  std::vector<double> buried(23, 0.0);
  buried[2] = -5.0;
  cases.push_back({"eom: wheels 5 m in the ground",
                   "eom --state " + w().json_file("buried", Json{{"q", buried}, {"u", std::vector<double>(23, 0.0)}}),
                   Want::kError, {"field 'q'", "m deep in the ground, more than its radius 0.085 m"}});
  const std::string posterior = w().calibration([&](Json& j) {
    j["scenario"] = drop.scenario;
    j["data"] = drop.data;
    j["bounds"]["c_q"] = {0.02, 0.2};
    j["max_evaluations"] = 40;
    j["method"] = "mcmc";
    j["mcmc"] = {{"walkers", 8}, {"steps", 4}, {"discard", 0}, {"target_ess", 0}, {"predictive_draws", 0},
                 {"noise_sd", 1e-4}};
  });
  const std::string posterior_out = w().out();
  cases.push_back({"a posterior starting at a fit on its bound", study_args("calibrate", posterior, posterior_out),
                   Want::kRunsOrFails,
                   {"the least-squares fit the chains started from would be NOT VALID on its own",
                    "c_q = 0.2 is on its bound"},
                   [=] {
                     const io::Hdf5Reader h5(posterior_out);
                     const std::string flaw = h5.attribute_string("/posterior", "start_fit_flaw");
                     return flaw.find("on its bound") != std::string::npos ? std::string()
                                                                           : "start_fit_flaw '" + flaw + "'";
                   }});
  const LinearSurrogate linear = linear_surrogate(w());
  const std::string &study_file = linear.study, &trained = linear.model;
  cases.push_back({"--predict --csv over the study file the surrogate was trained on",
                   "surrogate --predict " + trained + " --design " +
                       w().text_file("design", "x1,x2,x3,x4\n0.5,0,0,0\n", "csv") + " --csv " + study_file,
                   Want::kError, {"--csv", "the attribute study_file of --predict", "writing it would destroy it"},
                   unchanged(study_file)});
  run_table(w().dir(), cases);
}

// Calibration inputs: a byte-order mark does not hide a curve's declared
// channel; a time-offset bound reached by the offset scan's last point is a
// bound, not an internal error; a curve listed twice, a candidate setting a
// fitted parameter and an atol below round-off are refused; a posterior
// whose fit's every run failed exits 2, as the fit does.
TEST_F(Audit, TwelfthAuditCalibrationInputs) {
  std::vector<Case> cases;
  const LandingDrop drop = landing_drop(w());
  std::string log;
  const std::string g_z = w().out("csv");
  ASSERT_EQ(run_command(rover_binary() + " synthesize --scenario " + drop.scenario + " --channel G_z --cq 0.25 --out " +
                            g_z, &log), 0) << log;
  std::ifstream g_z_file(g_z, std::ios::binary);
  const std::string g_z_text((std::istreambuf_iterator<char>(g_z_file)), std::istreambuf_iterator<char>());
  const std::string marked = w().text_file("marked", "\xEF\xBB\xBF" + g_z_text, "csv");
  cases.push_back({"a G_z curve behind a byte-order mark, fitted as B_l_z",
                   study("calibrate", w().calibration([&](Json& j) {
                     j["scenario"] = drop.scenario;
                     j["data"] = marked;
                   })) + " --dry-run",
                   Want::kError, {marked, "declares its z to be G_z"}});
  cases.push_back({"a time-offset bound the scan ends on (upper 0.04 s, offset 0.05 s)",
                   study("calibrate", w().calibration([&](Json& j) {
                     j["scenario"] = drop.scenario;
                     j["data"] = drop.data;
                     j["bounds"]["time_offset"] = {-0.2, 0.04};
                     j["max_evaluations"] = 40;
                   })),
                   Want::kAllFailed, {"time_offset = 0.04 is on its bound (widen bounds.time_offset)"},
                   {}, {}, {"levenberg_marquardt: parameter"}});
  cases.push_back({"the same curve listed twice",
                   study("calibrate", w().calibration([&](Json& j) {
                     j["scenario"] = drop.scenario;
                     j["data"] = Json::array({{{"file", drop.data}}, {{"file", drop.data}}});
                   })) + " --dry-run",
                   Want::kError, {"'data[1].file'", "the same file as data[0]", "sqrt(2)"}});
  const std::string sets_c_q = w().json_file(
      "sets_c_q", Json{{"candidates", {{{"scenario", drop.scenario}, {"rate_hz", 500}, {"noise_sd", 1e-4},
                                        {"set", {{"c_q", 0.5}}}}}}});
  cases.push_back({"a candidate setting the fitted c_q",
                   study("calibrate", landing_fit(w(), drop, 1.0)) + " --dry-run --next-experiment " + sets_c_q,
                   Want::kError, {"'candidates[0].set.c_q'", "'c_q' is fitted by the study"}});
  cases.push_back({"atol 1e-300",
                   simulate(w().scenario([](Json& j) { j["integrator"] = {{"method", "dopri5"}, {"atol", 1e-300}}; })),
                   Want::kError, {"'integrator.atol'", "1e-300", "[1e-18, 0.01]"}});
  const std::string failing = w().scenario([](Json& j) { j["wall_time_budget"] = 1e-6; });
  cases.push_back({"a posterior whose fit's every run failed",
                   study("calibrate", w().calibration([&](Json& j) {
                     j["scenario"] = failing;
                     j["method"] = "mcmc";
                     j["mcmc"] = {{"walkers", 8}, {"steps", 4}, {"discard", 0}, {"target_ess", 0},
                                  {"predictive_draws", 0}, {"noise_sd", 1e-4}};
                   })),
                   Want::kAllFailed, {"no posterior: every one of the fit's", "every run failed"}});
  const std::string twins = w().json_file(
      "twins", Json{{"candidates", {{{"name", "drop"}, {"scenario", drop.scenario}, {"rate_hz", 500}, {"noise_sd", 1e-4}},
                                    {{"name", "drop"}, {"scenario", drop.scenario}, {"rate_hz", 1000}, {"noise_sd", 1e-4}}}}});
  cases.push_back({"two candidates of one name",
                   study("calibrate", landing_fit(w(), drop, 1.0)) + " --dry-run --next-experiment " + twins,
                   Want::kError, {"'candidates[1].name'", "candidates[0] has this name too"}});
  cases.push_back({"--plots all with --no-plot",
                   "montecarlo --study " + w().montecarlo([](Json&) {}) + " --out " + w().out() +
                       " --plots all --no-plot --dry-run",
                   Want::kError, {"--plots cannot be given together with --no-plot"}});
  run_table(w().dir(), cases);
}

// ---- The twelfth audit -------------------------------------------------------

// Class 4 (P5): a config nested thousands of levels deep is refused at once,
// naming the file, line and column and the limit, wherever the nesting is
// (not after memory growing with the square of the depth).
TEST_F(Audit, DeeplyNestedJsonIsRefusedAtOnce) {
  std::vector<Case> cases;
  const std::string deep_array = std::string(3000, '[') + std::string(3000, ']');
  const std::string bare = w().text_file("deep", deep_array);
  cases.push_back({"a study file of 3000 nested arrays", study("montecarlo", bare) + " --dry-run", Want::kError,
                   {bare + ":1:101: ", "nested deeper than 100 levels"}});
  std::string described = w().montecarlo([](Json&) {});
  const std::string study_text = file_bytes(described);
  described = w().text_file("deep_description",
                            "{\n\"description\": " + deep_array + "," + study_text.substr(study_text.find('{') + 1));
  cases.push_back({"a study whose description nests 3000 arrays", study("montecarlo", described) + " --dry-run",
                   Want::kError, {described + ":2:115: ", "nested deeper than 100 levels"}});
  std::string objects;
  for (int i = 0; i < 2000; ++i) objects += "{\"a\": ";
  objects += "1" + std::string(2000, '}');
  const std::string scenario = w().text_file("deep_scenario", objects);
  cases.push_back({"a scenario of 2000 nested objects", simulate(scenario), Want::kError,
                   {scenario + ":1:", "nested deeper than 100 levels"}});
  run_table(w().dir(), cases);
}

// Class 8 (P11): an HDF5 input that another program holds open for writing
// (HDF5's file locking, here flock(1) holding the same exclusive lock while
// rover runs) is said to be locked, not damaged; every HDF5 reader.
TEST_F(Audit, AnInputHeldOpenForWritingIsLockedNotDamaged) {
  const std::string dir = w().dir();
  const std::string curve = simulated_curve(dir + "/curve.h5");
  const LinearSurrogate linear = linear_surrogate(w());
  const std::string& model = linear.model;
  std::string log;
  const std::string design = w().text_file("design", "x1,x2,x3,x4\n0.5,0,0,0\n", "csv");
  struct Reader {
    std::string id, held, args;
  };
  const std::vector<Reader> readers = {
      {"compare, the curve judged", curve, "compare " + curve + " " + simulated_curve(dir + "/other.h5")},
      {"compare, the reference", curve, "compare " + simulated_curve(dir + "/judged.h5") + " " + curve},
      {"surrogate --predict", model, "surrogate --predict " + model + " --design " + design + " --csv " + w().out("csv")},
  };
  for (const Reader& r : readers) {
    std::string output;
    const int status = run_command("cd " + dir + " && OMPI_MCA_ess_singleton_isolated=1 flock -x " + r.held +
                                       " timeout -k 2 30 " + rover_binary() + " " + r.args,
                                   &output);
    SCOPED_TRACE(r.id + ": rover " + r.args + "\n" + output);
    EXPECT_EQ(status, 1);
    EXPECT_NE(output.find(r.held + " is locked by another program that has it open for writing"), std::string::npos);
    EXPECT_NE(output.find("close it there"), std::string::npos);
    EXPECT_EQ(output.find("damaged"), std::string::npos);
  }
}

// Class 4/2 (P4): a one-process command signalled while it writes its files
// ends with 130 and says what was written and what not; no temporary and no
// lock stays, and an earlier file at an unwritten path is left as it was.
TEST_F(Audit, ASignalWhileACommandWritesLeavesNoPartialFile) {
  const std::string dir = w().dir();
  // 0.5 s of a drop at 200 kHz: 100 000 rows, written in about a second.
  const std::string dense = w().scenario([](Json& j) {
    j["duration"] = 0.5;
    j["output_rate"] = 2e5;
  });
  const auto earlier = [](const std::string& path) {
    std::ofstream(path) << "an earlier result";
    return unchanged(path);
  };
  const auto no_leftovers = [](const std::string& output, const std::string& path) {
    EXPECT_FALSE(fs::exists(path + ".partial")) << output;
    EXPECT_FALSE(fs::exists(path + ".lock")) << output;
  };
  {  // while the HDF5 file is written: nothing written
    const std::string out = dir + "/dense.h5", csv = dir + "/dense.csv";
    const auto kept = earlier(out);
    const std::string output = signalled_run(dir, "simulate --no-plot --scenario " + dense + " --out " + out +
                                                      " --csv " + csv, dir + "/dense.log", file_exists(out + ".partial"));
    EXPECT_NE(output.find("status 130"), std::string::npos) << output;
    EXPECT_NE(output.find("interrupted (SIGTERM) while writing " + out + "; nothing written"), std::string::npos)
        << output;
    EXPECT_EQ(kept(), "") << output;
    EXPECT_FALSE(fs::exists(csv)) << output;
    no_leftovers(output, out);
    no_leftovers(output, csv);
  }
  {  // while the CSV is written, by SIGHUP: the HDF5 file stands, the CSV is not written
    const std::string out = dir + "/dense2.h5", csv = dir + "/dense2.csv";
    const auto kept = earlier(csv);
    const std::string output =
        signalled_run(dir, "simulate --no-plot --scenario " + dense + " --out " + out + " --csv " + csv,
                      dir + "/dense2.log", file_exists(csv + ".partial"), 0.0, "HUP");
    EXPECT_NE(output.find("status 130"), std::string::npos) << output;
    EXPECT_NE(output.find("interrupted (SIGHUP) while writing " + csv + "; wrote " + out + "; not written: " + csv),
              std::string::npos)
        << output;
    EXPECT_EQ(kept(), "") << output;
    EXPECT_EQ(io::Hdf5Reader(out).shape("/t"), (std::vector<std::size_t>{100001})) << output;
    no_leftovers(output, out);
    no_leftovers(output, csv);
  }
  {  // synthesize's curve: 0.3 s at 2 MHz, 600 000 rows
    const std::string out = dir + "/curve.csv";
    const auto kept = earlier(out);
    const std::string output = signalled_run(
        dir, "synthesize --scenario " + w().scenario([](Json& j) { j["duration"] = 0.3; }) + " --rate 2e6 --out " + out,
        dir + "/curve.log", file_exists(out + ".partial"));
    EXPECT_NE(output.find("status 130"), std::string::npos) << output;
    EXPECT_NE(output.find("interrupted (SIGTERM) while writing " + out + "; nothing written"), std::string::npos)
        << output;
    EXPECT_EQ(kept(), "") << output;
    no_leftovers(output, out);
  }
}

// Class 4 (P14): SIGHUP (a closed terminal or ssh session) stops a study as
// SIGTERM does, with its checkpoint and --resume line; progress into a pipe
// whose reader has gone (`| head`) stops it
// the same way (at its start if the banner already met the closed pipe)
// instead of killing it without a word.
TEST_F(Audit, HangupAndAClosedPipeStopAStudyWithItsCheckpoint) {
  const std::string dir = w().dir();
  const std::string many = w().montecarlo([](Json& j) { j["design"]["samples"] = 100000; });
  const std::string out = dir + "/hangup.h5";
  const std::string output = signalled_run(dir, study_args("montecarlo", many, out), dir + "/hangup.log",
                                           file_exists(out + ".lock"), 1.0, "HUP");
  expect_clean_interrupt(output, out, true);
  EXPECT_NE(output.find("interrupted (SIGHUP)"), std::string::npos) << output;

  const std::string piped = dir + "/piped.h5", status_file = dir + "/piped.status";
  std::string pipe_output;
  run_command("cd " + dir + " && { OMPI_MCA_ess_singleton_isolated=1 timeout -k 2 60 " + rover_binary() + " " +
                  study_args("montecarlo", many, piped) + " --progress-interval 1 2>&1; echo \"status $?\" > " +
                  status_file + "; } | head -c 1",
              &pipe_output);
  const std::string piped_status = file_bytes(status_file);
  EXPECT_EQ(piped_status, "status 130\n") << pipe_output;
  EXPECT_FALSE(fs::exists(piped)) << piped_status;
  EXPECT_FALSE(fs::exists(piped + ".partial")) << piped_status;
  EXPECT_FALSE(fs::exists(piped + ".lock")) << piped_status;
}

// Sets element `index` (row-major) of the double dataset `dataset` of the
// HDF5 file `path`, in place, as an editor of the file would.
void set_dataset_element(const std::string& path, const std::string& dataset, std::size_t index, double value) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0) << path;
  const hid_t set = H5Dopen2(file, dataset.c_str(), H5P_DEFAULT);
  ASSERT_GE(set, 0) << dataset;
  const hid_t space = H5Dget_space(set);
  std::vector<double> values(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  ASSERT_LT(index, values.size()) << dataset;
  ASSERT_GE(H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  values[index] = value;
  ASSERT_GE(H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  H5Sclose(space);
  H5Dclose(set);
  H5Fclose(file);
}

// Replaces the numeric attribute `name` of `object` in the HDF5 file `path`
// by a double of `value`, in place.
void set_attribute_number(const std::string& path, const std::string& object, const std::string& name, double value) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0) << path;
  ASSERT_GE(H5Adelete_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT), 0) << object << " " << name;
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attribute =
      H5Acreate_by_name(file, object.c_str(), name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(attribute, 0) << object << " " << name;
  ASSERT_GE(H5Awrite(attribute, H5T_NATIVE_DOUBLE, &value), 0);
  H5Aclose(attribute);
  H5Sclose(space);
  H5Fclose(file);
}

// Class 8/7: `surrogate --predict` checks every number of the model file it
// reads: multi-indices whole numbers from 0 to the degree, coefficients and
// the Gaussian process's arrays finite and of consistent shapes, its
// length-scales positive. An edited file is refused naming the file and the
// dataset, never crashes, allocates polynomials of degree 1e9 or predicts NaN.
TEST_F(Audit, ASurrogateFileIsCheckedBeforeItPredicts) {
  const std::string dir = w().dir();
  auto trained = [&](const std::string& kind) {
    Json j{{"type", "surrogate"}, {"surrogate", kind}, {"name", kind}, {"model", "ishigami"},
           {"design", {{"type", "lhs"}, {"samples", 100}, {"seed", 1}}}};
    if (kind == "pce") j["pce"] = {{"max_degree", 10}, {"bootstrap", 0}};
    else j["gp"] = {{"q2_threshold", 0.5}};  // 100 runs krige Ishigami to Q2 0.8 only
    const std::string model = dir + "/" + kind + ".h5";
    std::string output;
    EXPECT_EQ(run_command("cd " + dir + " && OMPI_MCA_ess_singleton_isolated=1 " + rover_binary() + " " +
                              study_args("surrogate", w().json_file(kind, j), model),
                          &output),
              0)
        << output;
    return model;
  };
  const std::string pce = trained("pce"), gp = trained("gp");
  const std::string design = w().text_file("points", "x1,x2,x3\n0.5,0.5,0.5\n", "csv");
  std::vector<Case> cases;
  auto edited = [&](const std::string& id, const std::string& model, const std::string& dataset, std::size_t index,
                    double value, std::vector<std::string> mentions) {
    const std::string copy = w().copy_of(model);
    set_dataset_element(copy, dataset, index, value);
    mentions.insert(mentions.begin(), {copy, "not a model written by `rover surrogate --study`, or edited", dataset});
    const std::string out = w().out("csv");
    cases.push_back({id, "surrogate --predict " + copy + " --design " + design + " --csv " + out, Want::kError,
                     mentions, absent_file(out)});
  };
  const std::string alpha = "/surrogate/models/y/multi_indices";
  edited("a multi-index of 1e30", pce, alpha, 1, 1e30, {"1e+30", "whole number from 0 to the expansion's degree"});
  edited("a multi-index above the degree", pce, alpha, 1, 21.0, {"holds 21", "the expansion's degree"});
  edited("a multi-index of -1", pce, alpha, 1, -1.0, {"holds -1"});
  edited("a multi-index of 2.5", pce, alpha, 1, 2.5, {"holds 2.5"});
  edited("a NaN coefficient", pce, "/surrogate/models/y/coefficients", 0, std::nan(""), {"nan", "finite"});
  edited("an infinite support", pce, "/surrogate/inputs/support", 1, HUGE_VAL, {"inf"});
  edited("a negative length-scale", gp, "/surrogate/models/y/length_scales", 0, -1.0, {"holds -1", "above 0"});
  edited("an infinite training point", gp, "/surrogate/models/y/scaled_inputs", 3, HUGE_VAL, {"inf"});
  edited("a NaN weight", gp, "/surrogate/models/y/weights", 0, std::nan(""), {"nan"});
  edited("a zero on the Cholesky diagonal", gp, "/surrogate/models/y/correlation_cholesky", 0, 0.0,
         {"its diagonal", "above 0"});
  auto attribute = [&](const std::string& id, const std::string& model, const std::string& object,
                       const std::string& name, double value, std::vector<std::string> mentions) {
    const std::string copy = w().copy_of(model);
    set_attribute_number(copy, object, name, value);
    mentions.insert(mentions.begin(), {copy, "or edited", object + " attribute " + name});
    cases.push_back({id, "surrogate --predict " + copy + " --design " + design + " --csv " + w().out("csv"),
                     Want::kError, mentions});
  };
  attribute("a degree of 1e9", pce, "/surrogate/models/y", "degree", 1e9, {"whole number from 0 to 20"});
  attribute("a NaN process variance", gp, "/surrogate/models/y", "process_variance", std::nan(""), {"nan"});
  attribute("a NaN Q2 threshold", gp, "/surrogate", "q2_threshold", std::nan(""), {"nan"});
  cases.push_back({"the unedited model predicts", "surrogate --predict " + pce + " --design " + design + " --csv " +
                                                       w().out("csv"),
                   Want::kRuns, {}});
  cases.push_back({"the unedited process predicts", "surrogate --predict " + gp + " --design " + design + " --csv " +
                                                         w().out("csv"),
                   Want::kRuns, {}});
  run_table(dir, cases);
}

// Class 2/7/8: a QoI's "label" names an HDF5 dataset, figure files and CSV
// columns, and a next-experiment candidate's "name" is shown and saved: both
// are refused before any run unless they are plain names, naming the field.
TEST_F(Audit, ResultLabelsArePlainNames) {
  std::vector<Case> cases;
  auto label_case = [&](const std::string& id, const std::string& label, std::vector<std::string> mentions) {
    const std::string path = w().montecarlo([&](Json& j) { j["qoi"] = {{{"name", "t_min"}, {"label", label}}}; });
    mentions.insert(mentions.begin(), {path, "'qoi[0].label'"});
    cases.push_back({id, study("montecarlo", path) + " --dry-run", Want::kError, mentions});
  };
  label_case("a label with '/'", "a/b", {"'a/b' holds '/'"});
  label_case("an empty label", "", {"is empty", "1 to 64 characters"});
  label_case("a label climbing out", "..x", {"holds \"..\""});
  label_case("a label of 250 characters", std::string(250, 'q'), {"has 250 characters"});
  label_case("a label with a control character", "a\x01" "b", {"'a\\x01b' holds a control character"});
  label_case("a label with a comma", "a,b", {"holds ','"});
  cases.push_back({"a plain label with spaces and brackets",
                   study("montecarlo", w().montecarlo([&](Json& j) {
                     j["qoi"] = {{{"name", "t_min"}, {"label", "t min (s) [drop 1]"}}};
                   })) + " --dry-run",
                   Want::kRuns, {}});
  auto candidate_case = [&](const std::string& id, const std::string& name, std::vector<std::string> mentions) {
    const std::string candidates = w().json_file(
        "candidates",
        Json{{"candidates", {{{"name", name}, {"scenario", w().quick()}, {"rate_hz", 500}, {"noise_sd", 1e-4}}}}});
    mentions.insert(mentions.begin(), {candidates, "'candidates[0].name'"});
    cases.push_back({id, study("calibrate", w().calibration([](Json&) {})) + " --dry-run --next-experiment " + candidates,
                     Want::kError, mentions});
  };
  candidate_case("a candidate named with a bell", "drop\x07", {"'drop\\x07' holds a control character"});
  candidate_case("an empty candidate name", "", {"is empty"});
  candidate_case("a candidate name of 300 characters", std::string(300, 'c'), {"has 300 characters"});
  run_table(w().dir(), cases);
}

// Class 5: a QoI or channel named twice in a list flag is refused before any
// run, naming the flag, as a study file refuses a QoI that appears twice.
TEST_F(Audit, AListFlagNamesEachItemOnce) {
  std::vector<Case> cases;
  const std::string design = w().text_file("design", "c_q\n0.1\n", "csv");
  auto evaluate = [&](const std::string& flags, const std::string& out) {
    return "evaluate --no-plot --scenario " + w().quick() + " --design " + design + " " + flags + " --out " + out;
  };
  for (const std::string ext : {"h5", "csv"}) {
    const std::string out = w().out(ext);
    cases.push_back({"evaluate --qoi with a QoI twice, into ." + ext, evaluate("--qoi B_l_z_min,t_min,B_l_z_min", out),
                     Want::kError, {"--qoi: 'B_l_z_min' is listed twice"}, absent_file(out)});
  }
  const std::string out = w().out();
  cases.push_back({"evaluate --channels with a channel twice", evaluate("--qoi t_min --channels G_z,B_l_z,G_z", out),
                   Want::kError, {"--channels: 'G_z' is listed twice"}, absent_file(out)});
  cases.push_back({"calibrate --fit with a parameter by name and alias",
                   study("calibrate", w().calibration([](Json& j) { j["bounds"]["s_structure.c_q"] = {0.02, 1.0}; })) +
                       " --fit c_q,s_structure.c_q --dry-run",
                   Want::kError, {"--fit", "'s_structure.c_q' is listed twice: it and 'c_q' are both"}});
  cases.push_back({"evaluate --qoi with distinct QoIs", evaluate("--qoi B_l_z_min,t_min", w().out("csv")), Want::kRuns,
                   {}});
  run_table(w().dir(), cases);
}

// Class 7: one spread rule for every distribution: its sd (and a finite
// support's width) above 1e-12 of the larger of its mean's size and the
// parameter's configured value, as a normal's sd already was. A narrower one
// is refused before any run, naming the parameter, the distribution and the rule.
TEST_F(Audit, EveryDistributionMustSpreadBeyondRounding) {
  std::vector<Case> cases;
  auto spread_case = [&](const std::string& id, const Json& distribution, std::vector<std::string> mentions) {
    const std::string path = w().montecarlo([&](Json& j) { j["parameters"]["c_q"] = distribution; });
    mentions.insert(mentions.begin(), {path, "'parameters.c_q", "use a fixed value"});
    cases.push_back({id, study("montecarlo", path) + " --dry-run", Want::kError, mentions});
  };
  spread_case("a uniform c_q on [1e-300, 1e-299]",
              {{"distribution", "uniform"}, {"min", 1e-300}, {"max", 1e-299}},
              {"uniform(min 1e-300, max 1e-299)", "not above 1e-12 of the configured value"});
  spread_case("a log-uniform c_q with min ~ max",
              {{"distribution", "log_uniform"}, {"min", 0.1}, {"max", 0.1 * (1 + 1e-14)}},
              {"log_uniform(", "not above 1e-12"});
  spread_case("a normal c_q truncated to a sliver",
              {{"distribution", "normal"}, {"mean", 0.14}, {"sd", 0.01}, {"truncate", {0.14, 0.14 + 1e-15}}},
              {"truncated to", "wide", "not above 1e-12"});
  spread_case("a lognormal c_q of log_sd 1e-14", {{"distribution", "lognormal"}, {"log_mean", -2.0}, {"log_sd", 1e-14}},
              {"lognormal(log_mean -2, log_sd 1e-14; the value's mean 0.1353, sd 1.353e-15)", "not above 1e-12"});
  spread_case("a lognormal c_q of sd 1e-300 around its mean",
              {{"distribution", "lognormal"}, {"mean", 0.14}, {"sd", 1e-300}}, {"not above 1e-12"});
  spread_case("a normal c_q of sd 1e-300 around 1e-300",
              {{"distribution", "normal"}, {"mean", 1e-300}, {"sd", 1e-300}},
              {"not above 1e-12 of the configured value"});
  cases.push_back({"the preloads from the rover file with sd_scale 1e-300",
                   study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"] = {{"M0", {{"from_config", true}, {"sd_scale", 1e-300}}}};
                   })) + " --dry-run",
                   Want::kError, {"'parameters.M0", "not above 1e-12"}});
  cases.push_back({"a uniform c_q narrow but resolved", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"]["c_q"] = {{"distribution", "uniform"}, {"min", 0.14}, {"max", 0.14 * (1 + 1e-9)}};
                   })) + " --dry-run",
                   Want::kRuns, {}});
  run_table(w().dir(), cases);
}

// Class 8: messages that name the right thing. A parameter given twice names
// the other entry ("M0", not the preload it expands to); a scenario, rover or
// candidates file given as a --study says what it is; a constant QoI of
// 1e308 is printed in a few digits, not 309.
TEST_F(Audit, MessagesNameWhatWasGiven) {
  const std::string dir = w().dir();
  std::vector<Case> cases;
  const std::string twice = w().montecarlo([](Json& j) {
    j["parameters"] = {{"M0", {{"from_config", true}}},
                       {"M0_11", {{"distribution", "uniform"}, {"min", 1.0}, {"max", 2.0}}}};
  });
  cases.push_back({"M0 and M0_11 in one study", study("montecarlo", twice) + " --dry-run", Want::kError,
                   {"'parameters.M0_11'", "is the same parameter as 'M0' (its M0_11)"}});
  const std::string rover_file = source_path("configs/rover.json");
  const std::string candidates = w().json_file(
      "candidates", Json{{"candidates", {{{"scenario", w().quick()}, {"rate_hz", 500}, {"noise_sd", 1e-4}}}}});
  for (const std::string command : {"montecarlo", "sensitivity", "surrogate", "calibrate", "surface"}) {
    cases.push_back({command + " --study a scenario file", study(command, w().quick()) + " --dry-run", Want::kError,
                     {w().quick(), "this is a scenario file", "not a study file"}});
    cases.push_back({command + " --study a rover file", study(command, rover_file) + " --dry-run", Want::kError,
                     {"this is a rover file", "not a study file"}});
  }
  cases.push_back({"calibrate --study a candidates file", study("calibrate", candidates) + " --dry-run", Want::kError,
                   {"this is a candidates file of rover calibrate --next-experiment"}});
  // A surrogate trained on runs whose QoI is 1e308 in every run.
  const std::string training = dir + "/constant.h5";
  std::string output;
  ASSERT_EQ(run_command("cd " + dir + " && OMPI_MCA_ess_singleton_isolated=1 " + rover_binary() + " " +
                            study_args("montecarlo",
                                       w().json_file("linear", Json{{"type", "montecarlo"},
                                                                    {"name", "linear"},
                                                                    {"model", "linear"},
                                                                    {"design", {{"type", "monte_carlo"}, {"samples", 20}, {"seed", 1}}}}),
                                       training),
                        &output),
            0)
      << output;
  for (std::size_t run = 0; run < 20; ++run) set_dataset_element(training, "/qoi/y", run, 1e308);
  const std::string constant = w().json_file(
      "constant", Json{{"type", "surrogate"},
                       {"surrogate", "pce"},
                       {"name", "constant"},
                       {"model", "linear"},
                       {"training", {{"file", training}}},
                       {"pce", {{"max_degree", 1}, {"bootstrap", 0}}}});
  cases.push_back({"a QoI of 1e308 in every run", study("surrogate", constant), Want::kRuns,
                   {"the QoI is constant over the 20 runs (1e+308)"}, {}, {}, {"0000000000"}});
  run_table(dir, cases);
}

// Inputs in the wrong encoding, numbers in the wrong base, outputs under the
// wrong format's name, and settings no run can finish: refused before any run,
// by what was typed and where.
TEST_F(Audit, EncodingsFormatsAndUnfinishableSettings) {
  const std::string dir = w().dir();
  std::vector<Case> cases;
  // UTF-16 text (with and without a byte-order mark) and NUL bytes.
  const std::string mc_text = file_bytes(w().montecarlo([](Json&) {}));
  std::string utf16 = "\xFF\xFE", utf16_bare;
  for (const char c : mc_text) {
    utf16 += c, utf16 += '\0';
    utf16_bare += c, utf16_bare += '\0';
  }
  const std::string utf16_study = w().text_file("utf16", utf16), bare_study = w().text_file("bare16", utf16_bare);
  cases.push_back({"a UTF-16 study", study("montecarlo", utf16_study), Want::kError,
                   {utf16_study + ": is UTF-16 text", "save a config as UTF-8"}, {}, {}, {"invalid JSON", "literal"}});
  cases.push_back({"a UTF-16 study without a mark", study("montecarlo", bare_study), Want::kError,
                   {bare_study + ": holds NUL bytes from its first characters on"}});
  std::string data16 = "\xFF\xFE";
  for (const char c : measured_text("\n")) data16 += c, data16 += '\0';
  const std::string data16_path = w().text_file("data16", data16, "csv");
  cases.push_back({"UTF-16 measured data", study("calibrate", w().calibration([&](Json& j) { j["data"] = data16_path; })),
                   Want::kError, {data16_path + ":1: is UTF-16 text", "save a CSV file as UTF-8"}, {}, {},
                   {"missing column"}});
  // Integer flags in decimal only; a missing value named as such.
  const std::string mc = w().montecarlo([](Json&) {});
  cases.push_back({"--samples 0x10", study("montecarlo", mc) + " --samples 0x10 --dry-run", Want::kError,
                   {"--samples", "decimal digits", "0x10"}});
  cases.push_back({"--samples 0b11", study("montecarlo", mc) + " --samples 0b11 --dry-run", Want::kError,
                   {"--samples", "0b11"}});
  cases.push_back({"--samples --dry-run", study("montecarlo", mc) + " --samples --dry-run", Want::kError,
                   {"--samples was given no value: the word after it, '--dry-run', is an option of its own"}});
  cases.push_back({"simulate --scenario --no-plot", "simulate --scenario --no-plot", Want::kError,
                   {"--scenario was given no value: the word after it, '--no-plot', is an option of its own"}, {}, {},
                   {"no such file"}});
  cases.push_back({"montecarlo --study --dry-run", "montecarlo --study --dry-run", Want::kError,
                   {"--study was given no value: the word after it, '--dry-run', is an option of its own"}});
  // Outputs named for another format.
  cases.push_back({"simulate --csv x.h5", simulate(w().quick()) + " --csv " + dir + "/x.h5", Want::kError,
                   {"--csv '" + dir + "/x.h5' ends in .h5, the name of an HDF5 file", "give a name ending in .csv"},
                   absent_file(dir + "/x.h5")});
  cases.push_back({"synthesize --out x.PNG", "synthesize --scenario " + w().quick() + " --out " + dir + "/x.PNG",
                   Want::kError, {"ends in .png, the name of a PNG file", "--out writes CSV"}});
  cases.push_back({"terrain --out t.csv", "terrain obstacle --out " + dir + "/t.csv", Want::kError,
                   {"--out '" + dir + "/t.csv'", "writes JSON"}});
  cases.push_back({"simulate --csv x.txt", simulate(w().quick()) + " --csv " + dir + "/x.txt", Want::kRuns, {}});
  // Settings no run can finish, and angles no rover reaches.
  cases.push_back({"rk4 at 1e-12 s", simulate(w().scenario([](Json& j) {
                     j["integrator"] = {{"method", "rk4"}, {"fixed_step", 1e-12}};
                   })),
                   Want::kError, {"rk4: fixed_step 1e-12 s takes", "use at least 5e-11 s (the output period 0.005 s "
                                  "divided by 100000000)"}, {}, {}, {"collapsed"}});
  // The step advised is one the scenario accepts.
  cases.push_back({"rk4 at the step advised", study("montecarlo", w().montecarlo([&](Json& j) {
                     j["scenario"] = w().scenario([](Json& k) {
                       k["integrator"] = {{"method", "rk4"}, {"fixed_step", 5e-11}};
                     });
                   })) + " --dry-run",
                   Want::kRuns, {"rk4 with fixed step 5e-11 s"}});
  cases.push_back({"an S-structure deflection of 100 rad", simulate(w().scenario([](Json& j) {
                     j["initial_q"]["b12"] = 100;
                   })),
                   Want::kError, {"'initial_q'", "b12 = 100 rad is beyond", "a quarter turn"}});
  cases.push_back({"a steering angle beyond the end-stop", simulate(w().scenario([](Json& j) {
                     j["initial_q"]["d3"] = 2.5;
                   })),
                   Want::kError, {"'initial_q'", "d3 = 2.5 rad is beyond the steering end-stop"}});
  std::vector<double> q(23, 0.0);
  q[2] = 0.281, q[9] = -100.0;
  cases.push_back({"eom at a deflection of 100 rad",
                   "eom --state " + w().json_file("state", Json{{"q", q}, {"u", std::vector<double>(23, 0.0)}}),
                   Want::kError, {"'q'", "b21 = -100 rad is beyond"}});
  cases.push_back({"rk4 named in the banner", study("montecarlo", w().montecarlo([](Json& j) {
                     j["integrator"] = {{"method", "rk4"}, {"fixed_step", 1e-3}};
                   })) + " --dry-run",
                   Want::kRuns, {}, {}, {}, {"rk4 at rtol"}});
  run_table(dir, cases);
}

// Plain words for JSON typos; lists, links, locks and launchers named as
// they are.
TEST_F(Audit, PlainWordsForTyposLinksAndLaunchers) {
  const std::string dir = w().dir();
  std::vector<Case> cases;
  const std::string trailing = w().text_file("trailing", "{\"type\": \"montecarlo\", \"name\": \"x\",}");
  cases.push_back({"a trailing comma", study("montecarlo", trailing), Want::kError,
                   {trailing + ":1:", "a comma before '}'"}, {}, {}, {"syntax error while", "string literal"}});
  const std::string quotes = w().text_file("quotes", "{'type': 'montecarlo'}");
  cases.push_back({"single quotes", study("montecarlo", quotes), Want::kError, {"single quotes"}, {}, {},
                   {"last read"}});
  const std::string nan_value = w().text_file("nan", "{\"type\": \"montecarlo\", \"seed\": NaN}");
  cases.push_back({"NaN", study("montecarlo", nan_value), Want::kError, {"'NaN' is not a JSON number"}});
  const std::string design = w().text_file("design", "c_q,c_q\n0.1,0.2\n", "csv");
  cases.push_back({"a design column twice", "evaluate --scenario " + w().quick() + " --design " + design + " --out " +
                                                w().out("csv"),
                   Want::kError, {design + ":1:", "column 'c_q' is given twice (columns 1 and 2)"}});
  cases.push_back({"--qoi with a stray comma", "evaluate --scenario " + w().quick() + " --design " +
                                                   w().text_file("d", "c_q\n0.1\n", "csv") + " --qoi B_l_z_min, --out " +
                                                   w().out("csv"),
                   Want::kError, {"--qoi 'B_l_z_min,': name 2 is empty"}});
  ASSERT_EQ(::symlink((dir + "/no_such_dir").c_str(), (dir + "/dangling").c_str()), 0);
  cases.push_back({"--out under a dangling link", "simulate --no-plot --scenario " + w().quick() + " --out " + dir + "/dangling/r.h5",
                   Want::kError, {"is a symbolic link to", "which does not exist"}, {}, {}, {"File exists"}});
  cases.push_back({"--out x.h5.lock", "simulate --no-plot --scenario " + w().quick() + " --out " + dir + "/x.h5.lock", Want::kError,
                   {"the lock rover holds beside an output while it writes it"}, {}, {}, {"removes"}});
  cases.push_back({"compare under a launcher of 2",
                   "compare " + w().quick() + " " + w().quick(), Want::kError,
                   {"runs on one process, but mpirun started 2", "do the same work"}, {}, "OMPI_COMM_WORLD_SIZE=2"});
  cases.push_back({"a time-grid parameter in a design",
                   "evaluate --scenario " + w().quick() + " --design " +
                       w().text_file("dur", "scenario.duration\n0.1\n", "csv") + " --out " + w().out("csv"),
                   Want::kError, {"cannot vary from run to run", "set it in the scenario file"}, {}, {},
                   {"curves and bands"}});
  run_table(dir, cases);
}

// A prediction's dry run writes nothing, and a prediction refuses the flags
// of a study; a surrogate is not trained on runs that leave part of an
// input's declared support uncovered, and a saved model whose runs do not
// cover its support predicts only where they do; two figures of one study
// never share a file name; a surrogate's figures are announced as its own.
TEST_F(Audit, PredictionFlagsCoverageAndFigureNames) {
  const std::string dir = w().dir();
  std::vector<Case> cases;
  const LinearSurrogate lin = linear_surrogate(w());
  const std::string design = w().text_file("x", "x1,x2,x3,x4\n0.5,0,0,0\n0.25,0,0,0\n", "csv");
  const std::string predict = "surrogate --predict " + lin.model + " --design " + design + " --csv ";
  std::string csv = w().out("csv");
  cases.push_back({"--predict --dry-run", predict + csv + " --dry-run", Want::kRuns, {"dry run", "2 points"}, absent_file(csv)});
  for (const std::string& flag : {"--out " + w().out(), std::string("--resume"), std::string("--restart"),
                                 std::string("--plots all"), std::string("--no-plot"),
                                 std::string("--checkpoint-every 3"), std::string("--progress-interval 9")}) {
    csv = w().out("csv");
    cases.push_back({"--predict with " + flag, predict + csv + " " + flag, Want::kError,
                     {flag.substr(0, flag.find(' ')) + " applies to --study, not to --predict"}, absent_file(csv)});
  }
  cases.push_back({"--design without --predict", study("surrogate", lin.study) + " --dry-run --design " + design,
                   Want::kError, {"--design applies to --predict, not to --study"}});
  // Runs of x1 over [0, 0.5] train a surrogate declared over [0, 1]: refused.
  auto runs_over = [&](double max) {
    const std::string runs = dir + "/runs_" + std::to_string(max) + ".h5";
    std::string log;
    EXPECT_EQ(run_command("cd " + dir + " && OMPI_MCA_ess_singleton_isolated=1 " + rover_binary() + " " +
                              study_args("montecarlo",
                                         w().json_file("half", Json{{"type", "montecarlo"},
                                                                    {"name", "half"},
                                                                    {"model", "linear"},
                                                                    {"parameters", {{"x1", {{"distribution", "uniform"},
                                                                                            {"min", 0.0}, {"max", max}}}}},
                                                                    {"design", {{"type", "monte_carlo"},
                                                                                {"samples", 30}, {"seed", 1}}}}),
                                         runs),
                          &log),
              0)
        << log;
    return runs;
  };
  auto trained_on = [&](const std::string& runs) {
    return w().json_file("on_runs", Json{{"type", "surrogate"},
                                         {"name", "on_runs"},
                                         {"model", "linear"},
                                         {"parameters", {{"x1", {{"distribution", "uniform"}, {"min", 0.0}, {"max", 1.0}}}}},
                                         {"training", {{"file", runs}}},
                                         {"pce", {{"max_degree", 1}, {"bootstrap", 0}}}});
  };
  const std::string half = runs_over(0.5), whole = runs_over(1.0);
  std::string out = w().out();
  cases.push_back({"training runs over half the support", study_args("surrogate", trained_on(half), out), Want::kError,
                   {"'training.file'", "'x1': the training runs cover 0.", "declared support [0, 1]", "above 0.4"},
                   absent_file(out)});
  cases.push_back({"training runs over half the support, dry run",
                   study("surrogate", trained_on(half)) + " --dry-run", Want::kError, {"'training.file'", "'x1'"}});
  cases.push_back({"training runs over the whole support", study("surrogate", trained_on(whole)), Want::kRuns, {}});
  // A model whose saved support reaches beyond its training runs (x1 in
  // [0, 2], runs in [0, 1]): a row at 1.9 is refused, one at 0.5 predicted.
  const std::string widened = w().copy_of(lin.model);
  set_dataset_element(widened, "/surrogate/inputs/support", 1, 2.0);
  set_dataset_element(widened, "/surrogate/inputs/parameters", 1, 2.0);
  const std::string far = w().text_file("far", "x1,x2,x3,x4\n1.9,0,0,0\n", "csv");
  csv = w().out("csv");
  cases.push_back({"a prediction beyond the training runs", "surrogate --predict " + widened + " --design " + far +
                                                                 " --csv " + csv,
                   Want::kError, {"row 1: x1 = 1.9 lies outside the training support [0", "declared support [0, 2]"},
                   absent_file(csv)});
  csv = w().out("csv");
  cases.push_back({"a prediction inside the training runs",
                   "surrogate --predict " + widened + " --design " + design + " --csv " + csv, Want::kRuns, {}});
  // A QoI labelled like the figures of a channel.
  const Json drop_inputs{{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}},
                         {"f", {{"distribution", "log_uniform"}, {"min", 1e3}, {"max", 1e5}}}};
  auto drop_sensitivity = [&](const std::string& method, const Json& qoi) {
    Json j{{"type", "sensitivity"},
           {"method", method},
           {"name", "sobl"},
           {"scenario", w().quick()},
           {"parameters", drop_inputs},
           {"design", {{"type", method == "sobol" ? "sobol" : "lhs"}, {"samples", 8}, {"seed", 1}}},
           {"qoi", qoi},
           {"channels", {"B_l_z"}}};
    if (method == "sobol") j["bootstrap"] = 100;
    return w().json_file("figures", j);
  };
  const Json clashing = Json::array({{{"name", "B_l_z_min"}, {"label", "t_B_l_z"}},
                                     {{"name", "deflection"}, {"label", "t_B_l_z_variance"}}});
  const std::string sobol = drop_sensitivity("sobol", clashing);
  cases.push_back({"sobol: QoI labels like a channel's figures",
                   "sensitivity --study " + sobol + " --out " + w().out() + " --plots all --dry-run", Want::kError,
                   {"QoI 't_B_l_z' and of channel 'B_l_z' (its indices along time)", "_sobol_t_B_l_z.png;",
                    "QoI 't_B_l_z_variance'", "give the QoI another \"label\""}});
  cases.push_back({"sobol: the same labels, summary only",
                   "sensitivity --study " + sobol + " --out " + w().out() + " --plots summary --dry-run", Want::kRuns, {}});
  const std::string pce = drop_sensitivity("pce", Json::array({{{"name", "B_l_z_min"}, {"label", "t_B_l_z"}}}));
  cases.push_back({"pce: a QoI label like a channel's figure",
                   "sensitivity --study " + pce + " --out " + w().out() + " --plots all --dry-run", Want::kError,
                   {"QoI 't_B_l_z' and of channel 'B_l_z'", "_pce_t_B_l_z.png"}});
  // A surrogate's figure of a channel is announced by `surrogate` (a 0.3 s
  // drop: the wheels land, so the curve varies).
  const std::string curves = w().json_file(
      "curves", Json{{"type", "surrogate"},
                     {"name", "curves"},
                     {"scenario", w().scenario([](Json& j) { j["duration"] = 0.3; })},
                     {"parameters", drop_inputs},
                     {"design", {{"type", "lhs"}, {"samples", 12}, {"seed", 1}}},
                     {"qoi", {"B_l_z_min"}},
                     {"channels", {"B_l_z"}},
                     {"pce", {{"max_degree", 2}, {"bootstrap", 0}}}});
  out = w().out();
  cases.push_back({"surrogate --plots all with a channel",
                   "surrogate --study " + curves + " --out " + out + " --plots all", Want::kRunsOrFails,
                   {"surrogate: wrote " + out.substr(0, out.size() - 3) + "_surrogate_t_B_l_z.png"}, {}, {},
                   {"sensitivity: wrote"}});
  run_table(dir, cases);
}

// Calibration inputs refused before any run, each naming the field: a prior
// whose support leaves out the start (typed, or the default nominal value), a
// noise prior reaching 0 m, a default start outside the bounds, a copy of a
// curve under another name, data separated by tabs or semicolons, and
// synthetic data with fewer than 3 points after the release. A fit whose
// estimate lies outside its prior ends with no posterior, status 2, naming
// the prior, not with the sampler's words.
TEST_F(Audit, PriorsStartsCopiesAndSeparatorsOfCalibrationInputs) {
  std::vector<Case> cases;
  const std::string dir = w().dir();
  const Json narrow = {{"c_q", {{"distribution", "uniform"}, {"min", 0.5}, {"max", 0.6}}}};
  const std::string typed_start = w().calibration([&](Json& j) {
    j["method"] = "mcmc";
    j["priors"] = narrow;
  });
  cases.push_back({"a prior whose support leaves out initial.c_q", study("calibrate", typed_start) + " --dry-run",
                   Want::kError, {"'priors.c_q'", "its support [0.5, 0.6]", "the start initial.c_q = 0.1"}});
  const std::string default_start = w().calibration([&](Json& j) {
    j["method"] = "mcmc";
    j["priors"] = narrow;
    j.erase("initial");
  });
  cases.push_back({"a prior whose support leaves out the nominal c_q", study("calibrate", default_start) + " --dry-run",
                   Want::kError, {"'priors.c_q'", "the default start 0.14", "initial.c_q"}});
  // A prior wider than the bounds is truncated to them, and said so.
  const std::string wide = w().calibration([&](Json& j) {
    j["method"] = "mcmc";
    j["priors"] = {{"c_q", {{"distribution", "normal"}, {"mean", 0.25}, {"sd", 5.0}}}};
  });
  cases.push_back({"a prior wider than the bounds", study("calibrate", wide) + " --dry-run", Want::kRuns,
                   {"c_q ~ normal(mean 0.25, sd 5), truncated to the bounds [0.02, 1]"}});
  const std::string noise_from_0 = w().calibration([&](Json& j) {
    j["method"] = "mcmc";
    j["mcmc"] = {{"noise_sd", {{"distribution", "uniform"}, {"min", 0}, {"max", 1e-3}}}};
  });
  cases.push_back({"a noise prior from 0 m", study("calibrate", noise_from_0) + " --dry-run", Want::kError,
                   {"'mcmc.noise_sd'", "the prior reaches 0 m", "1e-12"}});
  const std::string offset_default = w().calibration([&](Json& j) {
    j["fit"] = {"c_q", "time_offset"};
    j["bounds"]["time_offset"] = {0.0201, 0.1};
  });
  cases.push_back({"bounds.time_offset leaving out its default start", study("calibrate", offset_default) + " --dry-run",
                   Want::kError,
                   {"'bounds.time_offset'", "the default start 0 (time_offset's default)", "initial.time_offset"}});
  const std::string copy = w().copy_of(dir + "/quick_data.csv");
  const std::string copied = w().calibration([&](Json& j) {
    j["data"] = Json::array({{{"file", dir + "/quick_data.csv"}}, {{"file", copy}}});
  });
  cases.push_back({"a curve and its copy", study("calibrate", copied) + " --dry-run", Want::kError,
                   {"'data[1].file'", "holds the curve of data[0]", "quick_data.csv", "sqrt(2)"}});
  std::string one_row_less = measured_text("\n");
  one_row_less.erase(one_row_less.find('\n') + 1, one_row_less.find('\n', one_row_less.find('\n') + 1) -
                                                      one_row_less.find('\n'));
  const std::string near_copy = w().text_file("near_copy", one_row_less, "csv");
  cases.push_back({"a curve and its copy less one row",
                   study("calibrate", w().calibration([&](Json& j) {
                     j["data"] = Json::array({{{"file", dir + "/quick_data.csv"}}, {{"file", near_copy}}});
                   })) + " --dry-run",
                   Want::kError, {"'data[1].file'", "holds the curve of data[0]", "at 39 shared times (of 39 and 40 rows)"}});
  std::string tabbed = measured_text("\n");
  std::replace(tabbed.begin(), tabbed.end(), ',', '\t');
  std::string semicolons = measured_text("\n");
  std::replace(semicolons.begin(), semicolons.end(), ',', ';');
  cases.push_back({"tab-separated data",
                   study("calibrate", w().calibration([](Json&) {})) + " --data " +
                       w().text_file("tabbed", tabbed, "csv") + " --dry-run",
                   Want::kError, {"the header 't\\tz' is separated by tabs", "comma-separated values only"}});
  cases.push_back({"semicolon-separated data",
                   study("calibrate", w().calibration([](Json&) {})) + " --data " +
                       w().text_file("semicolons", semicolons, "csv") + " --dry-run",
                   Want::kError, {"the header 't;z' is separated by semicolons", "comma-separated values only"}});
  // The quick drop lasts 0.05 s; at 500 Hz its last three points are at 0.046, 0.048 and 0.05 s.
  for (const std::string offset : {"0.05", "0.047"}) {
    const std::string late = w().out("csv");
    cases.push_back({"synthesize --offset " + offset,
                     "synthesize --scenario " + w().quick() + " --noise 0 --offset " + offset + " --out " + late,
                     Want::kError, {"--offset " + offset + " s leaves", "at least 3", "at most 0.046 s"},
                     absent_file(late)});
  }
  cases.push_back({"synthesize --offset 0.046", "synthesize --scenario " + w().quick() + " --offset 0.046 --out " +
                       w().out("csv"), Want::kRuns, {}});
  // Data of c_q 0.25 under a prior on [0.05, 0.15]: the fit leaves the prior.
  const LandingDrop drop = landing_drop(w());
  const std::string disagreeing = w().calibration([&](Json& j) {
    j["scenario"] = drop.scenario;
    j["data"] = drop.data;
    j["max_evaluations"] = 40;
    j["method"] = "mcmc";
    j["priors"] = {{"c_q", {{"distribution", "uniform"}, {"min", 0.05}, {"max", 0.15}}}};
    j["mcmc"] = {{"walkers", 8}, {"steps", 6}, {"discard", 0}, {"target_ess", 0}, {"predictive_draws", 0}};
  });
  cases.push_back({"a fit that leaves its prior", study("calibrate", disagreeing), Want::kAllFailed,
                   {"no posterior", "the least-squares estimate c_q = ", "lies outside priors.c_q",
                    "the data and the prior disagree"},
                   {}, {}, {"no point of finite density"}});
  run_table(dir, cases);
}

// ---- study flags, checkpoints and sizes ---------------------------------
// A study whose runs fail in part keeps them in its checkpoint when it is
// refused: rk4 with a fixed step diverges on the stiff contact where c_q is
// small and f large.
std::string failing_sobol(Workshop& w, const std::function<void(Json&)>& edit = {}) {
  const std::string rk4 = w.scenario([](Json& j) {
    j["duration"] = 0.3;
    j["output_rate"] = 320;
    j["integrator"] = {{"method", "rk4"}, {"fixed_step", 0.003125}};
  });
  Json j{{"type", "sensitivity"},
         {"method", "sobol"},
         {"name", "sf"},
         {"scenario", rk4},
         {"parameters",
          {{"c_q", {{"distribution", "uniform"}, {"min", 0.05}, {"max", 0.4}}},
           {"f", {{"distribution", "log_uniform"}, {"min", 1e3}, {"max", 1e5}}}}},
         {"design", {{"type", "sobol"}, {"samples", 16}, {"seed", 1}}},
         {"qoi", {"B_l_z_min"}},
         {"bootstrap", 100}};
  if (edit) edit(j);
  return w.json_file("sf", j);
}

TEST_F(Audit, ResumeNamesTheFlagWhoseValueDiffersFromTheCheckpoints) {
  const std::string dir = w().dir();
  const std::string out = dir + "/sf.h5", study_file = failing_sobol(w());
  std::string output;
  run_command("cd " + dir + " && OMPI_MCA_ess_singleton_isolated=1 " + rover_binary() + " " +
                  study_args("sensitivity", study_file, out),
              &output);
  ASSERT_TRUE(fs::exists(out + ".checkpoint")) << output;
  std::vector<Case> cases;
  cases.push_back({"--resume with another --samples", study_args("sensitivity", study_file, out) + " --resume --samples 8",
                   Want::kError, {"--samples 8 here", "made with samples 16 (from the study file, no --samples)"},
                   unchanged(out + ".checkpoint"), {}, {"in some byte"}});
  // Another study aimed at that --out is told whose checkpoint it is.
  const std::string other = w().montecarlo([](Json& j) { j["name"] = "other_mc"; });
  cases.push_back({"--resume of a Monte Carlo over a sensitivity checkpoint",
                   study_args("montecarlo", other, out) + " --resume --dry-run", Want::kError,
                   {"study montecarlo 'other_mc' here", "made with study sensitivity '"},
                   unchanged(out + ".checkpoint")});
  run_table(dir, cases);
}

TEST_F(Audit, RaisingAnAnalysisOnlySettingKeepsTheCheckpointsRuns) {
  const std::string dir = w().dir();
  // Half the groups come through whole: enough for indices once the limit is raised.
  const std::string out = dir + "/sf2.h5",
                    study_file = failing_sobol(w(), [](Json& j) { j["parameters"]["c_q"]["max"] = 0.2; });
  std::string output;
  EXPECT_EQ(run_command("cd " + dir + " && OMPI_MCA_ess_singleton_isolated=1 " + rover_binary() + " " +
                            study_args("sensitivity", study_file, out),
                        &output),
            1);
  ASSERT_TRUE(fs::exists(out + ".checkpoint")) << output;
  // The advice is true: an unchanged --resume could only refuse the runs again.
  EXPECT_NE(output.find("raise \"max_failed_fraction\""), std::string::npos) << output;
  EXPECT_EQ(output.find("or --resume (reuse them)"), std::string::npos) << output;
  // The same file with a higher limit and another bootstrap count: the same runs.
  Json raised = io::read_json_file(study_file);
  raised["max_failed_fraction"] = 0.99;
  raised["bootstrap"] = 200;
  write_file(study_file, raised.dump(2));
  std::vector<Case> cases;
  cases.push_back({"--resume with max_failed_fraction raised", study_args("sensitivity", study_file, out) + " --resume",
                   Want::kRunsOrFails, {}, {}, {}, {"different study configuration"}});
  run_table(dir, cases);
}

TEST_F(Audit, SamplesOverrideAFileSizeTooSmallForTheStudy) {
  std::vector<Case> cases;
  const std::string pce = w().json_file(
      "pce", Json{{"type", "sensitivity"}, {"method", "pce"}, {"name", "p"}, {"model", "ishigami"},
                  {"design", {{"type", "lhs"}, {"samples", 2}, {"seed", 1}}}});
  cases.push_back({"pce: --samples replaces a file's too few runs", study("sensitivity", pce) + " --samples 60 --dry-run",
                   Want::kRuns, {}});
  cases.push_back({"pce: too few runs from --samples name the flag", study("sensitivity", pce) + " --samples 5 --dry-run",
                   Want::kError, {"--samples 5", "needs at least"}, {}, {}, {"design.samples"}});
  const std::string mc = w().montecarlo([](Json& j) { j["design"]["samples"] = 1; });
  cases.push_back({"montecarlo: --samples replaces a file's single sample",
                   study("montecarlo", mc) + " --samples 3 --dry-run", Want::kRuns, {}});
  const std::string gp = w().json_file(
      "gp", Json{{"type", "surrogate"}, {"surrogate", "gp"}, {"name", "g"}, {"model", "linear"},
                 {"design", {{"type", "latin_hypercube"}, {"samples", 3}, {"seed", 1}}}});
  cases.push_back({"gp surrogate: --samples replaces a file's three runs", study("surrogate", gp) + " --samples 20 --dry-run",
                   Want::kRuns, {}});
  run_table(w().dir(), cases);
}

TEST_F(Audit, AStudyTooLargeForTheMemoryIsRefusedBeforeAnyRun) {
  std::vector<Case> cases;
  const std::string mc = w().montecarlo([](Json& j) { j["channels"] = {"B_l_z"}; });
  const std::string out = w().out();
  cases.push_back({"montecarlo of 1e8 samples under ulimit -v 3 GB", study_args("montecarlo", mc, out) + " --samples 1e8",
                   Want::kError, {"GB", "ulimit -v", "--samples"}, absent_file(out), kUnder3GB});
  cases.push_back({"its dry run says so too", study("montecarlo", mc) + " --samples 1e8 --dry-run", Want::kError,
                   {"GB", "ulimit -v", "--samples"}, {}, kUnder3GB});
  run_table(w().dir(), cases);
}

// Output names and directories that cannot hold what rover writes beside a
// result (its checkpoint's temporary, a figure's temporary, a rename):
// refused before any run, with nothing left behind.
TEST_F(Audit, OutputsWithoutRoomForTheirSiblingsAreRefusedBeforeAnyRun) {
  std::vector<Case> cases;
  const std::string mc = w().montecarlo([](Json&) {});
  const std::string long_result = w().dir() + "/" + std::string(237, 'c') + ".h5";
  cases.push_back({"a result name with no room for its checkpoint's temporary",
                   study_args("montecarlo", mc, long_result), Want::kError,
                   {"240 characters", ".checkpoint.partial", "at most 236"}, absent_file(long_result)});
  const std::string long_figures = w().dir() + "/" + std::string(230, 'f') + ".h5";
  cases.push_back({"a figure name with no room for its temporary",
                   "montecarlo --plots summary --study " + mc + " --out " + long_figures, Want::kError,
                   {"--plots", "_summary.png", ".partial-"}, absent_file(long_figures)});
  run_table(w().dir(), cases);
}

TEST_F(Audit, AnAppendOnlyOutputDirectoryIsRefusedUnprobed) {
  const std::string dir = w().dir() + "/append_only";
  fs::create_directory(dir);
  std::string output;
  if (run_command("chattr +a " + dir, &output) != 0)
    GTEST_SKIP() << "this file system keeps no append-only attribute (chattr +a: " << output << ")";
  std::vector<Case> cases;
  cases.push_back({"simulate into an append-only directory",
                   "simulate --no-plot --scenario " + w().quick() + " --out " + dir + "/y.h5", Want::kError,
                   {"append-only", "renames"}});
  cases.push_back({"montecarlo into an append-only directory",
                   study_args("montecarlo", w().montecarlo([](Json&) {}), dir + "/m.h5"), Want::kError,
                   {"append-only", "renames"}});
  run_table(w().dir(), cases);
  run_command("chattr -a " + dir, &output);
  EXPECT_TRUE(fs::is_empty(dir)) << "files left in the append-only directory";
}

// Inputs and flags whose meaning the runs cannot honour: refused before any
// run, naming what was typed.
TEST_F(Audit, LineEndsTravelSpeedsSeedsPriorsAndFlagsWithoutUse) {
  std::vector<Case> cases;
  const std::string cr_data = w().text_file("cr_data", "t,z\r0,0.25\r0.1,0.24\r0.2,0.23\r0.3,0.22\r", "csv");
  cases.push_back({"data whose lines end in CR alone",
                   study("calibrate", w().calibration([](Json&) {})) + " --dry-run --data " + cr_data, Want::kError,
                   {cr_data, "carriage return alone", "LF or CRLF"}});
  std::string stray_nul_text = measured_text("\n");
  stray_nul_text.insert(stray_nul_text.find("\n", stray_nul_text.size() / 2) + 1, 1, '\0');
  const std::string stray_nul = w().text_file("stray_nul", stray_nul_text, "csv");
  cases.push_back({"data with one stray NUL byte at a line's start",
                   study("calibrate", w().calibration([](Json&) {})) + " --dry-run --data " + stray_nul,
                   Want::kError, {stray_nul, "holds a NUL byte"}, {}, {}, {"first characters"}});
  const std::string dangling = w().dir() + "/dangling_rover.json";
  fs::create_symlink("nowhere.json", dangling);
  cases.push_back({"a scenario whose rover is a dangling link",
                   simulate(w().scenario([&](Json& j) { j["rover"] = dangling; })), Want::kError,
                   {"'rover'", "is a symbolic link to 'nowhere.json', which does not exist"}});
  const std::string cr_design = w().text_file("cr_design", "c_q,f\r0.2,1e4\r0.3,2e3\r", "csv");
  cases.push_back({"a design whose lines end in CR alone",
                   "evaluate --scenario " + w().quick() + " --design " + cr_design + " --qoi t_min --out " +
                       w().out("csv") + " --dry-run",
                   Want::kError, {cr_design, "carriage return alone"}});
  const std::string travel = w().scenario([](Json& j) {
    j.erase("duration");
    j["travel_distance"] = 0.005;
    j["forward_speed"] = 0.1;
  });
  cases.push_back({"a varied speed where the travel distance sets the duration",
                   study("montecarlo", w().montecarlo([&](Json& j) {
                     j["scenario"] = travel;
                     j["parameters"] = {{"scenario.forward_speed", {{"distribution", "uniform"}, {"min", 0.05},
                                                                    {"max", 0.1}}}};
                   })),
                   Want::kError, {"scenario.forward_speed", "travel_distance", "time grid"}});
  const std::string grid = w().montecarlo([](Json& j) { j["design"] = {{"type", "grid"}, {"levels", 3}}; });
  cases.push_back({"--seed of a grid design", study("montecarlo", grid) + " --seed 5", Want::kError,
                   {"--seed does not apply to a grid design"}});
  cases.push_back({"the intervals of a grid design", study("montecarlo", grid), Want::kRuns,
                   {"a grid is no random sample"}, {}, {}, {", seed"}});
  const std::string fixed_prior = w().calibration([](Json& j) {
    j["method"] = "mcmc";
    j["priors"] = {{"c_q", {{"distribution", "fixed"}, {"value", 0.2}}}};
  });
  cases.push_back({"a fixed prior on a fitted parameter", study("calibrate", fixed_prior) + " --dry-run",
                   Want::kError, {"priors.c_q", "nothing to sample"}});
  const std::string fit = w().calibration([](Json&) {});
  for (const std::string flag : {"--resume", "--checkpoint-every 5"})
    cases.push_back({"a least-squares fit with " + flag, study("calibrate", fit) + " --dry-run " + flag,
                     Want::kError, {flag.substr(0, flag.find(' ')), "keeps no checkpoint"}});
  const std::string candidates = w().json_file(
      "candidates", Json{{"candidates", {{{"name", "a"}, {"scenario", w().quick()}, {"channel", "B_l_z"},
                                          {"rate_hz", 500}, {"noise_sd", 1e-4}}}}});
  cases.push_back({"a ranking with --plots",
                   "calibrate --study " + fit + " --out " + w().out() + " --dry-run --plots all --next-experiment " +
                       candidates,
                   Want::kError, {"--plots", "draws no figure"}});
  cases.push_back({"a ranking of a study that asks for a posterior",
                   study("calibrate", w().calibration([](Json& j) { j["method"] = "mcmc"; })) +
                       " --dry-run --next-experiment " + candidates,
                   Want::kError, {"--next-experiment", "\"method\" (mcmc", "--method optimize"}});
  cases.push_back({"a confidence no allowed bootstrap resolves",
                   study("montecarlo", w().montecarlo([](Json& j) { j["confidence"] = 0.999999; })), Want::kError,
                   {"'confidence'", "more than the 100000 allowed", "at most 0.99999"}});
  cases.push_back({"Sobol' indices without intervals",
                   study("sensitivity", w().sensitivity([](Json& j) { j["bootstrap"] = 0; })), Want::kRuns,
                   {"no intervals: \"bootstrap\": 0"}, {}, {}, {"nan"}});
  const std::string posterior = w().calibration([](Json& j) { j["method"] = "mcmc"; });
  cases.push_back({"a posterior of one step", study("calibrate", posterior) + " --dry-run --steps 1", Want::kError,
                   {"--steps 1", "leaves 1 step(s)", "give at least 4 steps"}, {}, {}, {"got 0"}});
  cases.push_back({"a Monte Carlo without an sd interval",
                   study("montecarlo", w().montecarlo([](Json& j) { j["bootstrap"] = 0; })), Want::kRuns,
                   {"no sd interval"}});
  run_table(w().dir(), cases);
}

// A Sobol' study where only one pick-freeze group came through whole: no
// max_failed_fraction gives it indices, and a result without any index is
// not one to trust.
TEST_F(Audit, SensitivityWithoutAnyIndexSaysSoAndExitsTwo) {
  std::vector<Case> cases;
  cases.push_back({"the failed-runs advice when too few groups are whole", study("sensitivity", failing_sobol(w())),
                   Want::kError, {"no max_failed_fraction can make them usable", "needs at least 2"},
                   {}, {}, {"raise \"max_failed_fraction\""}});
  cases.push_back({"every index undefined",
                   study("sensitivity", failing_sobol(w(), [](Json& j) { j["max_failed_fraction"] = 0.94; })),
                   Want::kAllFailed, {"indices undefined", "no QoI or channel has indices"}});
  run_table(w().dir(), cases);
}

// A checkpoint damaged in its middle: the records from the damage on are
// dropped and computed again, and --resume says so.
TEST_F(Audit, ResumeSaysWhenItDropsADamagedPartOfTheCheckpoint) {
  const std::string dir = w().dir();
  const std::string out = dir + "/sf3.h5",
                    study_file = failing_sobol(w(), [](Json& j) { j["parameters"]["c_q"]["max"] = 0.2; });
  std::string output;
  run_command("cd " + dir + " && OMPI_MCA_ess_singleton_isolated=1 " + rover_binary() + " " +
                  study_args("sensitivity", study_file, out),
              &output);
  const std::string checkpoint = out + ".checkpoint";
  ASSERT_TRUE(fs::exists(checkpoint)) << output;
  {
    std::fstream damage(checkpoint, std::ios::in | std::ios::out | std::ios::binary);
    damage.seekp(static_cast<std::streamoff>(fs::file_size(checkpoint) / 2));
    damage.write("\xFF\xFF\xFF\xFF", 4);
  }
  Json raised = io::read_json_file(study_file);
  raised["max_failed_fraction"] = 0.99;
  write_file(study_file, raised.dump(2));
  std::vector<Case> cases;
  cases.push_back({"--resume of a checkpoint damaged in its middle",
                   study_args("sensitivity", study_file, out) + " --resume", Want::kRunsOrFails,
                   {"bytes hold no whole, intact record", "computed again"}});
  run_table(dir, cases);
}

TEST_F(Audit, SurrogateRunsAreThoseOfTheStudysRoverAndIntegrator) {
  const std::string dir = w().dir();
  const Json c_q = {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.4}};
  const Json f = {{"distribution", "log_uniform"}, {"min", 1e3}, {"max", 1e5}};
  // Runs of another rover: M0_11 held at 0.2, where the shipped rover has 1.924.
  std::string design = "c_q,f,M0_11\n";
  for (int i = 0; i < 12; ++i)
    design += std::to_string(0.1 + 0.3 * i / 11.0) + "," + std::to_string(std::pow(10.0, 3.0 + 2.0 * ((i * 5) % 12) / 11.0)) + ",0.2\n";
  const std::string design_file = w().text_file("xm0", design, "csv"), held = dir + "/em0.h5";
  std::string output;
  run_command("cd " + dir + " && OMPI_MCA_ess_singleton_isolated=1 " + rover_binary() + " evaluate --no-plot --scenario " +
                  w().quick() + " --design " + design_file + " --out " + held + " --qoi B_l_z_min",
              &output);
  ASSERT_TRUE(fs::exists(held)) << output;
  const Json surrogate{{"type", "surrogate"}, {"name", "st"}, {"surrogate", "pce"}, {"scenario", w().quick()},
                       {"parameters", {{"c_q", c_q}, {"f", f}}}, {"qoi", {"B_l_z_min"}}};
  Json other_rover = surrogate;
  other_rover["training"] = {{"file", held}};
  // A Monte Carlo on rk4 with a 1 ms step: its file records the step.
  const std::string rk4_runs = dir + "/mrk.h5";
  Json mc = io::read_json_file(w().montecarlo([](Json&) {}));
  mc["integrator"] = {{"method", "rk4"}, {"fixed_step", 0.001}};
  mc["parameters"] = {{"c_q", c_q}, {"f", f}};
  mc["design"] = {{"type", "latin_hypercube"}, {"samples", 20}, {"seed", 1}};
  mc["qoi"] = {"B_l_z_min"};
  run_command("cd " + dir + " && OMPI_MCA_ess_singleton_isolated=1 " + rover_binary() + " " +
                  study_args("montecarlo", w().json_file("mrk", mc), rk4_runs),
              &output);
  ASSERT_TRUE(fs::exists(rk4_runs)) << output;
  Json on_rk4 = surrogate;
  on_rk4["training"] = {{"file", rk4_runs}};
  on_rk4["pce"]["q2_threshold"] = 0.5;  // 20 runs: Q2 0.8, accepted knowingly
  // Every run of the design diverges: rk4 at 3.125 ms on the stiff contact.
  Json diverging = surrogate;
  diverging["scenario"] = w().scenario([](Json& j) {
    j["duration"] = 0.3;
    j["output_rate"] = 320;
    j["integrator"] = {{"method", "rk4"}, {"fixed_step", 0.003125}};
  });
  diverging["parameters"]["c_q"] = {{"distribution", "uniform"}, {"min", 0.35}, {"max", 0.4}};
  diverging["design"] = {{"type", "latin_hypercube"}, {"samples", 10}, {"seed", 1}};
  const std::string earlier = w().copy_of(held);
  std::vector<Case> cases;
  cases.push_back({"training runs of another rover", study("surrogate", w().json_file("st", other_rover)),
                   Want::kError, {"training.file", "M0_11", "0.2 in every run", "1.924"}});
  cases.push_back({"training runs on rk4 name their step", study("surrogate", w().json_file("sr", on_rk4)),
                   Want::kRuns, {"rk4 with fixed step 0.001 s"}, [=] {
                     const io::Hdf5Reader h5(rk4_runs);
                     if (!h5.has_attribute("/", "fixed_step_s")) return rk4_runs + " records no fixed_step_s";
                     return h5.attribute_double("/", "fixed_step_s") == 0.001 ? std::string()
                                                                               : rk4_runs + ": another fixed_step_s";
                   }, {}, {"fixed step 1e-05"}});
  cases.push_back({"every design run failing keeps the earlier result",
                   study_args("surrogate", w().json_file("sd", diverging), earlier), Want::kAllFailed,
                   {"every run failed", earlier + " is unchanged"}, unchanged(earlier)});
  run_table(dir, cases);
}

// Messages that name what the user did, and inputs that are what they claim:
// a command's own default output is not called --out; a study's description
// is text even where it spells a file's name; indices compared with a
// surrogate's are of the study's scenario; a simulated height beyond any
// simulated position is a damaged file; a checkpoint left by failed runs is
// not called interrupted.
TEST_F(Audit, DefaultsDescriptionsComparedIndicesAndDamagedCurves) {
  const std::string dir = w().dir();
  std::vector<Case> cases;
  // calibrate --next-experiment without --out, where results/ cannot be made.
  const std::string fresh = dir + "/fresh";
  fs::create_directory(fresh);
  write_file(fresh + "/results", "a file where the directory would go\n");
  const std::string candidates =
      w().json_file("candidates", Json{{"candidates", {{{"scenario", w().quick()}, {"rate_hz", 200}, {"noise_sd", 1e-4}}}}});
  const std::string calibration = w().calibration([](Json&) {});
  std::vector<Case> in_fresh;
  in_fresh.push_back({"calibrate --next-experiment with no --out and no room for results/",
                      "calibrate --no-plot --study " + calibration + " --next-experiment " + candidates + " --dry-run",
                      Want::kError, {"the default output 'results/c_next_experiment.h5'", "cannot create the directory 'results'"},
                      unchanged(fresh + "/results"), {}, {"--out 'results"}});
  run_table(fresh, in_fresh);
  // A surrogate study whose description spells its own result's name.
  const Json c_q = {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}}};
  const Json f_and_c_q = {{"f", {{"distribution", "log_uniform"}, {"min", 1e3}, {"max", 1e4}}},
                          {"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}}};
  const auto surrogate = [&](const std::string& scenario, const Json& inputs, const std::function<void(Json&)>& edit) {
    Json j{{"type", "surrogate"}, {"name", "sg"}, {"scenario", scenario}, {"parameters", inputs}, {"qoi", {"t_min"}},
           {"design", {{"type", "latin_hypercube"}, {"samples", 8}, {"seed", 1}}}};
    edit(j);
    return w().json_file("sg", j);
  };
  const std::string described = dir + "/described.h5";
  write_file(described, "an earlier result\n");
  cases.push_back({"a surrogate study whose description names its result",
                   study_args("surrogate", surrogate(w().quick(), c_q, [&](Json& j) { j["description"] = described; }),
                              described) + " --dry-run",
                   Want::kRuns, {}, unchanged(described)});
  // Indices of another scenario to compare with.
  const std::string longer = w().scenario([](Json& j) { j["duration"] = 0.15; });  // past the touchdown
  const std::string indices = dir + "/indices.h5";
  std::string log;
  ASSERT_EQ(run_command("cd " + dir + " && " + rover_binary() + " " +
                            study_args("sensitivity",
                                       w().json_file("sobol", Json{{"type", "sensitivity"}, {"method", "sobol"},
                                                                   {"name", "so"}, {"scenario", longer},
                                                                   {"parameters", f_and_c_q}, {"qoi", {"B_l_z_min"}},
                                                                   {"design", {{"type", "sobol"}, {"samples", 8},
                                                                               {"seed", 1}}},
                                                                   {"bootstrap", 100}}),
                                       indices),
                        &log),
            0) << log;
  const auto compared = [&](const std::string& scenario) {
    return surrogate(scenario, f_and_c_q, [&](Json& j) {
      j["qoi"] = {"B_l_z_min"};
      j["compare"] = {{"file", indices}};
    });
  };
  cases.push_back({"compare indices of another scenario", study("surrogate", compared(w().quick())) + " --dry-run",
                   Want::kError, {"'compare.file'", indices + ": compared runs: were made on another scenario",
                                  "duration"}});
  cases.push_back({"compare indices of the same scenario", study("surrogate", compared(longer)) + " --dry-run",
                   Want::kRuns, {}});
  // A simulated curve with one height no simulation reaches.
  const std::string damaged = simulated_curve(dir + "/damaged.h5");
  set_dataset_element(damaged, "/B_l_z", 5, 1.78e127);
  cases.push_back({"compare a simulated curve holding 1.78e127 m", "compare " + damaged + " " + damaged,
                   Want::kError, {damaged + ": sample 5: B_l_z = 1.78e+127 m is beyond the bound |B_l_z|"}});
  // An evaluation whose every run failed leaves an earlier result as it was and keeps its runs in the
  // checkpoint; the next run names that.
  const std::string budgetless = w().scenario([](Json& s) { s["wall_time_budget"] = 1e-9; });
  const std::string design = w().text_file("design", "c_q\n0.1\n0.2\n", "csv");
  const std::string failed = dir + "/failed.csv";
  write_file(failed, "an earlier result\n");
  const std::string evaluate = "evaluate --scenario " + budgetless + " --design " + design + " --qoi t_min --out " + failed;
  ASSERT_EQ(run_command("cd " + dir + " && " + rover_binary() + " " + evaluate, &log), 2) << log;
  ASSERT_TRUE(fs::exists(failed + ".checkpoint")) << log;
  cases.push_back({"evaluate again beside the checkpoint of failed runs", evaluate, Want::kError,
                   {"stopped before its end (interrupted, or ended by failed runs)", "--restart"},
                   unchanged(failed + ".checkpoint"), {}, {"of an interrupted study"}});
  // Impact QoIs read from a coarse recording are warned of; others are not.
  const std::string coarse = w().scenario([](Json& j) { j["output_rate"] = 50; });
  const std::string warned = "warning: the scenario records at output_rate 50 Hz (a sample every 20 ms)";
  cases.push_back({"montecarlo of B_l_z_min recorded at 50 Hz",
                   study("montecarlo", w().montecarlo([&](Json& j) {
                     j["scenario"] = coarse;
                     j["qoi"] = {"B_l_z_min", "at_rest"};
                   })) + " --dry-run",
                   Want::kRuns, {warned, "and B_l_z_min are read from those samples"}});
  cases.push_back({"montecarlo of at_rest recorded at 50 Hz",
                   study("montecarlo", w().montecarlo([&](Json& j) {
                     j["scenario"] = coarse;
                     j["qoi"] = {"at_rest"};
                   })) + " --dry-run",
                   Want::kRuns, {}, {}, {}, {"output_rate"}});
  cases.push_back({"evaluate t_min recorded at 50 Hz",
                   "evaluate --scenario " + coarse + " --design " + design + " --qoi t_min --out " + w().out("csv") +
                       " --dry-run",
                   Want::kRuns, {warned, "and t_min are read"}});
  run_table(dir, cases);
}

// Names and files a command is given: a study's name holds no control
// character; a missing file named inside a config is named with its field;
// an output name needs a name before its extension and no mount over it; a
// design's columns are checked before its values; a training file's run
// count, a channel listed twice and a checkpoint's integrator are found
// before any run.
TEST_F(Audit, OutputNamesMountsDesignsAndNamedFiles) {
  const std::string dir = w().dir();
  std::vector<Case> cases;
  const std::string nul_name = w().montecarlo([](Json& j) { j["name"] = std::string("a\0b", 3); });
  cases.push_back({"a study name holding a NUL", "montecarlo --no-plot --dry-run --study " + nul_name, Want::kError,
                   {"field 'name'", "control character"}, absent_file(dir + "/results")});
  cases.push_back({"a calibration's data file missing", study("calibrate", w().calibration([](Json& j) {
                     j["data"] = "nonexist.csv";
                   })) + " --dry-run",
                   Want::kError, {"field 'data'", "file not found: " + dir + "/nonexist.csv"}});
  const std::string candidates = w().json_file(
      "cand", Json{{"candidates", {{{"scenario", "missing.json"}, {"rate_hz", 200}, {"noise_sd", 1e-4}}}}});
  cases.push_back({"a candidate's scenario missing",
                   "calibrate --no-plot --study " + w().calibration([](Json&) {}) + " --next-experiment " + candidates +
                       " --out " + w().out() + " --dry-run",
                   Want::kError, {candidates, "field 'candidates[0].scenario'", "file not found"}});
  cases.push_back({"simulate --out .h5", "simulate --no-plot --scenario " + w().quick() + " --out " + dir + "/.h5",
                   Want::kError, {"has no name before its extension .h5"}, absent_file(dir + "/.h5"),
                   {}, {"must end in .h5"}});
  cases.push_back({"simulate --csv .csv",
                   "simulate --no-plot --scenario " + w().quick() + " --out " + w().out() + " --csv " + dir + "/.csv",
                   Want::kError, {"--csv", "has no name before its extension .csv"}, absent_file(dir + "/.csv")});
  cases.push_back({"montecarlo --out .h5", study_args("montecarlo", w().montecarlo([](Json&) {}), dir + "/.h5"),
                   Want::kError, {"has no name before its extension .h5"}});
  // rover evaluate's own output given back as a design; a column that is no
  // parameter with a value that is no number.
  const std::string evaluated = dir + "/evaluated.csv";
  write_file(evaluated, "c_q,t_min,status,message\n0.1,0.05,0,\n");
  const std::string bogus = w().text_file("bogus", "c_q,bogus\n0.1,abc\n", "csv");
  cases.push_back({"evaluate's output as a design",
                   "evaluate --scenario " + w().quick() + " --design " + evaluated + " --qoi t_min --out " + w().out("csv"),
                   Want::kError, {"column 2 't_min' is an output of rover evaluate"}, {}, {}, {"not a finite number"}});
  cases.push_back({"a design column that is no parameter, with text in it",
                   "evaluate --scenario " + w().quick() + " --design " + bogus + " --qoi t_min --out " + w().out("csv"),
                   Want::kError, {"column 2", "unknown parameter 'bogus'"}, {}, {}, {"not a finite number"}});
  // A surrogate study trained on too few runs, found by --dry-run.
  const Json c_q = {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}}};
  const std::string four_runs = dir + "/four.h5";
  std::string log;
  ASSERT_EQ(run_command("cd " + dir + " && " + rover_binary() + " " +
                            study_args("montecarlo", w().montecarlo([](Json& j) { j["design"]["samples"] = 2; }),
                                       four_runs),
                        &log),
            0) << log;
  const std::string thin = w().json_file(
      "thin", Json{{"type", "surrogate"}, {"name", "thin"}, {"scenario", w().quick()}, {"parameters", c_q},
                   {"qoi", {"t_min"}}, {"training", {{"file", four_runs}}}, {"pce", {{"max_degree", 2}}}});
  cases.push_back({"a surrogate trained on 2 runs, dry run", study("surrogate", thin) + " --dry-run", Want::kError,
                   {"field 'training.file'", "2 successful training runs", "needs at least"}});
  cases.push_back({"a channel listed twice", study("montecarlo", w().montecarlo([](Json& j) {
                     j["channels"] = {"B_l_z", "B_l_z"};
                   })) + " --dry-run",
                   Want::kError, {"field 'channels[1]'", "channel 'B_l_z' appears twice"}});
  // The checkpoint of an evaluation made with the scenario's integrator.
  const std::string budgetless = w().scenario([](Json& s) { s["wall_time_budget"] = 1e-9; });
  const std::string design = w().text_file("design", "c_q\n0.1\n0.2\n", "csv");
  const std::string failed = dir + "/failed.csv";
  write_file(failed, "an earlier result\n");  // kept, and the failed runs with it
  const std::string evaluate = "evaluate --scenario " + budgetless + " --design " + design + " --qoi t_min --out " + failed;
  ASSERT_EQ(run_command("cd " + dir + " && " + rover_binary() + " " + evaluate, &log), 2) << log;
  cases.push_back({"evaluate --resume under another --integrator", evaluate + " --resume --integrator dopri5 --dry-run",
                   Want::kError, {"the scenario's integrator (no --integrator)"}, {}, {}, {"study file"}});
  // Data that end before the run starts at every offset the bounds allow.
  std::string early = "t,z\n";
  for (int k = 0; k <= 17; ++k) early += std::to_string(-2.0 + 0.1 * k) + "," + std::to_string(0.28 - 0.001 * k) + "\n";
  const std::string early_data = w().text_file("early", early, "csv");
  cases.push_back({"data that end before the run starts", study("calibrate", w().calibration([&](Json& j) {
                     j["data"] = early_data;
                   })) + " --dry-run",
                   Want::kError, {early_data, "before the simulated run", "smallest time offset, -0.2 s"}});
  // A rover file named like a plot of the result: refused only where plots are drawn.
  const std::string plot_named = dir + "/pm_summary.png";
  fs::copy_file(source_path("configs/rover.json"), plot_named);
  const std::string plot_named_study = w().montecarlo([&](Json& j) {
    j["scenario"] = w().scenario([&](Json& k) { k["rover"] = plot_named; });
  });
  cases.push_back({"a rover file named like a plot, --no-plot",
                   study_args("montecarlo", plot_named_study, dir + "/pm.h5") + " --dry-run", Want::kRuns, {},
                   unchanged(plot_named)});
  cases.push_back({"a rover file named like a plot, plotted",
                   "montecarlo --study " + plot_named_study + " --out " + dir + "/pm.h5 --dry-run", Want::kError,
                   {"a plot written beside it"}, unchanged(plot_named)});
  // A friction fit below its own quality bar is not a result to trust.
  cases.push_back({"friction with mu_k above mu_s", "friction --mu-s 0.5 --mu-k 0.6", Want::kAllFailed,
                   {"misses the quality bar", "not to be trusted", "mu_k is above mu_s"}});
  // A file mounted over the output path (where this process may mount).
  const std::string mounted = dir + "/mounted.h5", source = dir + "/source.h5";
  write_file(mounted, "");
  write_file(source, "an earlier result\n");
  const bool mounts = run_command("mount --bind " + source + " " + mounted + " 2>/dev/null", &log) == 0;
  // A file system too small for the result, though not for the checkpoint.
  const std::string tiny = dir + "/tiny";
  fs::create_directory(tiny);
  const bool small_disk = mounts && run_command("mount -t tmpfs -o size=160k tmpfs " + tiny, &log) == 0;
  if (mounts)
    cases.push_back({"simulate --out onto a bind mount",
                     "simulate --no-plot --scenario " + w().quick() + " --out " + mounted, Want::kError,
                     {"is a mount point"}, unchanged(source)});
  if (small_disk)
    cases.push_back({"a result too large for its disk",
                     study_args("montecarlo", w().montecarlo([&](Json& j) {
                       j["scenario"] = w().scenario([](Json& k) {
                         k["duration"] = 0.3;
                         k["output_rate"] = 500;
                       });
                       j["design"]["samples"] = 100;
                       j["channels"] = {"B_l_z"};
                     }), tiny + "/m.h5"),
                     Want::kError, {"No space left", "the finished runs are kept in " + tiny + "/m.h5.checkpoint",
                                    "--resume"}, absent_file(tiny + "/m.h5")});
  run_table(dir, cases);
  if (mounts) {
    EXPECT_EQ(run_command("umount " + mounted, &log), 0) << log;
  }
  if (small_disk) {
    EXPECT_EQ(run_command("umount " + tiny, &log), 0) << log;
  }
}

// Inputs that set one number twice (M0_scale beside a preload), a posterior
// target its chains can never reach, chassis and wheel angles in degrees,
// and a rest time read at two instants of a moving curve.
TEST_F(Audit, OverlapsReachableTargetsAnglesAndRestTimes) {
  std::vector<Case> cases;
  const std::vector<std::string> overlap = {"overlap", "M0_scale", "M0_11", "multiplies all eight preloads"};
  auto with = [](std::vector<std::string> mentions, const std::vector<std::string>& more) {
    mentions.insert(mentions.end(), more.begin(), more.end());
    return mentions;
  };
  // The factor and a preload, in either column order, in a design.
  for (const std::string header : {"M0_scale,M0_11", "M0_11,M0_scale"}) {
    const std::string design = w().text_file("scaled", header + "\n1,1.924\n1.2,1.924\n", "csv");
    cases.push_back({"evaluate: columns " + header,
                     "evaluate --scenario " + w().quick() + " --design " + design + " --qoi t_min --out " +
                         w().out("csv"),
                     Want::kError, with(overlap, {design + ":1", "columns 1 and 2"})});
  }
  const Json uniform = {{"distribution", "uniform"}, {"min", 0.8}, {"max", 1.2}};
  const Json preload = {{"distribution", "uniform"}, {"min", 1.0}, {"max", 2.0}};
  const std::string scaled_mc = w().montecarlo([&](Json& j) {
    j["parameters"] = {{"M0_scale", uniform}, {"M0_11", preload}};
  });
  cases.push_back({"montecarlo: M0_scale and M0_11", study("montecarlo", scaled_mc) + " --dry-run", Want::kError,
                   with(overlap, {scaled_mc, "'parameters.M0_"})});
  const std::string scaled_fit = w().calibration([](Json& j) {
    j["fit"] = {"M0_scale", "M0_11"};
    j["bounds"]["M0_scale"] = {0.5, 2.0};
    j["bounds"]["M0_11"] = {0.5, 5.0};
  });
  cases.push_back({"calibrate: fit M0_scale and M0_11", study("calibrate", scaled_fit) + " --dry-run", Want::kError,
                   with(overlap, {scaled_fit, "'fit'"})});
  cases.push_back({"calibrate: --fit M0_11,M0_scale", study("calibrate", scaled_fit) + " --dry-run --fit M0_11,M0_scale",
                   Want::kError, with(overlap, {"--fit"})});
  const std::string scaled_set = w().json_file(
      "scaled_set", Json{{"candidates",
                          {{{"scenario", w().quick()}, {"rate_hz", 1000}, {"noise_sd", 1e-4},
                            {"set", {{"M0_scale", 1.1}, {"M0_11", 2.0}}}}}}});
  cases.push_back({"next experiment: set M0_scale and M0_11",
                   study("calibrate", w().calibration([](Json&) {})) + " --dry-run --next-experiment " + scaled_set,
                   Want::kError, with(overlap, {scaled_set, "'candidates[0].set."})});
  const std::string fitted_preload = w().calibration([](Json& j) {
    j["fit"] = {"M0_11"};
    j["bounds"]["M0_11"] = {0.5, 5.0};
  });
  const std::string scale_set = w().json_file(
      "scale_set", Json{{"candidates",
                         {{{"scenario", w().quick()}, {"rate_hz", 1000}, {"noise_sd", 1e-4},
                           {"set", {{"M0_scale", 1.1}}}}}}});
  cases.push_back({"next experiment: set M0_scale beside a fitted M0_11",
                   study("calibrate", fitted_preload) + " --dry-run --next-experiment " + scale_set, Want::kError,
                   with(overlap, {scale_set, "'candidates[0].set.M0_scale'", "which the study fits"})});
  // A target above walkers x (steps - burn-in) draws is never met.
  for (const auto& [target, text] : {std::pair{1e9, "1e+09"}, std::pair{1e300, "1e+300"}}) {
    const double target_ess = target;
    const std::string far = w().calibration([&](Json& j) {
      j["method"] = "mcmc";
      j["mcmc"] = {{"walkers", 8}, {"steps", 30}, {"target_ess", target_ess}};
    });
    cases.push_back({std::string("posterior target_ess ") + text, study("calibrate", far) + " --dry-run",
                     Want::kError,
                     {far, "'mcmc.target_ess'", text, "8 x (30 - 10) = 160 draws", "can never be met",
                      "from 0", "to 160"}});
  }
  cases.push_back({"posterior default target beyond --walkers 4 --steps 20",
                   study("calibrate", w().calibration([](Json&) {})) + " --dry-run --method mcmc --walkers 4 --steps 20",
                   Want::kError, {"--walkers 4 --steps 20", "the default target_ess 400", "4 x (20 - 10) = 40 draws"}});
  // Chassis, bogie and wheel angles in degrees.
  auto angle_case = [&](const std::string& id, const Json& initial_q, std::vector<std::string> mentions) {
    const std::string scenario = w().scenario([&](Json& j) { j["initial_q"] = initial_q; });
    mentions.insert(mentions.begin(), {scenario, "'initial_q'"});
    mentions.push_back("an angle in degrees?");
    cases.push_back({id, simulate(scenario), Want::kError, mentions});
  };
  angle_case("pitch of 30 rad", {{"z", 0.6}, {"chi", 30.0}, {"psi", 0.0042}},
             {"chi = 30 rad is beyond +-1.570796327 rad", "stands on its end or its side"});
  angle_case("roll of 5 rad", {{"z", 0.6}, {"psi", 5.0}}, {"psi = 5 rad is beyond +-1.570796327 rad"});
  angle_case("heading of 1e17 rad", {{"z", 0.281}, {"chi", 0.039}, {"theta", 1e17}},
             {"theta = 1e+17 rad is beyond +-6.283185307 rad", "a full turn"});
  angle_case("bogie at 45 rad", {{"z", 0.6}, {"phi", 45.0}}, {"phi = 45 rad is beyond +-1.570796327 rad", "bogie"});
  angle_case("wheel angle of 90 rad", {{"z", 0.281}, {"chi", 0.039}, {"z3", 90.0}},
             {"z3 = 90 rad is beyond +-6.283185307 rad", "rolling angle"});
  auto state_with = [&](int index, double value) {
    std::vector<double> q(23, 0.0);
    q[2] = 0.5;
    q[static_cast<std::size_t>(index)] = value;
    return w().json_file("state_angle", Json{{"q", q}, {"u", std::vector<double>(23, 0.0)}});
  };
  const std::string yaw_state = state_with(3, 1e300), roll_state = state_with(5, 1e17);
  cases.push_back({"eom: theta 1e300", "eom --state " + yaw_state, Want::kError,
                   {yaw_state, "'q'", "theta = 1e+300 rad", "an angle in degrees?"}});
  cases.push_back({"eom: psi 1e17", "eom --state " + roll_state, Want::kError,
                   {roll_state, "'q'", "psi = 1e+17 rad", "an angle in degrees?"}});
  const std::string pitched_mc = w().montecarlo([](Json& j) {
    j["parameters"] = {{"scenario.initial_q.chi", {{"distribution", "uniform"}, {"min", 20.0}, {"max", 40.0}}}};
  });
  cases.push_back({"montecarlo of pitches in degrees", study("montecarlo", pitched_mc), Want::kError,
                   {pitched_mc, "'parameters'", "scenario.initial_q.chi", "chi = 20", "an angle in degrees?"}});
  // z_r of both curves at one time: A 0 .. 0.3 s, B -0.02 .. 0.28 s on A's
  // clock (its last time 0.27999999999999997), the rover still rising.
  const std::string drop = w().scenario([](Json& j) {
    j["duration"] = 0.3;
    j["output_rate"] = 500;
  });
  const std::string a = w().out(), b = w().out("csv");
  std::string output;
  ASSERT_EQ(run_command(rover_binary() + " simulate --no-plot --scenario " + drop + " --out " + a, &output), 0)
      << output;
  ASSERT_EQ(run_command(rover_binary() + " synthesize --scenario " + drop + " --cq 0.3 --noise 1e-4 --offset 0.02 --out " +
                            b, &output), 0)
      << output;
  const std::string compare = "compare " + a + " " + b + " --time-offset 0.02";
  cases.push_back({"compare: the default rest time beyond both ends", compare, Want::kRuns,
                   {"the default --rest-time 1 s lies outside the times both curves cover, [0, 0.28] s",
                    "z_r of both is read at 0.28 s, the last time both cover"}, {}, {}, {"\"rest_time_s\": 1"}});
  cases.push_back({"compare: a rest time beyond one curve", compare + " --rest-time 0.29", Want::kError,
                   {"--rest-time 0.29 s lies outside the times both curves cover, [0, 0.28] s",
                    "give a rest time within [0, 0.28] s"}});
  cases.push_back({"compare: a rest time at B's end, to rounding", compare + " --rest-time 0.28", Want::kRuns,
                   {"\"deflection_error\""}, {}, {}, {"warning", "outside"}});
  run_table(w().dir(), cases);
}

// Config text that is not UTF-8, integer fields with their own ranges, grid
// levels in any whole-number form, and a file of another kind than the one
// a flag or field reads.
TEST_F(Audit, ConfigTextCountsAndFileKinds) {
  const std::string dir = w().dir();
  std::vector<Case> cases;
  // JSON text that is not UTF-8 is named by its line, column and byte.
  const std::string mc_text = io::read_json_file(w().montecarlo([](Json&) {})).dump(1);
  const std::string latin1 = w().text_file("latin1", "{\"description\": \"Caf\xe9 x\",\n" + mc_text.substr(1));
  cases.push_back({"a study file holding a Latin-1 byte", study("montecarlo", latin1) + " --dry-run", Want::kError,
                   {latin1 + ":1:21: is not UTF-8 text: byte 0xE9", "save a config as UTF-8"}, {}, {}, {"backslash"}});
  const std::string truncated = w().text_file("truncated", "{\"description\": \"x\xc3\",\n" + mc_text.substr(1));
  cases.push_back({"a study file whose string ends in half a character", study("montecarlo", truncated) + " --dry-run",
                   Want::kError, {":1:19: is not UTF-8 text: byte 0xC3"}, {}, {}, {"backslash"}});
  const std::string surrogate = w().text_file("surrogate", "{\"description\": \"\\ud800\",\n" + mc_text.substr(1));
  cases.push_back({"a lone surrogate escape", study("montecarlo", surrogate) + " --dry-run", Want::kError,
                   {"a lone UTF-16 surrogate escape"}, {}, {}, {"Windows path"}});
  // An integer field states the range it accepts.
  cases.push_back({"a surface axis of 2.5 points",
                   study("surface", w().surface([](Json& j) { j["c_q"]["count"] = 2.5; })) + " --dry-run",
                   Want::kError, {"field 'c_q.count' (value 2.5)", "must be a whole number from 1 to 1000000"}, {},
                   {}, {"2147483647"}});
  cases.push_back({"a surface axis of 3e9 points",
                   study("surface", w().surface([](Json& j) { j["c_q"]["count"] = 3e9; })) + " --dry-run",
                   Want::kError, {"field 'c_q.count'", "must be a whole number from 1 to 1000000"}});
  cases.push_back({"a Monte Carlo bootstrap of 2.5 resamples",
                   study("montecarlo", w().montecarlo([](Json& j) { j["bootstrap"] = 2.5; })) + " --dry-run",
                   Want::kError, {"field 'bootstrap'", "0 (no sd interval), or from 100 to 100000"}});
  // A file of another kind is named for what it is.
  const std::string a_study = w().montecarlo([](Json&) {});
  cases.push_back({"simulate a study file", "simulate --scenario " + a_study + " --out " + w().out(), Want::kError,
                   {"this is a study file", "not a scenario file"}, {}, {}, {"missing required field"}});
  cases.push_back({"simulate the rover file", "simulate --scenario " + source_path("configs/rover.json") + " --out " +
                                                  w().out(),
                   Want::kError, {"this is a rover file", "not a scenario file"}, {}, {}, {"missing required field"}});
  const std::string csv = w().text_file("d1", "# t [s], B_l_z [m]\n0,0.1\n", "csv");
  cases.push_back({"a data CSV given as a study", study("montecarlo", csv) + " --dry-run", Want::kError,
                   {csv + ": a CSV (text data) file", "not a JSON study file"}, {}, {}, {"invalid JSON"}});
  // Grid levels: whole numbers in any form; an array shows the object form.
  const auto grid = [&](const Json& levels) {
    return study("montecarlo", w().montecarlo([&](Json& j) {
             j["design"] = {{"type", "grid"}, {"levels", levels}};
           })) + " --dry-run";
  };
  cases.push_back({"grid levels 1e1", grid(1e1), Want::kRuns, {}});
  cases.push_back({"grid levels 2.5", grid(2.5), Want::kError,
                   {"field 'design.levels' (value 2.5)", "must be a whole number from 1 to 100000000"}});
  cases.push_back({"grid levels as an array", grid(Json::array({3})), Want::kError,
                   {"field 'design.levels'", "\"levels\": {\"c_q\": 3}"}});
  run_table(dir, cases);
}

// A scenario named inside a candidates file or a calibration's data list
// that is no scenario is named with that file and field; a design type's
// alias is one for every study.
TEST_F(Audit, NamedScenariosAndDesignAliases) {
  const std::string dir = w().dir();
  std::vector<Case> cases;
  const std::string calibration = w().calibration([](Json&) {});
  const std::string candidates = w().json_file(
      "cand", Json{{"candidates", {{{"scenario", calibration}, {"rate_hz", 200}, {"noise_sd", 1e-4}}}}});
  cases.push_back({"a candidate's scenario that is a study file",
                   "calibrate --no-plot --study " + calibration + " --next-experiment " + candidates + " --out " +
                       w().out() + " --dry-run",
                   Want::kError, {candidates, "field 'candidates[0].scenario'", "this is a study file"}});
  const std::string broken = w().scenario([](Json& j) { j["duration"] = -1.0; });
  const std::string joint = w().calibration([&](Json& j) {
    j["data"] = {{{"file", j["data"]}, {"scenario", broken}}};
  });
  cases.push_back({"a data entry's scenario that is refused", study("calibrate", joint) + " --dry-run", Want::kError,
                   {joint, "field 'data[0].scenario'", "duration"}});
  cases.push_back({"a Monte Carlo design of type lhs", study("montecarlo", w().montecarlo([](Json& j) {
                     j["design"]["type"] = "lhs";
                   })) + " --dry-run",
                   Want::kRuns, {"latin_hypercube"}});
  // The spread of the from_config preload draws is no input of a run; a QoI
  // label "." names no dataset.
  cases.push_back({"a preload's sd as an uncertain input", study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"]["s_structure.preload_sd[0]"] = {
                         {"distribution", "uniform"}, {"min", 0.01}, {"max", 0.05}};
                   })) + " --dry-run",
                   Want::kError, {"s_structure.preload_sd[0]", "is no input of a run", "M0_11"}});
  cases.push_back({"a QoI labelled '.'", study("montecarlo", w().montecarlo([](Json& j) {
                     j["qoi"] = {{{"name", "t_min"}, {"label", "."}}};
                   })) + " --dry-run",
                   Want::kError, {"'qoi[0].label'", "names no dataset"}});
  // A seed of the full 64-bit range, in the study file, recorded as given.
  const std::string seeded = dir + "/seeded.h5";
  cases.push_back({"the largest seed in a study file",
                   study_args("montecarlo", w().montecarlo([](Json& j) {
                     j["design"]["seed"] = std::numeric_limits<std::uint64_t>::max();
                   }), seeded),
                   Want::kRuns, {"seed 18446744073709551615"}, [=] {
                     const io::Hdf5Reader h5(seeded);
                     return h5.attribute_double("/", "seed") > 1.8e19 ? std::string() : seeded + ": seed not recorded";
                   }});
  // A study's integrator replaces all of the scenario's: no dopri5 min_step
  // carried into its Rosenbrock runs.
  const std::string fenced = w().scenario([](Json& j) {
    j["duration"] = 0.3;  // past the touchdown, where steps shrink
    j["output_rate"] = 1000;
    j["integrator"] = {{"method", "dopri5"}, {"min_step", 0.002}, {"initial_step", 0.002}};
  });
  cases.push_back({"a study's rosenbrock over a scenario's dopri5 step limits",
                   study("montecarlo", w().montecarlo([&](Json& j) {
                     j["scenario"] = fenced;
                     j["integrator"] = {{"method", "rosenbrock"}};
                   })),
                   Want::kRuns, {"2 runs (0 failed)"}});
  run_table(dir, cases);
}

// The NLopt searches' settings where a least-squares fit alone runs; numbers
// written in hexadecimal; grids, integrators, QoI labels and obstacles whose
// settings would not do what they say.
TEST_F(Audit, SearchSettingsHexNumbersGridsAndLabels) {
  const std::string dir = w().dir();
  std::vector<Case> cases;
  const std::string calibration = w().calibration([](Json& j) { j.erase("max_evaluations"); });
  cases.push_back({"a least-squares fit given --max-evaluations",
                   study("calibrate", calibration) + " --max-evaluations 5 --dry-run", Want::kError,
                   {"--max-evaluations 5", "NLopt first search", "--max-iterations"}});
  cases.push_back({"a least-squares fit given --starts", study("calibrate", calibration) + " --starts 2 --dry-run",
                   Want::kError, {"--starts 2", "--algorithm"}});
  cases.push_back({"a least-squares fit with its profiles given --max-evaluations",
                   study("calibrate", calibration) + " --max-evaluations 5 --profile --dry-run", Want::kRuns, {}});
  cases.push_back({"a study file's starts for a least-squares fit",
                   study("calibrate", w().calibration([](Json& j) { j["starts"] = 3; })) + " --dry-run",
                   Want::kError, {"field 'starts'", "NLopt first search"}});
  cases.push_back({"a study file's starts for a first search",
                   study("calibrate", w().calibration([](Json& j) { j["starts"] = 3; })) +
                       " --algorithm LN_BOBYQA --dry-run",
                   Want::kRuns, {"3 start(s) of at most 2 simulations"}});
  cases.push_back({"a study file's search budget for a least-squares fit",
                   study("calibrate", w().calibration([](Json& j) { j["xtol_rel"] = 0.1; })) + " --dry-run",
                   Want::kRuns, {"note: max_evaluations and xtol_rel in", "levenberg_marquardt alone"}});
  cases.push_back({"a hexadecimal damping flag",
                   "simulate --scenario " + w().quick() + " --cq 0x1p-3 --out " + w().out("csv"), Want::kError,
                   {"--cq", "decimal digits", "0x1p-3"}});
  const std::string hex_design = w().text_file("hex", "c_q\n0x1p-3\n", "csv");
  cases.push_back({"a hexadecimal design cell",
                   "evaluate --scenario " + w().quick() + " --design " + hex_design + " --dry-run --out " +
                       w().out("csv"),
                   Want::kError, {hex_design + ":2", "hexadecimal is not read"}});
  const std::string quoted = w().text_file("quoted", "\"c_q\",\"f\"\n0.1,1e4\n", "csv");
  cases.push_back({"a design header quoted as RFC 4180 allows",
                   "evaluate --scenario " + w().quick() + " --design " + quoted + " --dry-run --out " + w().out("csv"),
                   Want::kRuns, {}});
  cases.push_back({"a grid that holds an uncertain input at its midpoint",
                   study("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"]["f"] = {{"distribution", "uniform"}, {"min", 1e3}, {"max", 1e4}};
                     j["design"] = {{"type", "grid"}, {"levels", {{"c_q", 1}, {"f", 2}}}};
                   })) + " --dry-run",
                   Want::kRuns, {"holds 'c_q'", "at its median 0.15", "does not vary"}});
  const std::string tight = w().scenario([](Json& j) {
    j["integrator"] = {{"method", "rosenbrock"}, {"rtol", 1e-9}, {"atol", 1e-9}};
  });
  cases.push_back({"a study's rosenbrock over a scenario's tight rosenbrock",
                   study("montecarlo", w().montecarlo([&](Json& j) {
                     j["scenario"] = tight;
                     j["integrator"] = {{"method", "rosenbrock"}};
                   })) + " --dry-run",
                   Want::kRuns, {"rtol 1e-05"}, {}, {}, {"rtol 1e-09"}});
  cases.push_back({"Sobol' indices from a base that is no power of two",
                   study("sensitivity", w().sensitivity([](Json& j) { j["design"]["samples"] = 12; })) +
                       " --dry-run",
                   Want::kRuns, {"12 Sobol' base points are not a power of two"}});
  cases.push_back({"a QoI label that repeats another QoI's name",
                   study("montecarlo", w().montecarlo([](Json& j) {
                     j["qoi"] = {"B_l_z_min", {{"name", "t_min"}, {"label", "B_l_z_min"}}};
                   })) + " --dry-run",
                   Want::kError, {"'qoi[1]'", "its label 'B_l_z_min' is also the name of qoi[0]"}});
  cases.push_back({"an obstacle top shorter than any grid",
                   "terrain obstacle --top-length 1e-9 --out " + w().out("json"), Want::kError,
                   {"top is 1e-09 m long", "--top-length 0 for a ridge"}, {}, {}, {"spacing of at most"}});
  run_table(dir, cases);
}

// A polynomial chaos of a QoI no input moves: its leave-one-out Q2 is
// 0 / 0, undefined, never 1.
TEST_F(Audit, TheQ2OfAConstantOutputIsUndefined) {
  const std::string dir = w().dir();
  const std::string surrogate = w().json_file(
      "steering", Json{{"type", "surrogate"},
                       {"name", "k"},
                       {"scenario", w().quick()},
                       {"parameters", {{"steering.limit", {{"distribution", "uniform"}, {"min", 1.0}, {"max", 1.7}}}}},
                       {"design", {{"type", "lhs"}, {"samples", 8}, {"seed", 1}}},
                       {"pce", {{"max_degree", 1}, {"bootstrap", 0}}},
                       {"qoi", {"B_l_z_min"}}});
  run_table(dir, {{"a PCE of a QoI no input moves", study_args("surrogate", surrogate, dir + "/k.h5"), Want::kRuns,
                   {"Q2 LOO undefined (constant output)"}, {}, {}, {"Q2 LOO 1.0000"}}});
}

// Numbers that a double cannot hold or JSON does not allow, dashes copied
// from documents before any subcommand, and compare given a column that is
// no height.
TEST_F(Audit, UnderflowsLeadingZerosDashesAndNonHeights) {
  const std::string dir = w().dir();
  std::vector<Case> cases;
  const std::string underflow = w().text_file("underflow", R"({"duration": 1e-400})", "json");
  cases.push_back({"a JSON number below the smallest double", "simulate --scenario " + underflow, Want::kError,
                   {underflow, "field 'duration'", "1e-400 is below the smallest double"}});
  const std::string leading_zero = w().text_file("leading_zero", R"({"duration": 09.5})", "json");
  cases.push_back({"a JSON number with a leading zero", "simulate --scenario " + leading_zero, Want::kError,
                   {leading_zero + ":1:", "'09.5' is not a JSON number", "write 9.5"}, {}, {}, {"missing comma"}});
  cases.push_back({"an em dash before any subcommand", "\xE2\x80\x94study x", Want::kError,
                   {"starts with an em dash (U+2014)"}, {}, {}, {"unknown subcommand"}});
  const std::string run = w().dir() + "/run.csv";
  ASSERT_EQ(run_command(rover_binary() + " simulate --scenario " + w().quick() + " --csv " + run + " --out " +
                        w().dir() + "/run.h5 --no-plot"),
            0);
  for (const std::string column : {"Fn_1", "u_z", "q_chi"})
    cases.push_back({"compare --column " + column + " of a simulated CSV",
                     "compare " + run + " " + run + " --column " + column, Want::kError,
                     {"--column " + column + " is ", "not a height"}});
  // q_z is a height (this drop has no rebound yet, so no deflection error).
  cases.push_back({"compare --column q_z of a simulated CSV", "compare " + run + " " + run + " --column q_z",
                   Want::kError, {"column q_z), the reference, rises by 0 m"}, {}, {}, {"not a height"}});
  run_table(dir, cases);
}

// Under mpirun both ranks check an output whose directories do not exist
// yet, at once: each sees the other's probe directory come and go, and
// neither may refuse it alone (the other would wait for it forever).
TEST_F(Audit, TwoRanksMakeAMissingOutputDirectoryTogether) {
  const std::string study = w().montecarlo([](Json& j) { j["design"]["samples"] = 4; });
  for (int attempt = 0; attempt < 6; ++attempt) {
    const std::string out = w().dir() + "/new" + std::to_string(attempt) + "/deeper/m.h5";
    std::string output;
    EXPECT_EQ(run_command("timeout 60 " + testing::mpiexec() + " -np 2 " + rover_binary() + " montecarlo --study " +
                              study + " --no-plot --out " + out + " 2>&1",
                          &output),
              0)
        << output;
    EXPECT_TRUE(std::filesystem::exists(out)) << output;
  }
  // A directory that cannot be made is refused by rank 0, for every rank.
  std::string output;
  EXPECT_EQ(run_command("timeout 60 " + testing::mpiexec() + " -np 2 " + rover_binary() + " montecarlo --study " +
                            study + " --no-plot --out /proc/rover_no_such_dir/m.h5 2>&1",
                        &output),
            1)
      << output;
  EXPECT_NE(output.find("cannot create the directory '/proc/rover_no_such_dir'"), std::string::npos) << output;
  EXPECT_EQ(output.find("the other ranks did not stop here"), std::string::npos) << output;
}

// A Morris design blind to an effect periodic in half the range, the sd of
// a constant QoI, QoIs an analytic model does not have, held-out runs that
// are the design's own, binary files given as CSV, and seeds in exponent form
// beyond 2^53.
TEST_F(Audit, BlindScreeningConstantsForeignQoisAndBinaryCsv) {
  const std::string dir = w().dir();
  std::vector<Case> cases;
  const std::string morris = w().json_file(
      "morris", Json{{"type", "sensitivity"}, {"method", "morris"}, {"name", "mor"}, {"model", "ishigami"},
                     {"design", {{"trajectories", 20}, {"levels", 4}, {"seed", 1}}}});
  const std::string mor = dir + "/mor.h5";
  cases.push_back({"Morris screening of Ishigami", study_args("sensitivity", morris, mor) + " --no-plot", Want::kRuns,
                   {}, [=] {
                     // x2 enters as 7 sin^2(x2): its mu* is of order 7, not rounding.
                     const double mu_star = io::Hdf5Reader(mor).read_doubles("/morris/y/mu_star").at(1);
                     return mu_star > 1.0 ? std::string() : "mu* of x2 is " + std::to_string(mu_star);
                   }});
  const std::string constant = dir + "/constant.h5";
  cases.push_back({"a Monte Carlo QoI no input moves",
                   study_args("montecarlo", w().montecarlo([](Json& j) {
                     j["parameters"] = {{"drive.tau_max", {{"distribution", "uniform"}, {"min", 3}, {"max", 4}}}};
                     j["design"]["samples"] = 8;
                   }), constant) + " --no-plot",
                   Want::kRuns, {}, [=] {
                     const io::Hdf5Reader h5(constant);
                     const double sd = h5.read_doubles("/summary/t_min/sd").at(0);
                     return sd == 0.0 ? std::string() : "sd of a constant t_min is " + std::to_string(sd);
                   }});
  cases.push_back({"a QoI of the rover asked of an analytic model",
                   study("sensitivity", w().sensitivity([](Json& j) { j["qoi"] = {"B_l_z_min"}; })) + " --dry-run",
                   Want::kError, {"field 'qoi'", "has one output, y"}});
  // Held-out runs made by the surrogate study's own design.
  const Json own{{"type", "surrogate"},
                 {"name", "own"},
                 {"model", "linear"},
                 {"parameters", {{"x1", {{"distribution", "uniform"}, {"min", 0.0}, {"max", 1.0}}}}},
                 {"design", {{"type", "lhs"}, {"samples", 12}, {"seed", 3}}},
                 {"pce", {{"max_degree", 1}, {"bootstrap", 0}}}};
  const std::string trained = dir + "/own.h5";
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " " + study_args("surrogate", w().json_file("own", own), trained) +
                            " --no-plot", &log), 0) << log;
  Json again = own;
  again["held_out"] = {{"file", trained}};
  cases.push_back({"held-out runs that the design will make again",
                   study_args("surrogate", w().json_file("again", again), dir + "/again.h5") + " --dry-run",
                   Want::kError, {"field 'held_out.file'", "12 of the 12 held-out runs", "are training runs too"}});
  cases.push_back({"an HDF5 result given as a design",
                   "evaluate --scenario " + w().quick() + " --design " + trained + " --dry-run --out " + w().out("csv"),
                   Want::kError, {trained, "is an HDF5 file, not text"}, {}, {}, {"\x89"}});
  cases.push_back({"an HDF5 result given as measured data",
                   study("calibrate", w().calibration([](Json&) {})) + " --data " + trained + " --dry-run",
                   Want::kError, {trained}, {}, {}, {"\x89"}});
  cases.push_back({"a seed of 1e16", study("montecarlo", w().montecarlo([](Json&) {})) + " --seed 1e16 --dry-run",
                   Want::kError, {"--seed", "2^53", "write larger ones in digits"}});
  run_table(dir, cases);
}

// On a disk with no room left for a figure, the earlier figure stays, and
// no figure is reported written; a terrain file that does not fit is named
// with the system's reason (where this process may mount a tmpfs).
TEST_F(Audit, AFigureThatDoesNotFitKeepsTheEarlierOne) {
  const std::string dir = w().dir(), disk = dir + "/small";
  fs::create_directory(disk);
  std::string log;
  if (run_command("mount -t tmpfs -o size=1000k tmpfs " + disk + " 2>&1", &log) != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here: " << log;
  const std::string out = disk + "/s.h5", png = disk + "/s.png";
  ASSERT_EQ(run_command(rover_binary() + " simulate --scenario " + w().quick() + " --out " + out, &log), 0) << log;
  const auto result_bytes = fs::file_size(out);
  fs::remove(out);
  fs::remove(disk + "/s_attitude.png");
  // Leave room for the result and a few kilobytes of the figure.
  const auto free_bytes = fs::space(disk).available;
  const auto keep = result_bytes + 16 * 1024;
  ASSERT_GT(free_bytes, keep);
  write_file(disk + "/fill", std::string(free_bytes - keep, 'x'));
  run_table(dir, {{"simulate with no room for its figure",
                   "simulate --scenario " + w().quick() + " --out " + out, Want::kRunsOrFails,
                   {"s.png"}, unchanged(png), {}, {"wrote " + png}}});
  // A terrain file says why it was not written, as the other writers do.
  const std::string terrain = disk + "/t.json";
  run_table(dir, {{"terrain obstacle with no room for its file",
                   "terrain obstacle --spacing 0.005 --out " + terrain, Want::kError,
                   {"t.json", "No space left"}, absent_file(terrain)}});
  EXPECT_EQ(run_command("umount " + disk, &log), 0) << log;
}

// Under mpirun one rank refuses its study file while the other, given a
// good one (an MPMD launch, or files that differ between nodes), goes on to
// the runs: the job ends within seconds, with the refusing rank's reason.
TEST_F(Audit, ARefusalOfOneRankEndsTheWholeJob) {
  const std::string good = w().montecarlo([](Json& j) { j["design"]["samples"] = 16; });
  const std::string bad = w().montecarlo([](Json& j) { j["parameters"]["c_q"]["min"] = -0.1; });
  const std::string good_fit = w().calibration([](Json&) {});
  const std::string bad_fit = w().calibration([](Json& j) { j["initial"]["c_q"] = 5.0; });
  struct Launch {
    std::string rank0, rank1, reason;
  };
  const std::string out = w().out("h5");
  const auto args = [&](const std::string& command, const std::string& file) {
    return command + " --study " + file + " --no-plot --out " + out;
  };
  // A study file one rank refuses, and a command line one rank refuses
  // before any study starts (a flag montecarlo does not have, a subcommand
  // that is none), on either rank.
  for (const Launch& launch :
       {Launch{args("montecarlo", good), args("montecarlo", bad), "narrow the distribution"},
        Launch{args("calibrate", bad_fit), args("calibrate", good_fit), "outside bounds.c_q"},
        Launch{args("montecarlo", good), args("montecarlo", good) + " --integrator rk4", "(rank 1)"},
        Launch{args("montecarlo", good) + " --integrator rk4", args("montecarlo", good), "--integrator"},
        Launch{args("montecarlo", good), "montecarl --study " + good, "unknown subcommand 'montecarl'"},
        Launch{args("montecarlo", good), args("montecarlo", good) + " --help", "was given --help"},
        Launch{args("montecarlo", good) + " --help", args("montecarlo", good), "Usage:"}}) {
    const Outcome o = mpmd_launch(launch.rank0, launch.rank1);
    EXPECT_NE(o.status, 0) << o.output;
    EXPECT_NE(o.status, 124) << "the job hung:\n" << o.output;
    EXPECT_NE(o.output.find(launch.reason), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("the other ranks did not stop here"), std::string::npos) << o.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << o.output;
  }
  // An environment MPI cannot start with, on rank 1 only: that rank says so.
  const Outcome o = mpmd_launch(args("montecarlo", good), args("montecarlo", good),
                                "OMPI_MCA_btl_vader_eager_limit=abc");
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find("error: (rank 1) the environment variable OMPI_MCA_btl_vader_eager_limit='abc'"),
            std::string::npos) << o.output;
  EXPECT_FALSE(std::filesystem::exists(out)) << o.output;
}

// Output paths holding a control character (typed by a slip of the shell's
// quoting) are refused for every kind of output; a UTF-8 name is written.
TEST_F(Audit, OutputNamesWithControlCharactersAreRefused) {
  const std::string dir = w().dir();
  const auto named = [&](const std::string& printf_format) { return "\"$(printf '" + dir + "/" + printf_format + "')\""; };
  std::vector<Case> cases;
  cases.push_back({"--out with a newline", "simulate --no-plot --scenario " + w().quick() + " --out " + named("a\\nb.h5"),
                   Want::kError, {"--out", "control character (byte 0x0a"}, absent_file(dir + "/a\nb.h5")});
  cases.push_back({"--csv with a tab", "simulate --no-plot --scenario " + w().quick() + " --csv " + named("t\\tx.csv"),
                   Want::kError, {"--csv", "byte 0x09"}, absent_file(dir + "/t\tx.csv")});
  cases.push_back({"a study's --out with an escape",
                   "montecarlo --no-plot --study " + w().montecarlo([](Json&) {}) + " --out " + named("e\\033.h5"),
                   Want::kError, {"--out", "byte 0x1b"}, absent_file(dir + "/e\033.h5")});
  cases.push_back({"terrain --out with DEL", "terrain obstacle --out " + named("d\\177.json"), Want::kError,
                   {"--out", "byte 0x7f"}, absent_file(dir + "/d\177.json")});
  cases.push_back({"a UTF-8 name", "simulate --no-plot --scenario " + w().quick() + " --out " + named("r\\303\\251.h5"),
                   Want::kRuns, {}, [=] { return fs::exists(dir + "/r\u00e9.h5") ? "" : std::string("no r\u00e9.h5"); }});
  run_table(dir, cases);
}

// A ranking draws no figure: a candidate's rover file named like a plot of
// --out (<stem>_1.png) is not refused as one that plot would replace; the
// ranking's result itself still may not replace it.
TEST_F(Audit, ARankingIsNotRefusedForAPlotItNeverDraws) {
  const std::string dir = w().dir();
  const LandingDrop drop = landing_drop(w());
  const std::string fit = landing_fit(w(), drop, 1.0);
  const std::string png_rover = dir + "/nr_1.png";
  fs::copy_file(source_path("configs/rover.json"), png_rover);
  const std::string scenario = w().scenario([&](Json& j) {
    j["duration"] = 0.3;
    j["rover"] = png_rover;
  });
  const std::string candidates = w().json_file(
      "cands", Json{{"candidates", {{{"scenario", scenario}, {"rate_hz", 500}, {"noise_sd", 1e-4}}}}});
  std::vector<Case> cases;
  cases.push_back({"a ranking beside a rover file named like its plot",
                   "calibrate --study " + fit + " --next-experiment " + candidates + " --out " + dir + "/nr.h5 --dry-run",
                   Want::kRuns, {}, unchanged(png_rover)});
  cases.push_back({"a ranking over that rover file",
                   "calibrate --study " + fit + " --next-experiment " + candidates + " --out " + png_rover + " --dry-run",
                   Want::kError, {"--out", "nr_1.png"}, unchanged(png_rover)});
  run_table(dir, cases);
}

// A plotter that never returns is ended after ROVER_PLOT_TIMEOUT seconds:
// the result stays written, the figure is reported not drawn; a time limit
// that is not a number of seconds is refused before any run.
TEST_F(Audit, APlotterThatNeverReturnsIsEnded) {
  const std::string dir = w().dir(), bin = dir + "/hung";
  fs::create_directory(bin);
  write_file(bin + "/gnuplot", "#!/bin/sh\nexec /bin/sleep 100\n");
  fs::permissions(bin + "/gnuplot", fs::perms::owner_all);
  const std::string hung = "PATH=" + bin + ":$PATH";
  const std::string out = dir + "/hung.h5";
  std::vector<Case> cases;
  cases.push_back({"simulate with a plotter that never returns",
                   "simulate --scenario " + w().quick() + " --out " + out, Want::kRuns,
                   {"gnuplot did not finish within 1 s", "hung.png not written"},
                   [=] { return fs::exists(out) && !fs::exists(dir + "/hung.png") ? "" : std::string("files"); },
                   hung + " ROVER_PLOT_TIMEOUT=1"});
  const std::string refused = dir + "/refused.h5";
  cases.push_back({"a time limit of no seconds",
                   "montecarlo --study " + w().montecarlo([](Json&) {}) + " --out " + refused, Want::kError,
                   {"ROVER_PLOT_TIMEOUT='0'", "from 1 to 86400", "--no-plot"}, absent_file(refused),
                   "ROVER_PLOT_TIMEOUT=0"});
  cases.push_back({"a time limit in words", "simulate --scenario " + w().quick() + " --out " + dir + "/words.h5",
                   Want::kError, {"ROVER_PLOT_TIMEOUT='ten'", "--no-plot"}, absent_file(dir + "/words.h5"),
                   "ROVER_PLOT_TIMEOUT=ten"});
  run_table(dir, cases);
}

// A surrogate trained on a file whose QoIs of the same names were computed
// otherwise (rms_vs against another reference curve or time offset, a
// settling time in another band) is refused before its fit, naming the QoI;
// the same definitions train.
TEST_F(Audit, TrainingRunsOfAnotherQoiDefinitionAreRefused) {
  const LandingDrop drop = landing_drop(w());
  const std::string other_reference = w().out("csv");
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " synthesize --scenario " + drop.scenario + " --cq 0.1 --out " +
                            other_reference, &log), 0) << log;
  const Json parameters = {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.3}}}};
  const Json made_qois = Json::array({Json{{"name", "rms_vs"}, {"reference", drop.data}},
                                      Json{{"name", "settling_time"}, {"band", 0.002}}});
  const std::string runs = w().out();
  ASSERT_EQ(run_command(rover_binary() + " " + study_args("montecarlo", w().montecarlo([&](Json& j) {
              j["scenario"] = drop.scenario;
              j["parameters"] = parameters;
              j["design"] = {{"type", "latin_hypercube"}, {"samples", 12}, {"seed", 2}};
              j["qoi"] = made_qois;
            }), runs), &log), 0) << log;
  auto surrogate = [&](const Json& qois) {
    return study("surrogate", w().json_file("surrogate", Json{{"type", "surrogate"}, {"name", "pce"},
                                                              {"scenario", drop.scenario},
                                                              {"training", {{"file", runs}}},
                                                              {"parameters", parameters},
                                                              {"pce", {{"max_degree", 2}, {"bootstrap", 0}}},
                                                              {"qoi", qois}}));
  };
  std::vector<Case> cases;
  cases.push_back({"rms_vs against another reference curve",
                   surrogate(Json::array({Json{{"name", "rms_vs"}, {"reference", other_reference}}})), Want::kError,
                   {"QoI 'rms_vs'", "reference curve", "train on runs of the same QoI"}});
  cases.push_back({"rms_vs at another time offset",
                   surrogate(Json::array({Json{{"name", "rms_vs"}, {"reference", drop.data}, {"time_offset", 0.01}}})),
                   Want::kError, {"QoI 'rms_vs'", "time offset 0.01 s"}});
  cases.push_back({"a settling time in another band", surrogate(Json::array({"settling_time"})), Want::kError,
                   {"QoI 'settling_time'", "band 0.002 m", "defines it as settling_time, band"}});
  cases.push_back({"the same definitions", surrogate(made_qois), Want::kRuns, {}});
  run_table(w().dir(), cases);
}

// A CSV output's temporary file, <csv>.partial, never replaces an input of
// that name: a scenario, a design, a saved surrogate.
TEST_F(Audit, ACsvTemporaryNeverReplacesAnInput) {
  const std::string dir = w().dir();
  const std::string scenario = dir + "/o.csv.partial";
  fs::copy_file(w().quick(), scenario);
  const Json linear{{"type", "surrogate"},
                    {"name", "lin"},
                    {"model", "linear"},
                    {"parameters", {{"x1", {{"distribution", "uniform"}, {"min", 0.0}, {"max", 1.0}}}}},
                    {"design", {{"type", "lhs"}, {"samples", 12}, {"seed", 3}}},
                    {"pce", {{"max_degree", 1}, {"bootstrap", 0}}}};
  const std::string model = dir + "/m.csv.partial", trained = dir + "/lin.h5";
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " " + study_args("surrogate", w().json_file("lin", linear), trained) +
                            " --no-plot", &log), 0) << log;
  fs::copy_file(trained, model);
  const std::string design = dir + "/d.csv.partial";
  write_file(design, "x1\n0.5\n");
  std::vector<Case> cases;
  cases.push_back({"synthesize over its scenario's name + .partial",
                   "synthesize --scenario " + scenario + " --out " + dir + "/o.csv", Want::kError,
                   {"--out", "o.csv.partial"}, unchanged(scenario)});
  cases.push_back({"simulate --csv over its scenario's name + .partial",
                   "simulate --no-plot --scenario " + scenario + " --out " + w().out() + " --csv " + dir + "/o.csv",
                   Want::kError, {"--csv", "o.csv.partial"}, unchanged(scenario)});
  cases.push_back({"a prediction over its design's name + .partial",
                   "surrogate --predict " + trained + " --design " + design + " --csv " + dir + "/d.csv",
                   Want::kError, {"--csv", "d.csv.partial"}, unchanged(design)});
  cases.push_back({"a prediction over its model's name + .partial",
                   "surrogate --predict " + model + " --design " + w().text_file("x", "x1\n0.2\n", "csv") +
                       " --csv " + dir + "/m.csv",
                   Want::kError, {"--csv", "m.csv.partial"}, unchanged(model)});
  run_table(dir, cases);
}


// A surrogate trained on a result file runs nothing, so --resume and
// --checkpoint-every have nothing to act on; a fitted parameter the files
// give no value of needs its start; the runs' wall-time limit is no fit
// parameter.
TEST_F(Audit, FlagsAndFitsWithNothingToActOnAreRefused) {
  const std::string runs = w().out();
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " " + study_args("montecarlo", w().montecarlo([](Json& j) {
              j["design"]["samples"] = 6;
            }), runs), &log), 0) << log;
  const std::string trained = w().json_file("surrogate", Json{
      {"type", "surrogate"}, {"name", "g"}, {"scenario", w().quick()}, {"surrogate", "gp"},
      {"training", {{"file", runs}}},
      {"parameters", {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}}}},
      {"qoi", {"t_min"}}});
  std::vector<Case> cases;
  cases.push_back({"surrogate on a file with --resume", study_args("surrogate", trained, w().out()) + " --resume",
                   Want::kError, {"--resume", "trains on the runs of", "nothing to resume"}});
  cases.push_back({"surrogate on a file with --checkpoint-every",
                   study_args("surrogate", trained, w().out()) + " --checkpoint-every 5", Want::kError,
                   {"--checkpoint-every", "keeps no checkpoint"}});
  cases.push_back({"a fitted parameter without a value in the files",
                   study("calibrate", w().calibration([](Json& j) {
                           j["fit"] = {"c_q", "scenario.forward_speed"};
                           j["bounds"]["scenario.forward_speed"] = {0.0, 0.1};
                         })) + " --dry-run",
                   Want::kError, {"'initial.scenario.forward_speed'", "give one inside the bounds"}, {}, {},
                   {"nan"}});
  cases.push_back({"the wall-time limit fitted", study("calibrate", w().calibration([](Json& j) {
                                                   j["fit"] = {"c_q", "scenario.wall_time_budget"};
                                                   j["bounds"]["scenario.wall_time_budget"] = {1.0, 10.0};
                                                 })) + " --dry-run",
                   Want::kError, {"wall-time limit", "fit a model parameter"}});
  run_table(w().dir(), cases);
}


// Ranks launched with other study files or flags (an MPMD launch) would mix
// their runs into one result: every rank refuses before any run.
TEST_F(Audit, RanksGivenOtherStudiesRefuseTogether) {
  const std::string mc = w().montecarlo([](Json& j) { j["design"]["samples"] = 8; });
  const std::string mc_more = w().montecarlo([](Json& j) { j["design"]["samples"] = 9; });
  struct Launch {
    std::string rank0, rank1;
  };
  const std::string out = w().out("h5"), other_out = w().out("h5");
  // Another study, seed or size; another --out; or flags that decide whether
  // and how it runs: --dry-run on one rank left the other waiting forever.
  for (const Launch& launch : {Launch{"--study " + mc, "--study " + mc_more},
                               Launch{"--study " + mc + " --seed 3", "--study " + mc + " --seed 4"},
                               Launch{"--study " + mc, "--study " + mc + " --samples 6"},
                               Launch{"--study " + mc, "--study " + mc + " --dry-run"},
                               Launch{"--study " + mc + " --dry-run", "--study " + mc},
                               Launch{"--study " + mc, "--study " + mc + " --restart"}}) {
    const auto rank = [&](const std::string& flags) { return "montecarlo --no-plot --out " + out + " " + flags; };
    const Outcome o = mpmd_launch(rank(launch.rank0), rank(launch.rank1));
    EXPECT_EQ(o.status, 1) << o.output;
    EXPECT_NE(o.output.find("not all given the same study"), std::string::npos) << o.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << o.output;
  }
  const Outcome o = mpmd_launch("montecarlo --no-plot --study " + mc + " --out " + out,
                                "montecarlo --no-plot --study " + mc + " --out " + other_out);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find("not all given the same study"), std::string::npos) << o.output;
  EXPECT_FALSE(std::filesystem::exists(out) || std::filesystem::exists(other_out)) << o.output;
}

// Settings no run can use, found before the runs (and by --dry-run): an
// rk4 step that does not divide the scenario's output period, given by a
// study's "integrator", and the runs' wall-time limit as an uncertain input.
TEST_F(Audit, SettingsNoRunCanUseAreRefusedBeforeTheRuns) {
  const Json rk4_off_period = {{"method", "rk4"}, {"fixed_step", 0.0015}};  // the quick drop records every 5 ms
  const std::vector<std::string> off_period = {"'integrator'", "rk4: fixed_step 0.0015 s does not divide the output "
                                               "period 0.005 s", "output rate 200 Hz"};
  std::vector<Case> cases;
  cases.push_back({"montecarlo with an rk4 step off the output period",
                   study("montecarlo", w().montecarlo([&](Json& j) { j["integrator"] = rk4_off_period; })) +
                       " --dry-run",
                   Want::kError, off_period});
  cases.push_back({"calibration with an rk4 step off the output period",
                   study("calibrate", w().calibration([&](Json& j) { j["integrator"] = rk4_off_period; })) +
                       " --dry-run",
                   Want::kError, off_period});
  cases.push_back({"surface with an rk4 step off the output period",
                   study("surface", w().surface([&](Json& j) { j["integrator"] = rk4_off_period; })) + " --dry-run",
                   Want::kError, off_period});
  cases.push_back({"montecarlo with an rk4 step on the output period",
                   study("montecarlo", w().montecarlo([&](Json& j) {
                     j["integrator"] = {{"method", "rk4"}, {"fixed_step", 0.001}};
                   })) + " --dry-run",
                   Want::kRuns, {"dry run"}});
  const Json budget = {{"distribution", "uniform"}, {"min", 10.0}, {"max", 100.0}};
  cases.push_back({"montecarlo over the wall-time limit",
                   study("montecarlo", w().montecarlo([&](Json& j) {
                     j["parameters"]["scenario.wall_time_budget"] = budget;
                   })) + " --dry-run",
                   Want::kError, {"'parameters.scenario.wall_time_budget'", "wall-time limit", "no physics"}});
  cases.push_back({"Sobol' indices of the wall-time limit",
                   study("sensitivity", w().json_file("sens", Json{
                       {"type", "sensitivity"}, {"method", "sobol"}, {"name", "s"}, {"scenario", w().quick()},
                       {"parameters", {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.2}}},
                                       {"scenario.wall_time_budget", budget}}},
                       {"design", {{"type", "sobol"}, {"samples", 8}, {"seed", 1}}},
                       {"qoi", {"t_min"}}})) + " --dry-run",
                   Want::kError, {"'parameters.scenario.wall_time_budget'", "wall-time limit"}});
  // --integrator rk4 takes rk4's default step, 1e-5 s: no divisor of 1/300 s.
  cases.push_back({"evaluate --integrator rk4 at 300 Hz",
                   "evaluate --scenario " + w().scenario([](Json& j) { j["output_rate"] = 300; }) +
                       " --qoi t_min --out " + w().out("csv") + " --integrator rk4 --design " +
                       w().text_file("design", "c_q\n0.1\n", "csv"),
                   Want::kError, {"--integrator rk4 at its default settings", "does not divide the output period"}});
  run_table(w().dir(), cases);
}

// Inputs that are no regular file (a pipe nothing writes to, an endless
// device) are refused before they are opened, as every other input is: a
// design, a compared curve, or a design to predict at.
TEST_F(Audit, DesignsAndCurvesThatAreNoFileAreRefused) {
  const std::string pipe = w().dir() + "/pipe.csv";
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  const std::string data = source_path("configs/data/drop_horizontal_synthetic.csv");
  const std::string evaluate = "evaluate --scenario " + w().quick() + " --qoi t_min --out " + w().out("csv");
  std::vector<Case> cases;
  cases.push_back({"evaluate --design a pipe", evaluate + " --design " + pipe, Want::kError,
                   {pipe + ": is a pipe, not a design file"}});
  cases.push_back({"evaluate --design /dev/zero", evaluate + " --design /dev/zero", Want::kError,
                   {"/dev/zero: is a device"}});
  cases.push_back({"compare a pipe with data", "compare " + pipe + " " + data, Want::kError,
                   {pipe + ": is a pipe, not a curve file"}});
  cases.push_back({"compare data with a pipe", "compare " + data + " " + pipe, Want::kError,
                   {pipe + ": is a pipe"}});
  cases.push_back({"compare /dev/zero with data", "compare /dev/zero " + data, Want::kError,
                   {"/dev/zero: is a device"}});
  const auto trained_on = [&](const std::string& file) {
    return study("surrogate", w().json_file("surrogate", Json{{"type", "surrogate"}, {"name", "p"},
                                                             {"surrogate", "pce"}, {"model", "ishigami"},
                                                             {"training", {{"file", file}}}}));
  };
  cases.push_back({"a surrogate trained on a pipe", trained_on(pipe), Want::kError,
                   {"'training.file'", pipe + ": is a pipe"}});
  cases.push_back({"a surrogate trained on no file", trained_on(w().dir() + "/none.h5"), Want::kError,
                   {"'training.file'", "none.h5: no such file"}});
  run_table(w().dir(), cases);
}

// A bootstrap of a few pick-freeze groups or Morris trajectories gives
// intervals that look precise and cover nothing (2 units have 3 distinct
// resamples): none are printed or written, and the study says why; 10 groups
// get their intervals.
TEST_F(Audit, IntervalsNeedUnitsToResample) {
  const std::string ishigami = source_path("configs/studies/sobol_ishigami.json");
  const std::string two_groups = w().out();
  std::vector<Case> cases;
  cases.push_back({"Sobol' indices of Ishigami from 2 groups",
                   "sensitivity --no-plot --study " + ishigami + " --samples 2 --out " + two_groups, Want::kRuns,
                   {"no intervals: 2 groups are too few to resample (at least 10)", "use more samples"}, {}, {},
                   {"% intervals"}});
  // Ishigami from 8 groups of seed 1: x3's S1 comes out -0.4, an index no variance share can have.
  cases.push_back({"Sobol' indices of Ishigami from 8 groups",
                   "sensitivity --no-plot --study " + ishigami + " --samples 8 --out " + w().out(), Want::kRuns,
                   {"the indices themselves are sampling noise at this size", "x3 S1 -0.", " below 0"}});
  cases.push_back({"Sobol' indices of Ishigami from 10 groups",
                   "sensitivity --no-plot --study " + ishigami + " --samples 10 --out " + w().out(), Want::kRuns,
                   {"95 % intervals"}, {}, {}, {"too few to resample"}});
  // Morris: mu* intervals need as many trajectories, and curves are not screened.
  const auto morris = [&](int trajectories) {
    return study("sensitivity", w().sensitivity([&](Json& j) {
      j["method"] = "morris";
      j["design"] = {{"trajectories", trajectories}, {"levels", 4}, {"seed", 1}};
    }));
  };
  cases.push_back({"Morris mu* from 2 trajectories", morris(2), Want::kRuns,
                   {"no intervals: 2 trajectories are too few to resample (at least 10)", "use more trajectories"}});
  cases.push_back({"Morris mu* from 10 trajectories", morris(10), Want::kRuns, {}, {}, {}, {"no intervals"}});
  const Json morris_of_a_curve{
      {"type", "sensitivity"}, {"method", "morris"}, {"name", "m"}, {"scenario", w().quick()},
      {"parameters", {{"c_q", {{"distribution", "uniform"}, {"min", 0.1}, {"max", 0.3}}},
                      {"f", {{"distribution", "log_uniform"}, {"min", 1e3}, {"max", 1e5}}}}},
      {"design", {{"trajectories", 4}, {"levels", 4}, {"seed", 1}}}, {"qoi", {"B_l_z_min"}}, {"channels", {"B_l_z"}}};
  cases.push_back({"Morris of a channel", study("sensitivity", w().json_file("morris", morris_of_a_curve)) + " --dry-run",
                   Want::kError, {"'channels'", "\"morris\" screens the QoIs only"}});
  run_table(w().dir(), cases);
  const io::Hdf5Reader result(two_groups);
  for (const double bound : result.read_doubles("/indices/y/S1_lower")) EXPECT_TRUE(std::isnan(bound));
}

// Indices and surrogates that predict worse than the mean of their runs
// (Q2 < 0), or no indices for want of runs, are results not to be trusted:
// status 2, and said so; so is a prediction from such a model.
TEST_F(Audit, SurrogatesWorseThanTheMeanAreNotToBeTrusted) {
  const std::string ishigami = source_path("configs/studies/pce_ishigami.json");
  std::vector<Case> cases;
  cases.push_back({"PCE indices of Ishigami from 15 runs (Q2_LOO -0.30)",
                   "sensitivity --no-plot --study " + ishigami + " --samples 15 --out " + w().out(), Want::kAllFailed,
                   {"predicts worse than the mean of its runs (leave-one-out Q2 -0.303, ", "exit status 2"}});
  cases.push_back({"PCE of Ishigami from 17 runs: no term beyond the constant",
                   "sensitivity --no-plot --study " + ishigami + " --samples 17 --out " + w().out(), Want::kAllFailed,
                   {"the QoI varies over the 17 runs", "selected no term beyond the constant"}});
  cases.push_back({"PCE indices of Ishigami from 6 runs (5 terms, Q2_LOO 0.999)",
                   "sensitivity --no-plot --study " + ishigami + " --samples 6 --out " + w().out(), Want::kAllFailed,
                   {"(5 terms selected on 6 runs) cannot be cross-validated (a fold of 6 runs leaves 5",
                    "give at least 10 runs", "exit status 2"}});
  cases.push_back({"PCE indices of Ishigami from 14 runs (12 terms, Q2_LOO 0.94)",
                   "sensitivity --no-plot --study " + ishigami + " --samples 14 --out " + w().out(), Want::kAllFailed,
                   {"Q2_LOO 0.9421, 10-fold cross-validated Q2 (terms re-selected) -0.7919",
                    "predicts worse than the mean", "exit status 2"}});
  const auto ishigami_of_seed = [&](int seed) {
    std::string text = file_bytes(ishigami);
    text.replace(text.find("\"seed\": 1"), 9, "\"seed\": " + std::to_string(seed));
    return "sensitivity --no-plot --study " + w().text_file("pce_seed", text, "json");
  };
  cases.push_back({"PCE indices of Ishigami from 20 runs of seed 3 (cross-validated Q2 0.09)",
                   ishigami_of_seed(3) + " --samples 20 --out " + w().out(), Want::kAllFailed,
                   {"falls short of q2_threshold", "< 0.95", "exit status 2"}});
  // Cross-validated Q2 0.66 and 0.75: total indices 0.2 from the exact ones.
  cases.push_back({"PCE indices of Ishigami from 30 runs of seed 5", ishigami_of_seed(5) + " --samples 30 --out " + w().out(),
                   Want::kAllFailed, {"falls short of q2_threshold", "exit status 2"}});
  cases.push_back({"PCE indices of Ishigami from 40 runs of seed 6", ishigami_of_seed(6) + " --samples 40 --out " + w().out(),
                   Want::kAllFailed, {"falls short of q2_threshold", "exit status 2"}});
  cases.push_back({"PCE indices of Ishigami from 100 runs", "sensitivity --no-plot --study " + ishigami +
                                                                " --samples 100 --out " + w().out(),
                   Want::kRuns, {}, {}, {}, {"worse than the mean"}});
  run_table(w().dir(), cases);
  // A surrogate of Ishigami on 15 runs, and a prediction from it.
  const std::string model = w().out();
  const Json surrogate{{"type", "surrogate"}, {"name", "p"}, {"surrogate", "pce"}, {"model", "ishigami"},
                       {"design", {{"type", "lhs"}, {"samples", 15}, {"seed", 1}}},
                       {"pce", {{"max_degree", 14}, {"bootstrap", 0}}}};
  Outcome o;
  o.status = run_command(rover_binary() + " " + study_args("surrogate", w().json_file("surrogate", surrogate), model) +
                             " 2>&1",
                         &o.output);
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("predicts worse than the mean"), std::string::npos) << o.output;
  const std::string design = w().text_file("points", "x1,x2,x3\n0.1,0.2,0.3\n", "csv");
  o.status = run_command(rover_binary() + " surrogate --predict " + model + " --design " + design + " --csv " +
                             w().out("csv") + " 2>&1",
                         &o.output);
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("WARNING: the surrogate of 'y' predicts worse than the mean"), std::string::npos)
      << o.output;
}

// A surrogate of few runs has a leave-one-out Q2 that can mean nothing (its
// true Q2 on Ishigami is below 0): too few runs to cross-validate it with
// its terms re-selected, or a cross-validated Q2 below 0.5, and it is not to
// be trusted, nor its predictions; with enough runs it is.
TEST_F(Audit, ASurrogateWithAboutAsManyTermsAsRunsIsNotTrusted) {
  const std::string model = w().out();
  const auto surrogate = [](int samples, double held_out_fraction, int seed = 1) {
    Json spec{{"type", "surrogate"}, {"name", "p"}, {"surrogate", "pce"}, {"model", "ishigami"},
              {"design", {{"type", "lhs"}, {"samples", samples}, {"seed", seed}}},
              {"pce", {{"max_degree", 14}, {"bootstrap", 0}}}};
    if (held_out_fraction > 0.0) spec["held_out"] = {{"fraction", held_out_fraction}};
    return spec;
  };
  Outcome o;
  o.status = run_command(rover_binary() + " " +
                             study_args("surrogate", w().json_file("surrogate", surrogate(6, 0.0)), model) + " 2>&1",
                         &o.output);
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("(5 terms selected on 6 runs) cannot be cross-validated"), std::string::npos) << o.output;
  const std::string design = w().text_file("points", "x1,x2,x3\n0.1,0.2,0.3\n", "csv");
  o.status = run_command(rover_binary() + " surrogate --predict " + model + " --design " + design + " --csv " +
                             w().out("csv") + " 2>&1",
                         &o.output);
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("WARNING: the surrogate of 'y' (5 terms selected on 6 runs)"), std::string::npos)
      << o.output;
  // 14 runs of seed 3 select 3 terms with Q2_LOO 0.21; re-selected, the Q2 is below 0.
  const std::string few_terms = w().out();
  o.status = run_command(rover_binary() + " " +
                             study_args("surrogate", w().json_file("surrogate", surrogate(14, 0.0, 3)), few_terms) +
                             " 2>&1",
                         &o.output);
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("Q2 LOO 0.2091, 10-fold cross-validated Q2 (terms re-selected) -0.8658"), std::string::npos)
      << o.output;
  o.status = run_command(rover_binary() + " surrogate --predict " + few_terms + " --design " + design + " --csv " +
                             w().out("csv") + " 2>&1",
                         &o.output);
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("predicts worse than the mean"), std::string::npos) << o.output;
  // 100 training runs: enough runs per term, and a held-out Q2 near 1.
  o.status = run_command(rover_binary() + " " +
                             study_args("surrogate", w().json_file("surrogate", surrogate(125, 0.2)), w().out()) +
                             " 2>&1",
                         &o.output);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_EQ(o.output.find("not to be trusted"), std::string::npos) << o.output;
  // A Gaussian process on 6 runs: Q2_LOO 0.97 with length-scales fitted to them; re-estimated, -0.45.
  Json gp = surrogate(6, 0.0, 3);
  gp["surrogate"] = "gp";
  gp.erase("pce");
  const std::string gp_model = w().out();
  o.status = run_command(rover_binary() + " " + study_args("surrogate", w().json_file("gp", gp), gp_model) + " 2>&1",
                         &o.output);
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("6-fold cross-validated Q2 (length-scales re-estimated) -0.45"), std::string::npos)
      << o.output;
  o.status = run_command(rover_binary() + " surrogate --predict " + gp_model + " --design " + design + " --csv " +
                             w().out("csv") + " 2>&1",
                         &o.output);
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("predicts worse than the mean"), std::string::npos) << o.output;
}

// An effective sample size above the kept draws (a tau below 1, estimated
// from a short chain) is said to be one, never printed as if it were real.
TEST_F(Audit, AnEffectiveSampleSizeAboveTheDrawsIsExplained) {
  const Json mcmc = {{"walkers", 4}, {"steps", 20}, {"discard", 10}, {"target_ess", 0}, {"predictive_draws", 0}};
  const std::string posterior = study("calibrate", w().calibration([&](Json& j) {
    j["max_evaluations"] = 40;
    j["method"] = "mcmc";
    j["mcmc"] = mcmc;
  }));
  Outcome o;
  o.status = run_command(rover_binary() + " " + posterior + " 2>&1", &o.output);
  EXPECT_EQ(o.status, 2) << o.output;  // 20 steps: not valid
  constexpr double kKeptDraws = 4 * (20 - 10);
  std::istringstream lines(o.output);
  int ess_lines = 0, above_the_draws = 0;
  for (std::string line; std::getline(lines, line);) {
    const std::size_t at = line.find(", ESS ");
    if (at == std::string::npos) continue;
    ++ess_lines;
    const double ess = std::stod(line.substr(at + 6));
    above_the_draws += ess > kKeptDraws;
    EXPECT_EQ(ess > kKeptDraws, line.find("more than the 40 kept draws") != std::string::npos) << line;
  }
  EXPECT_EQ(ess_lines, 2) << o.output;  // c_q and noise_sd
  EXPECT_GT(above_the_draws, 0) << "this seed no longer gives an ESS above the draws:\n" << o.output;
}


// A posterior run for a fixed number of steps ("target_ess": 0) is still
// judged by the study's max_rhat: walkers whose nested R-hat reaches it have
// not mixed, and the posterior is NOT VALID; a bar they pass lets it stand.
// The quick drop is a free fall, so it is gravity that its data determine.
TEST_F(Audit, AFixedLengthPosteriorIsJudgedByItsMaxRhat) {
  const auto posterior = [&](double max_rhat, const std::string& out) {
    return study_args("calibrate", w().calibration([&](Json& j) {
      j["fit"] = {"gravity"};
      j["bounds"] = {{"gravity", {5.0, 15.0}}, {"time_offset", {-0.2, 0.2}}};
      j["initial"] = {{"gravity", 9.0}};
      j.erase("max_evaluations");
      j["method"] = "mcmc";
      j["mcmc"] = {{"walkers", 4}, {"steps", 200}, {"discard", 10}, {"target_ess", 0},
                   {"predictive_draws", 0}, {"max_rhat", max_rhat}};
    }), out);
  };
  const std::string strict = w().out(), loose = w().out();
  Outcome o;
  o.status = run_command(rover_binary() + " " + posterior(1.0001, strict) + " 2>&1", &o.output);
  EXPECT_EQ(o.status, 2) << o.output;
  for (const std::string& text :
       {"NOT VALID", "ran a fixed 200 steps and the walkers have not mixed: nested R-hat gravity", "(max_rhat 1.0001)"})
    EXPECT_NE(o.output.find(text), std::string::npos) << text << "\n" << o.output;
  EXPECT_EQ(io::Hdf5Reader(strict).attribute_integer("/diagnostics", "mixed"), 0);
  o.status = run_command(rover_binary() + " " + posterior(2.0, loose) + " 2>&1", &o.output);
  EXPECT_EQ(o.status, 0) << o.output;  // 190 kept steps of an independence sampler: long enough
  EXPECT_EQ(io::Hdf5Reader(loose).attribute_integer("/diagnostics", "mixed"), 1);
}


// What was typed is named with what was meant: a subcommand that does not
// exist, an option whose first word is right, a result of another study given
// as a model; and a design of quoted numbers, as spreadsheets save one, runs.
TEST_F(Audit, TypedNamesGetWhatWasMeantAndQuotedNumbersRead) {
  std::vector<Case> cases;
  cases.push_back({"terrain flat", "terrain flat --out " + w().out("json"), Want::kError,
                   {"'flat' is not a subcommand of terrain", "obstacle"}, {}, {}, {"a subcommand is required"}});
  cases.push_back({"kinematics --crab-angle", "kinematics --mode parallel --v 0.1 --crab-angle 10", Want::kError,
                   {"unknown option '--crab-angle'", "did you mean '--crab-deg'?"}});
  const std::string quoted = w().text_file("quoted", "\"c_q\",\"f\"\n\"0.25\",\" 8000 \"\n", "csv");
  cases.push_back({"a design of quoted numbers",
                   "evaluate --scenario " + w().quick() + " --qoi t_min --design " + quoted + " --out " + w().out("csv"),
                   Want::kRuns});
  const std::string monte_carlo = w().out("h5");
  ASSERT_EQ(run_command(rover_binary() + " " + study_args("montecarlo", w().montecarlo([](Json&) {}), monte_carlo)), 0);
  cases.push_back({"surrogate --predict from a Monte Carlo result",
                   "surrogate --predict " + monte_carlo + " --design " + quoted + " --csv " + w().out("csv"),
                   Want::kError, {monte_carlo + ": a montecarlo result, not a surrogate model"}, {}, {}, {"damaged"}});
  run_table(w().dir(), cases);
}


// A calibration runs on the stiff integrator unless the study chooses one,
// whatever its scenario says; the first line says so, and names the
// scenario's integrator it does not use.
TEST_F(Audit, ACalibrationSaysWhichIntegratorItRunsOn) {
  const std::string dopri5 = w().scenario([](Json& j) { j["integrator"] = {{"method", "dopri5"}}; });
  std::vector<Case> cases;
  cases.push_back({"a calibration of a dopri5 scenario",
                   study("calibrate", w().calibration([&](Json& j) { j["scenario"] = dopri5; })) + " --dry-run",
                   Want::kRuns,
                   {"every run on rosenbrock at rtol 1e-05, atol 0.0002 (the calibration's default, not the "
                    "scenario's dopri5 at rtol 1e-06, atol 1e-09"}});
  cases.push_back({"a calibration that chooses dopri5",
                   study("calibrate", w().calibration([&](Json& j) {
                     j["scenario"] = dopri5;
                     j["integrator"] = {{"method", "dopri5"}, {"rtol", 1e-7}, {"atol", 1e-10}};
                   })) + " --dry-run",
                   Want::kRuns, {"every run on dopri5 at rtol 1e-07, atol 1e-10"}, {}, {}, {"not the scenario's"}});
  run_table(w().dir(), cases);
}


// A scenario read from /dev/stdin has no folder: its relative names resolve
// against /dev, and the refusal says so. A step refused for rounding names
// what sets the floor: a duration of 1e6 s, not the time of the step.
TEST_F(Audit, StreamsAndRoundingFloorsAreExplained) {
  std::vector<Case> cases;
  const std::string shipped = source_path("configs/scenarios/drop_horizontal.json");
  cases.push_back({"a shipped scenario through /dev/stdin",
                   "simulate --scenario /dev/stdin --no-plot --out " + w().out() + " < " + shipped, Want::kError,
                   {"file not found: /rover.json", "/dev/stdin is a stream", "resolved against /dev",
                    "give absolute paths"}});
  const std::string million_seconds = w().scenario([](Json& j) {
    j["duration"] = 1e6;
    j["output_rate"] = 1;
    j.erase("integrator");  // Dormand-Prince: the impact at 0.09 s needs steps under the floor
  });
  cases.push_back({"a run of 1e6 s", "simulate --scenario " + million_seconds + " --no-plot --out " + w().out(),
                   Want::kAllFailed, {"rounding units of the duration 1000000 s", "a run this long resolves"}});
  run_table(w().dir(), cases);
}


// A recording that fits rover's own 8 GiB bound but not the memory the
// process may hold (ulimit -v) is refused when the scenario is read, by every
// command and by a dry run, naming the scenario's fields: 1e7 samples of 448
// bytes are 4.5 GB, beyond a 3 GB limit.
TEST_F(Audit, ARecordingBeyondTheProcessMemoryIsRefusedUpFront) {
  const std::string dense = w().scenario([](Json& j) {
    j["duration"] = 1.0;
    j["output_rate"] = 1e7;
  });
  const std::vector<std::string> mentions = {dense, "field 'duration'", "would record 1.0e+07 samples (4.48 GB",
                                             "of the address-space limit (ulimit -v)",
                                             "reduce duration or output_rate"};
  std::vector<Case> cases;
  cases.push_back({"simulate", "simulate --no-plot --scenario " + dense + " --out " + w().out(), Want::kError,
                   mentions, {}, kUnder3GB});
  cases.push_back({"synthesize", "synthesize --scenario " + dense + " --rate 100 --out " + w().out("csv"),
                   Want::kError, mentions, {}, kUnder3GB});
  cases.push_back({"a Monte Carlo's dry run",
                   study("montecarlo", w().montecarlo([&](Json& j) { j["scenario"] = dense; })) + " --dry-run",
                   Want::kError, mentions, {}, kUnder3GB});
  run_table(w().dir(), cases);
}

}  // namespace
}  // namespace rover
