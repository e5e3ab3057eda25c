#pragma once
// The errors of `shapespline view`, so that the command line maps them to its exit codes without
// knowing the viewer's insides.
#include <stdexcept>
#include <string>

namespace shapespline::viewer {

// A line of a --script file that breaks a rule (the CLI: exit 2). what() = "line N: RULE (got TEXT)".
class ScriptError : public std::invalid_argument {
 public:
  ScriptError(int line, const std::string& text, const std::string& rule)
      : std::invalid_argument("line " + std::to_string(line) + ": " + rule + " (got '" + text + "')"),
        line_(line) {}
  int line() const { return line_; }

 private:
  int line_;
};

// No display, no window, no device that can present (the CLI: exit 3).
class DisplayError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Validation was asked for and the layers reported messages (the CLI: exit 3).
class ValidationFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace shapespline::viewer
