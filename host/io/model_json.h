#pragma once
// Model files (docs/format.md) to typed models and back.
//
// Reading checks the JSON-level rules of docs/format.md "Fields" (object, known keys only, keys the
// construction uses only, required keys, JSON types, integer-valued numbers, finite numbers, point /
// row shapes, alpha shape) and then the typed rules of docs/math.md §11 via core/validate.h. Every failure
// is a ModelError naming the field as a JSON path ("points[2][1]", "alpha[1][2]", "order[1]"), the
// offending value (io::shortValue) and the rule; malformed JSON text gives field "(document)". The
// text is parsed within the limits of io/input_file.h (nesting depth, keys per object, array
// length, no duplicate keys) and a file is read with io::readInputFile (a regular file of at most
// kMaxInputFileBytes).
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string_view>
#include <variant>

#include <shapespline/core/model.h>

namespace shapespline::io {

using Model = std::variant<CurveModel, SurfaceModel>;

// JSON value -> validated model. Throws ModelError.
Model parseModel(const nlohmann::json& doc);
// JSON text -> validated model. Throws ModelError (field "(document)" for malformed text).
Model parseModelText(std::string_view text);
// File -> validated model. Throws ModelError for bad content, a file that is not a regular file or
// is too large (field "(file)"), and std::runtime_error when the file cannot be opened or read (so
// a caller can tell an I/O failure from an invalid model).
Model loadModelFile(const std::filesystem::path& path);

// Model -> docs/format.md JSON: 2-D curves as [x, y], alpha as a per-vertex array, doubles written
// round-trippably, so parseModel(toJson(m)) reproduces m exactly.
nlohmann::json toJson(const Model& model);
nlohmann::json toJson(const CurveModel& model);
nlohmann::json toJson(const SurfaceModel& model);

}  // namespace shapespline::io
