#pragma once
// Exit codes of the shapespline command line (documented in --help and the README), and the error
// type every subcommand throws for bad command-line input.
#include <stdexcept>
#include <string>

namespace shapespline::cli {

inline constexpr int kExitSuccess = 0;
inline constexpr int kExitBadInput = 2;   // bad model, bad arguments, unusable input/output path
inline constexpr int kExitRuntime = 3;    // Vulkan/device failure, I/O failure while writing, internal error

inline constexpr const char* kExitCodeHelp =
    "Exit codes: 0 success; 2 bad input (model file, arguments, output path); "
    "3 device or runtime error (Vulkan, I/O while writing, internal).";

// A command-line argument or input file that breaks a rule: exit code 2.
// Printed as "shapespline: error: <field>: <rule> (got <value>)".
class InputError : public std::invalid_argument {
 public:
  InputError(std::string field, std::string value, std::string rule)
      : std::invalid_argument(field + ": " + rule + (value.empty() ? "" : " (got " + value + ")")),
        field_(std::move(field)),
        value_(std::move(value)),
        rule_(std::move(rule)) {}
  const std::string& field() const { return field_; }
  const std::string& value() const { return value_; }
  const std::string& rule() const { return rule_; }

 private:
  std::string field_, value_, rule_;
};

// A device or runtime failure the user should see named (exit code 3): printed as
// "shapespline: error: <field>: <rule> (got <value>)", like InputError.
class RuntimeError : public std::runtime_error {
 public:
  RuntimeError(std::string field, std::string value, std::string rule)
      : std::runtime_error(field + ": " + rule + (value.empty() ? "" : " (got " + value + ")")),
        field_(std::move(field)),
        value_(std::move(value)),
        rule_(std::move(rule)) {}
  const std::string& field() const { return field_; }
  const std::string& value() const { return value_; }
  const std::string& rule() const { return rule_; }

 private:
  std::string field_, value_, rule_;
};

}  // namespace shapespline::cli
