// Distributions read from study files (study/model/distribution_json.cpp):
// every kind, defaults from the nominal value, truncation, and errors that
// name the file, the field and the value.
#include "study/model/distribution_json.hpp"

#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "io/json_reader.hpp"

namespace rover::study {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Distribution parse(const std::string& text, double nominal = kNaN) {
  const io::Json json = io::Json::parse(text);
  const io::JsonReader r(json, "study.json", "parameters.c_q");
  const Distribution d = parse_distribution(r, nominal);
  r.finish();  // every key was consumed
  return d;
}

// Parsing `text` throws a ConfigError naming the file, the field and `fragment`.
void expect_config_error(const std::string& text, const std::string& field,
                         const std::string& fragment, double nominal = kNaN) {
  try {
    parse(text, nominal);
    ADD_FAILURE() << "no error for " << text;
  } catch (const io::ConfigError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("study.json"), std::string::npos) << message;
    EXPECT_NE(message.find("'parameters.c_q." + field + "'"), std::string::npos) << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << message;
  }
}

TEST(ParseDistribution, EveryKind) {
  Distribution d = parse(R"({"distribution": "fixed", "value": 4.5})");
  EXPECT_EQ(d.kind, DistributionKind::kFixed);
  EXPECT_EQ(d.a, 4.5);

  d = parse(R"({"distribution": "uniform", "min": -1, "max": 3})");
  EXPECT_EQ(d.kind, DistributionKind::kUniform);
  EXPECT_EQ(d.a, -1.0);
  EXPECT_EQ(d.b, 3.0);

  d = parse(R"({"distribution": "log_uniform", "min": 1e-2, "max": 100})");
  EXPECT_EQ(d.kind, DistributionKind::kLogUniform);
  EXPECT_EQ(d.a, 1e-2);
  EXPECT_EQ(d.b, 100.0);

  d = parse(R"({"distribution": "normal", "mean": 1.924, "sd": 0.039, "truncate": [0, null]})");
  EXPECT_EQ(d.kind, DistributionKind::kNormal);
  EXPECT_EQ(d.a, 1.924);
  EXPECT_EQ(d.b, 0.039);
  EXPECT_EQ(d.lower, 0.0);
  EXPECT_EQ(d.upper, kInf);

  d = parse(R"({"distribution": "normal", "mean": 0, "sd": 1, "truncate": [null, 2.5]})");
  EXPECT_EQ(d.lower, -kInf);
  EXPECT_EQ(d.upper, 2.5);

  d = parse(R"({"distribution": "lognormal", "log_mean": 0.1, "log_sd": 0.2})");
  EXPECT_EQ(d.kind, DistributionKind::kLognormal);
  EXPECT_EQ(d.a, 0.1);
  EXPECT_EQ(d.b, 0.2);
  EXPECT_EQ(d.lower, 0.0);
  EXPECT_EQ(d.upper, kInf);

  d = parse(R"({"distribution": "lognormal", "mean": 2, "sd": 0.3, "truncate": [null, 5]})");
  EXPECT_NEAR(d.b, std::sqrt(std::log(1.0 + 0.0225)), 1e-15);
  EXPECT_NEAR(d.a, std::log(2.0) - 0.5 * std::log(1.0 + 0.0225), 1e-15);
  EXPECT_EQ(d.lower, 0.0);
  EXPECT_EQ(d.upper, 5.0);
}

TEST(ParseDistribution, RelativeSdAndNominalDefaults) {
  Distribution d = parse(R"({"distribution": "normal", "sd_percent": 5})", -2.0);
  EXPECT_EQ(d.a, -2.0);
  EXPECT_NEAR(d.b, 0.1, 1e-15);  // 5 % of |mean|

  d = parse(R"({"distribution": "normal", "mean": 10, "sd_percent": 2})", 3.0);
  EXPECT_EQ(d.a, 10.0);
  EXPECT_NEAR(d.b, 0.2, 1e-15);

  d = parse(R"({"distribution": "fixed"})", 7.25);
  EXPECT_EQ(d.a, 7.25);

  // Lognormal: mean from the nominal, sd_percent the coefficient of variation.
  d = parse(R"({"distribution": "lognormal", "sd_percent": 10})", 4.0);
  EXPECT_NEAR(d.mean(), 4.0, 1e-12);
  EXPECT_NEAR(d.sd(), 0.4, 1e-12);
}

TEST(ParseDistribution, BadInputNamesFileFieldAndValue) {
  expect_config_error(R"({"distribution": "gaussian", "mean": 1})", "distribution",
                      "valid: fixed, uniform, log_uniform, normal, lognormal");
  expect_config_error(R"({"distribution": "gaussian"})", "distribution", "\"gaussian\"");
  expect_config_error(R"({"distribution": "uniform", "min": 2, "max": 2})", "max",
                      "must be greater than min");
  expect_config_error(R"({"distribution": "uniform", "min": 3, "max": 2})", "max", "(value 2)");
  expect_config_error(R"({"distribution": "normal", "mean": 1, "sd": 0})", "sd", "must be positive");
  expect_config_error(R"({"distribution": "normal", "mean": 1, "sd": -0.1})", "sd", "(value -0.1)");
  expect_config_error(R"({"distribution": "log_uniform", "min": 0, "max": 2})", "min",
                      "must be positive");
  expect_config_error(R"({"distribution": "log_uniform", "min": -1, "max": 2})", "min",
                      "must be positive");
  expect_config_error(R"({"distribution": "normal", "mean": 0, "sd": 1, "truncate": [2, 1]})",
                      "truncate", "lower bound must be less than the upper bound");
  expect_config_error(R"({"distribution": "lognormal", "mean": 1, "sd": 1, "truncate": [3, 3]})",
                      "truncate", "[3,3]");
  expect_config_error(R"({"distribution": "normal", "mean": 0, "sd": 1, "truncate": [50, 60]})",
                      "truncate", "less than 1e-300");
  expect_config_error(R"({"distribution": "normal", "mean": 0, "sd": 1, "truncate": [0]})",
                      "truncate", "expected [lower, upper]");
  expect_config_error(R"({"distribution": "normal", "mean": 0, "sd": 1, "truncate": ["a", 1]})",
                      "truncate", "element 0");
  expect_config_error(R"({"distribution": "uniform", "min": 0, "max": 1, "truncate": [0, 1]})",
                      "truncate", "normal and lognormal only");
  expect_config_error(R"({"distribution": "normal", "mean": 1})", "sd", "missing");
  expect_config_error(R"({"distribution": "normal", "mean": 1, "sd": 1, "sd_percent": 3})",
                      "sd_percent", "not both");
  expect_config_error(R"({"distribution": "normal", "mean": 0, "sd_percent": 3})", "sd_percent",
                      "give sd instead");
  expect_config_error(R"({"distribution": "normal", "sd": 1})", "mean", "no nominal value");
  expect_config_error(R"({"distribution": "fixed"})", "value", "no nominal value");
  expect_config_error(R"({"distribution": "lognormal", "sd": 1})", "mean", "must be positive", -3.0);
  expect_config_error(R"({"distribution": "lognormal", "log_mean": 0, "log_sd": 1, "sd": 1})", "sd",
                      "not both");
  expect_config_error(R"({"distribution": "lognormal", "log_mean": 0})", "log_sd", "missing");
  expect_config_error(R"({"distribution": 3})", "distribution", "expected a string");
}

TEST(ParseDistribution, LeavesOtherKeysToTheCaller) {
  const io::Json json = io::Json::parse(R"({"distribution": "uniform", "min": 0, "max": 1, "unit": "m"})");
  const io::JsonReader r(json, "study.json", "parameters.x");
  parse_distribution(r, kNaN);  // does not call finish()
  EXPECT_EQ(r.string("unit"), "m");
  EXPECT_NO_THROW(r.finish());
}

}  // namespace
}  // namespace rover::study
