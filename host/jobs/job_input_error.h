#pragma once
// A scheduler variable, shard option or shard file that breaks a rule: the command line reports it
// as bad input (exit 2), naming the field (a variable, an option, SHARD[k]), the value and the rule.
#include <stdexcept>
#include <string>
#include <utility>

namespace shapespline::jobs {

class JobInputError : public std::invalid_argument {
 public:
  JobInputError(std::string field, std::string value, std::string rule)
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

}  // namespace shapespline::jobs
