#pragma once
// The parts a CAD bench runs on: the STEP/IGES files given, or else the tests' own parts
// (tests/cad/test_parts: a filleted box, a drilled plate, a free-form face) written to STEP in
// `scratch`; run(name, file) gives each part's row of the bench's JSON.
#include "../../tests/cad/test_parts.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace shapespline::bench {

inline nlohmann::json benchEachPart(const std::vector<std::filesystem::path>& given, const std::filesystem::path& scratch,
                                    const std::function<nlohmann::json(const std::string&, const std::filesystem::path&)>& run) {
  nlohmann::json rows = nlohmann::json::array();
  if (!given.empty()) {
    for (const std::filesystem::path& file : given) rows.push_back(run(file.stem().string(), file));
    return rows;
  }
  const std::pair<const char*, TopoDS_Shape> own[] = {
      {"filleted_box", test::filletedBox()}, {"drilled_plate", test::drilledPlate()}, {"free_form", test::freeForm()}};
  for (const auto& [name, shape] : own) {
    const std::filesystem::path step = scratch / (std::string(name) + ".step");
    test::writeStep(shape, step);
    rows.push_back(run(name, step));
  }
  return rows;
}

}  // namespace shapespline::bench
