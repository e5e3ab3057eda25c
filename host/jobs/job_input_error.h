#pragma once
// A scheduler variable, shard option or shard file that breaks a rule: the command line reports it
// as bad input (exit 2), naming the field (a variable, an option, SHARD[k]), the value and the rule.
#include <shapespline/core/field_error.h>

#include <stdexcept>

namespace shapespline::jobs {

class JobInputError : public FieldError<std::invalid_argument> {
 public:
  using FieldError::FieldError;
};

}  // namespace shapespline::jobs
