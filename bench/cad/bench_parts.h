#pragma once
// The parts a CAD bench runs on: the STEP/IGES files given, or else the tests' own parts
// (tests/cad/test_parts: a filleted box, a drilled plate, a free-form face) written to STEP in a
// scratch folder of the bench's own; run(name, file, scratch) gives each part's row of the bench's
// JSON, which is written to `json` unless that is empty. The scratch folder is removed after.
#include "../../tests/cad/test_parts.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

namespace shapespline::bench {

inline void benchEachPart(
    const std::string& bench, const std::vector<std::filesystem::path>& given, const std::string& json,
    const std::function<nlohmann::json(const std::string&, const std::filesystem::path&, const std::filesystem::path&)>& run) {
  const std::filesystem::path scratch =
      std::filesystem::temp_directory_path() / (bench + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(scratch);
  nlohmann::json rows = nlohmann::json::array();
  if (!given.empty()) {
    for (const std::filesystem::path& file : given) rows.push_back(run(file.stem().string(), file, scratch));
  } else {
    const std::pair<const char*, TopoDS_Shape> own[] = {
        {"filleted_box", test::filletedBox()}, {"drilled_plate", test::drilledPlate()}, {"free_form", test::freeForm()}};
    for (const auto& [name, shape] : own) {
      const std::filesystem::path step = scratch / (std::string(name) + ".step");
      test::writeStep(shape, step);
      rows.push_back(run(name, step, scratch));
    }
  }
  std::filesystem::remove_all(scratch);
  if (!json.empty()) std::ofstream(json) << rows.dump(1) << "\n";
}

}  // namespace shapespline::bench
