#pragma once
// Helpers shared by the subcommands: model loading, argument parsing, notices, progress.
#include <shapespline/cli/exit_codes.h>
#include <shapespline/core/diagnostics.h>
#include <shapespline/core/curve.h>
#include <shapespline/core/sample_grid.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/job_metadata.h>
#include <shapespline/io/model_json.h>
#include <shapespline/sampling/report.h>

#include <CLI/CLI.hpp>
#include <glm/vec3.hpp>

#include <chrono>
#include <cstdint>
#include <map>
#include <utility>
#include <string>
#include <vector>

namespace shapespline::cli {

// Every subcommand registers itself on the app; the callback runs the command.
void registerSample(CLI::App& app);
void registerEval(CLI::App& app);
void registerBasis(CLI::App& app);
void registerGbFit(CLI::App& app);
void registerExtend(CLI::App& app);
void registerImport(CLI::App& app);
void registerInfo(CLI::App& app);
void registerDemo(CLI::App& app);
void registerMerge(CLI::App& app);
void registerRender(CLI::App& app);  // cmd_render.cpp
void registerView(CLI::App& app);    // cmd_view.cpp (the viewer, host/viewer)
void registerProject(CLI::App& app);  // cmd_project.cpp

// The options given on the command line (CLI11's counts), by long name ("--rate") with their values
// joined by commas, so that a command refuses an option its input does not take instead of
// ignoring it.
using GivenOptions = std::map<std::string, std::string>;
GivenOptions givenOptions(const CLI::App& sub);
// InputError (exit 2) naming `option` and its value when it was given: "does not apply to <what>".
void refuseOption(const GivenOptions& given, const std::string& option, const std::string& what);

// --threads: InputError unless 0 (one per CPU this process may use) .. 1024.
void requireThreadCount(int threads);

// -q/--quiet, which every subcommand takes so that a script may pass it to each alike; `silences`
// says what it silences in this one (help text).
void addQuietFlag(CLI::App* sub, bool& quiet, const std::string& silences);

// --shard K/N|auto and --shard-count, as `sample` and `project` take them; `what` says what shard K
// of N covers ("the K-th (1-based) of N equal ranges of spans/patches").
void addShardOptions(CLI::App* sub, std::string& shard, std::string& shardCount, const std::string& what);

// Loads and validates a model file: ModelError passes through (exit 2), a file that cannot be read
// becomes InputError("MODEL", path, ...). Arrays it references are read from its folder, or from
// anywhere with `allowOutsideArrays` (--allow-outside-arrays). Each array file is also added to
// `digest` (the model's SHA-256, hashed beside the parse) before it is read.
io::Model loadModel(const std::string& path, bool allowOutsideArrays = false,
                    std::vector<std::filesystem::path>* arrayFiles = nullptr, io::ModelDigest* digest = nullptr);
// loadModel as an outline (io::ModelArrays::outline): a surface whose points are a file comes back
// without the values of its array files, which `arrays` lists (deferred) for io/streamed_net.h.
io::Model loadModelOutline(const std::string& path, bool allowOutsideArrays, io::ModelArrays& arrays,
                           io::ModelDigest* digest);
// Reads a JSON file; malformed JSON or an unreadable file is an InputError naming `field`.
nlohmann::json readJsonFile(const std::string& path, const std::string& field);

// "X,Y" or "X,Y,Z" -> point (z = 0 for two values). `dims` receives the count.
glm::dvec3 parsePoint(const std::string& text, const std::string& field, int* dims = nullptr);
// "a,b,c" -> finite numbers.
std::vector<double> parseNumbers(const std::string& text, const std::string& field);
// "WxH" (or WXH) of an image or window, minSide <= W, H <= 8192; InputError naming `field`.
std::pair<int, int> parseImageSize(const std::string& text, const std::string& field, int minSide);

// --device auto|vulkan|cpu ("gpu" = vulkan), --precision float|double, --require-device.
// --fields a,b,...: fields by name (io::fieldName), of a surface or a curve; the point is always in
// the mask. `withFlags`: --derivatives/--normals were given too (sample), which is refused.
FieldMask parseFields(const std::string& text, bool surface, bool withFlags);

sampling::DeviceKind parseDevice(const std::string& text);
Precision parsePrecision(const std::string& text);
sampling::DeviceRequest parseDeviceRequest(const std::string& device, const std::string& precision, bool require);

// The report's fallbacks as "shapespline: notice: <reason>; falling back to the CPU fp64 path"
// lines on stderr, and a notice when the CPU path was asked for fp32 output (it computes fp64);
// nothing when quiet.
void printNotices(const sampling::Report& report, bool quiet);

// The rule of a finite evaluation whose value the output precision cannot hold (exit 3): the same
// text on every device, since both paths evaluate large and tiny nets scaled by a power of two.
std::string beyondRangeRule(Precision precision);

// Throws RuntimeError (exit 3) when a vector is not finite: an evaluation bug or a value beyond
// the output precision's range, never written.
void requireFinite(const glm::dvec3& v, const char* what);

// Precision warnings (core/diagnostics.h) for the model, plus those of fp32 GPU evaluation, as
// "shapespline: warning: <field>: <message>" lines on stderr unless quiet. `gpuFloat`: the job runs
// the fp32 GPU kernels.
void printPrecisionWarnings(const CurveModel& model, bool gpuFloat, bool quiet);
void printPrecisionWarnings(const Surface& surface, bool gpuFloat, bool quiet);
// The same for a net of `cols` columns seen as a stream (SurfaceWarningScan).
void printPrecisionWarnings(const SurfaceWarningScan& scan, int cols, bool gpuFloat, bool quiet);
// Those of a curve whose values were seen as a stream (the same as of its model).
void printPrecisionWarnings(const CurveWarningScan& scan, bool gpuFloat, bool quiet);

// With --precision float every value is rounded to fp32 (max 3.4e38): a net beyond kMaxFloatNet
// leaves no headroom for derivatives, so it is refused (InputError on --precision, exit 2).
inline constexpr double kMaxFloatNet = 1e36;
void requireFloatRange(const std::vector<glm::dvec3>& points, Precision precision);
// The same for a net whose largest |coordinate| is `largest` (a net streamed, not held).
void requireFloatRange(double largest, Precision precision);

// Test-only CLI fault (issue 7): SHAPESPLINE_FAULT=nan makes `sample` and `eval` see a NaN in the
// first evaluated value, to prove it never reaches a file. main calls takeCliFault() first; it
// consumes that value (removing it from the environment, so host/vk's own SHAPESPLINE_FAULT
// parser never sees it) and leaves every other value to host/vk.
void takeCliFault();
bool nanFaultInjected();

// Progress bar on stderr, shown only when stderr is a terminal, the job is long and not --quiet.
class Progress {
 public:
  Progress(uint64_t total, bool quiet);
  ~Progress();
  void add(uint64_t done);

 private:
  void draw(bool final);
  uint64_t total_ = 0, done_ = 0;
  bool enabled_ = false;
  std::chrono::steady_clock::time_point last_;
};

// JSON output with 17 significant digits (the `eval` promise).
std::string number17(double v);
std::string vector17(const glm::dvec3& v, int dims);
// Output values: the shortest text that reads back to v as `precision` stores it (fp32: v rounded
// to float, at most 9 significant digits; fp64: at most 17), io/number_text.h writeValue.
std::string numberText(double v, Precision precision);
std::string vectorText(const glm::dvec3& v, int dims, Precision precision);

}  // namespace shapespline::cli

namespace shapespline::cli {

// SVG of a curve (x, y projection): the curve, its control polygon (dashed) and `dataPoints` (red).
std::string curveSvg(const Curve& curve, const std::vector<glm::dvec3>& dataPoints, const std::string& title,
                     int samplesPerSpan = 64);
// Writes a model file atomically (io::toJson, 2-space indent).
void writeModelFile(const io::Model& model, const std::string& path, const std::string& option = "-o");

}  // namespace shapespline::cli
