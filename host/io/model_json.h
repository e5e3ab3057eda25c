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
//
// `points`, `alpha` and `weights` may instead name a .npy array (io/npy_array.h) relative to the
// model file's folder: "points": {"npy": "net.npy"} (docs/format.md "Arrays in .npy files"). The
// array's shape must be the one the key's JSON form has (curve points (n, 2) or (n, 3), surface
// points (rows, cols, 3), alpha / weights (n) or (rows, cols)) and every value finite; its float64
// copy may take at most ModelArrays::maxValueBytes. Errors name the key and the file. A caller
// that holds the arrays in memory (the Python module) hands them over in ModelArrays::given, the
// document naming them {"array": "points"}: the same rules and messages, no JSON numbers.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <shapespline/core/model.h>
#include <shapespline/core/validate.h>
#include <shapespline/io/npy_array.h>

namespace shapespline::io {

using Model = std::variant<CurveModel, SurfaceModel>;

// The default budget for the float64 values of one referenced array: 4 GiB (a 13,000² surface
// net), far beyond what a JSON model can hold and within what a sampling machine has.
inline constexpr std::uint64_t kDefaultArrayBudget = std::uint64_t{4} << 30;

// An array reference the parser left unread (ModelArrays::outline).
struct DeferredArray {
  std::string key;               // "points", "alpha" or "weights"
  std::string name;              // the file name as the model writes it, for messages
  std::filesystem::path file;
  NpyHeader header;              // checked: dtype, order, the shape the key needs, the budget
};

// Where array references are read from: .npy files in a folder, or arrays given in memory.
struct ModelArrays {
  std::filesystem::path folder;  // relative names are resolved here (the model file's folder)
  bool allowOutside = false;     // absolute names, "..", and symlinks that lead out of `folder`
  std::uint64_t maxValueBytes = kDefaultArrayBudget;
  std::map<std::string, NpyArray> given;  // by key; the parser moves each one it uses out
  // The .npy files the parser read, in key order (points, alpha, weights): what the job metadata
  // hashes with the model file, and what an output must not replace.
  std::vector<std::filesystem::path> files;
  // Called with each file of `files` as it is found, before it is read (io::ModelDigest::add).
  std::function<void(const std::filesystem::path&)> onFile;
  // Outline: a surface whose points are a file comes back with its shape and without the values
  // of its array files: their headers are checked (the shape each key needs) and listed in
  // `deferred`, the files still go to onFile and `files`, and an α given as one number is kept in
  // `uniformAlpha` rather than once per vertex. Only the shape rules are checked (core
  // validateSurfaceShape or validateCurveShape with outlineCounts); io/streamed_net.h and
  // io/streamed_bands.h read and check the values. A curve whose points are a file is left unread
  // the same way (its points empty, its dimension from the file). Models with their points written
  // out are read in full (`deferred` stays empty).
  bool outline = false;
  std::vector<DeferredArray> deferred;
  std::optional<double> uniformAlpha;
};

// How many points, α and weights an outline's surface has, its deferred arrays counted.
SurfaceCounts outlineCounts(const SurfaceModel& model, const ModelArrays& arrays);
SurfaceCounts outlineCounts(const CurveModel& model, const ModelArrays& arrays);

// The rule every value of an array file follows: finite. Throws the parser's ModelError (the field
// names the element, key[i][j]..., the value the file's `name`) for the first value that is not
// among `count` values starting at flat index `first` of an array of `shape`.
void requireFiniteArrayValues(const std::string& key, const std::string& name, const std::vector<std::uint64_t>& shape,
                              const double* values, size_t count, std::uint64_t first);

// JSON value -> validated model. Throws ModelError. Without `arrays`, an array reference is refused
// (a model that is not a file has no folder to resolve it in).
Model parseModel(const nlohmann::json& doc, ModelArrays* arrays = nullptr);
// JSON text -> validated model. Throws ModelError (field "(document)" for malformed text).
Model parseModelText(std::string_view text, ModelArrays* arrays = nullptr);
// File -> validated model, array references resolved in its folder. Throws ModelError for bad
// content, a file that is not a regular file or is too large (field "(file)"), and
// std::runtime_error when the file cannot be opened or read (so a caller can tell an I/O failure
// from an invalid model).
Model loadModelFile(const std::filesystem::path& path, bool allowOutside = false,
                    std::uint64_t maxValueBytes = kDefaultArrayBudget);

// Model -> docs/format.md JSON: 2-D curves as [x, y], alpha as a per-vertex array, doubles written
// round-trippably, so parseModel(toJson(m)) reproduces m exactly.
nlohmann::json toJson(const Model& model);
nlohmann::json toJson(const CurveModel& model);
nlohmann::json toJson(const SurfaceModel& model);

class OutputSet;
// Adds `path` (a model file) to `outputs` with the model's points, per-vertex α and weights as
// float64 .npy arrays beside it, STEM.points.npy, STEM.alpha.npy, STEM.weights.npy (an α that is
// the same at every vertex stays one number): loadModelFile(path) then gives `model` exactly. The
// caller commits the set. `option` names the files in errors (OutputSet::add).
void saveModelWithArrays(const CurveModel& model, const std::filesystem::path& path, OutputSet& outputs,
                         const std::string& option);
void saveModelWithArrays(const SurfaceModel& model, const std::filesystem::path& path, OutputSet& outputs,
                         const std::string& option);

}  // namespace shapespline::io
