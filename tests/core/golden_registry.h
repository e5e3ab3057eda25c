#pragma once
// The registry the core golden test runs. Checker files register their families with a static
// GoldenRegistration object, so each family's checker lives next to the tests of its module.
#include "support/golden.h"

namespace shapespline::test {

GoldenRegistry& coreGoldenRegistry();

struct GoldenRegistration {
  GoldenRegistration(const std::string& family, FamilyChecker checker) {
    coreGoldenRegistry().add(family, std::move(checker));
  }
};

}  // namespace shapespline::test
