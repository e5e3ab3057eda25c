#pragma once
// Exit codes of the shapespline command line (documented in --help and the README), and the error
// type every subcommand throws for bad command-line input.
#include <shapespline/core/field_error.h>

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

// `sample` of several models where some failed (each was reported as it failed): exit code 1.
class BatchFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A command-line argument or input file that breaks a rule (core/field_error.h): exit code 2.
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
