#pragma once
// Exit codes of the shapespline command line (documented in --help and the README), and the error
// type every subcommand throws for bad command-line input.
#include <stdexcept>
#include <string>

namespace shapespline::cli {

inline constexpr int kExitSuccess = 0;
inline constexpr int kExitSomeFailed = 1;  // `sample` of several models: some failed (each reported), the rest written
inline constexpr int kExitBadInput = 2;   // bad model, bad arguments, unusable input/output path
inline constexpr int kExitRuntime = 3;    // Vulkan/device failure, I/O failure while writing, internal error

inline constexpr const char* kExitCodeHelp =
    "Exit codes: 0 success; 1 some of several models failed (each reported, the others written); "
    "2 bad input (model file, arguments, output path); 3 device or runtime error (Vulkan, I/O while writing, "
    "internal).";

// A user-facing error naming a field, the offending value and the rule, on top of the standard
// exception `Base` that decides its exit code. Printed as "shapespline: error: <field>: <rule>
// (got <value>)".
template <class Base>
class FieldError : public Base {
 public:
  FieldError(std::string field, std::string value, std::string rule)
      : Base(field + ": " + rule + (value.empty() ? "" : " (got " + value + ")")),
        field_(std::move(field)),
        value_(std::move(value)),
        rule_(std::move(rule)) {}
  const std::string& field() const { return field_; }
  const std::string& value() const { return value_; }
  const std::string& rule() const { return rule_; }

 private:
  std::string field_, value_, rule_;
};

// `sample` of several models where some failed (each was reported as it failed): exit code 1.
class BatchFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A command-line argument or input file that breaks a rule: exit code 2.
class InputError : public FieldError<std::invalid_argument> {
 public:
  using FieldError::FieldError;
};

// A device or runtime failure the user should see named: exit code 3.
class RuntimeError : public FieldError<std::runtime_error> {
 public:
  using FieldError::FieldError;
};

}  // namespace shapespline::cli
