#pragma once
// A double as text in error messages, one rule each (not installed; core and io use it).
#include <charconv>
#include <cmath>
#include <sstream>
#include <string>

namespace shapespline {

// 17 significant digits in iostream's general form ("0.10000000000000001"): every bit shown.
inline std::string preciseText(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

// The shortest text that reads back as the same double ("0.1", "1e-310"); "nan", "inf", "-inf".
inline std::string shortestText(double v) {
  if (std::isnan(v)) return "nan";
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

}  // namespace shapespline
