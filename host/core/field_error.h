#pragma once
// An error naming a field, the offending value and the rule, on top of the standard exception `Base`
// that decides how a front end reports it. what() is "<field>: <rule> (got <value>)".
#include <string>
#include <utility>

namespace shapespline {

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

}  // namespace shapespline
