#include <shapespline/cli/common.h>

#include <shapespline/core/diagnostics.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/number_text.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/sampling/net_scale.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string_view>

namespace shapespline::cli {

namespace {
// A path from the command line, shown in a message: long enough to recognize, never unbounded.
constexpr size_t kMaxPathChars = 256;
}  // namespace

namespace {

io::Model parseModelFile(const std::string& path, bool allowOutsideArrays, io::ModelArrays& arrays,
                         io::ModelDigest* digest) {
  std::string text;
  try {
    text = io::readInputFile(path, "MODEL");
  } catch (const ModelError&) {
    throw;  // not a regular file, too large
  } catch (const std::exception& e) {
    throw InputError("MODEL", io::shortText(path, kMaxPathChars), std::string("cannot read the model file: ") + e.what());
  }
  // Array references ("points": {"npy": ...}) are resolved in the model file's folder.
  arrays.folder = std::filesystem::path(path).parent_path();
  arrays.allowOutside = allowOutsideArrays;
  if (digest) arrays.onFile = [digest](const std::filesystem::path& file) { digest->add(file); };
  return io::parseModelText(text, &arrays);
}

}  // namespace

io::Model loadModel(const std::string& path, bool allowOutsideArrays, std::vector<std::filesystem::path>* arrayFiles,
                    io::ModelDigest* digest) {
  io::ModelArrays arrays;
  io::Model model = parseModelFile(path, allowOutsideArrays, arrays, digest);
  if (arrayFiles) *arrayFiles = std::move(arrays.files);
  return model;
}

io::Model loadModelOutline(const std::string& path, bool allowOutsideArrays, io::ModelArrays& arrays,
                           io::ModelDigest* digest) {
  arrays.outline = true;
  return parseModelFile(path, allowOutsideArrays, arrays, digest);
}

nlohmann::json readJsonFile(const std::string& path, const std::string& field) {
  std::string text;
  try {
    text = io::readInputFile(path, field);
  } catch (const ModelError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(field, io::shortText(path, kMaxPathChars), std::string("cannot open the file: ") + e.what());
  }
  // Paths inside the file are named under the file's field: "--to-curve[0].points[2]".
  return io::parseJsonText(text, field, field);
}

std::pair<int, int> parseImageSize(const std::string& text, const std::string& field, int minSide) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < minSide ||
      h < minSide || w > 8192 || h > 8192)
    throw InputError(field, text, "expected WxH with " + std::to_string(minSide) + " <= W, H <= 8192");
  return {w, h};
}

std::vector<double> parseNumbers(const std::string& text, const std::string& field) {
  std::vector<double> out;
  size_t pos = 0;
  while (pos <= text.size()) {
    const size_t comma = text.find(',', pos);
    const std::string item = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size()) {
      throw InputError(field, io::shortText(text), "expected comma-separated numbers");
    }
    if (!std::isfinite(v)) throw InputError(field, io::shortText(text), "numbers must be finite");
    out.push_back(v);
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  return out;
}

glm::dvec3 parsePoint(const std::string& text, const std::string& field, int* dims) {
  const auto v = parseNumbers(text, field);
  if (v.size() != 2 && v.size() != 3) throw InputError(field, io::shortText(text), "expected X,Y or X,Y,Z");
  if (dims) *dims = static_cast<int>(v.size());
  return {v[0], v[1], v.size() == 3 ? v[2] : 0.0};
}

sampling::DeviceKind parseDevice(const std::string& text) {
  if (text == "auto") return sampling::DeviceKind::Auto;
  if (text == "vulkan" || text == "gpu") return sampling::DeviceKind::Vulkan;
  if (text == "cpu") return sampling::DeviceKind::Cpu;
  throw InputError("--device", text, "expected auto, vulkan or cpu");
}

Precision parsePrecision(const std::string& text) {
  if (text == "float" || text == "fp32") return Precision::Float;
  if (text == "double" || text == "fp64") return Precision::Double;
  throw InputError("--precision", text, "expected float or double");
}

sampling::DeviceRequest parseDeviceRequest(const std::string& device, const std::string& precision, bool require) {
  const sampling::DeviceKind kind = parseDevice(device);
  if (require && kind == sampling::DeviceKind::Cpu) {
    throw InputError("--require-device", "", "applies to --device auto or vulkan (--device cpu never uses the GPU)");
  }
  return {kind, parsePrecision(precision), require};
}

std::string beyondRangeRule(Precision precision) {
  return precision == Precision::Float
             ? "exceeds the fp32 range of the output (use --precision double); nothing was written"
             : "exceeds the fp64 range of the output (derivatives grow with the net's size and like 1/h^r for "
               "knot intervals h); nothing was written";
}

void requireThreadCount(int threads) {
  constexpr int kMaxThreads = 1024;
  if (threads < 0 || threads > kMaxThreads)
    throw InputError("--threads", std::to_string(threads),
                     "must be in [0, " + std::to_string(kMaxThreads) + "] (0 = one per CPU this process may use)");
}

void addQuietFlag(CLI::App* sub, bool& quiet, const std::string& silences) {
  sub->add_flag("-q,--quiet", quiet, silences);
}

void addShardOptions(CLI::App* sub, std::string& shard, std::string& shardCount, const std::string& what) {
  sub->add_option("--shard", shard,
                  "K/N: only " + what + " (merge joins them); auto: K/N from a Slurm job array "
                  "(SLURM_ARRAY_TASK_ID/MIN/MAX) or a Kubernetes Indexed Job (JOB_COMPLETION_INDEX + --shard-count). "
                  "A shard also writes OUT.shard.json (sizes, SHA-256); rerun, a shard that verifies is left as it is");
  sub->add_option("--shard-count", shardCount,
                  "with --shard auto in a Kubernetes Indexed Job: N, the job's completions (else SHAPESPLINE_SHARD_COUNT)");
}

GivenOptions givenOptions(const CLI::App& sub) {
  GivenOptions given;
  for (const CLI::Option* o : sub.get_options()) {
    if (o->count() == 0 || o->get_lnames().empty()) continue;
    std::string value;
    for (const std::string& r : o->results()) value += (value.empty() ? "" : ",") + r;
    given["--" + o->get_lnames()[0]] = value;
  }
  return given;
}

void refuseOption(const GivenOptions& given, const std::string& option, const std::string& what) {
  const auto it = given.find(option);
  if (it != given.end()) throw InputError(option, it->second, "does not apply to " + what);
}

void printNotices(const sampling::Report& report, bool quiet) {
  if (quiet) return;
  for (const auto& why : report.fallbacks) {
    std::fprintf(stderr, "shapespline: notice: %s; falling back to the CPU fp64 path\n", why.c_str());
  }
  if (report.fallbacks.empty() && report.computedPrecision != report.outputPrecision) {
    std::fprintf(stderr, "shapespline: notice: the CPU path computes in fp64; --precision float only rounds the output\n");
  }
}

void requireFinite(const glm::dvec3& v, const char* what) {
  if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
    throw RuntimeError(what, "", "evaluation produced a non-finite value (an internal error, or a value beyond the "
                                 "output precision's range); nothing was written");
  }
}

namespace {

// fp32 keeps about 7 significant digits: α below this loses more than 2 of them (docs/math.md §14:
// rounding errors grow like 1/α), a net resolved with fewer than 3 digits relative to its offset
// from the origin is shapeless.
constexpr double kAlphaWarnFloat = 1e-2;
constexpr double kRelativeExtentFloat = 1e-4;

std::string num3(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

// The fp32 kernels' warnings from the control points' spread and the smallest α (`name` gives
// the index part of α's field).
void floatWarnings(const PointSpread& points, const SmallestAlpha& alpha, const std::function<std::string(size_t)>& name,
                   std::vector<Warning>& out) {
  if (alpha.any && alpha.value < kAlphaWarnFloat && alpha.value >= kAlphaWarn) {  // below kAlphaWarn core warns
    out.push_back({"alpha" + name(alpha.where),
                   "alpha = " + num3(alpha.value) + " amplifies rounding errors by 1/alpha: the fp32 GPU kernels lose about " +
                       num3(std::floor(-std::log10(alpha.value))) + " of their 7 digits (use --precision double)"});
  }
  if (!points.any) return;
  double extent = 0.0;
  for (int d = 0; d < points.dims; ++d) extent = std::max(extent, points.hi[d] - points.lo[d]);
  const double biggest = points.biggest;
  if (extent > 0.0 && extent < kRelativeExtentFloat * biggest && extent >= kRelativeExtent * biggest) {
    out.push_back({"points", "the control net spans only " + num3(extent) + " but lies " + num3(biggest) +
                                 " from the origin: in fp32 (7 digits) fewer than 3 digits describe its shape "
                                 "(use --precision double)"});
  }
}

// The same from every control point (`forEachPoint(f)` calls f(P): a vector, or a surface's net in
// place) and the α values.
template <class ForEach>
void floatWarnings(ForEach&& forEachPoint, int dims, const std::vector<double>& alpha,
                   const std::function<std::string(size_t)>& name, std::vector<Warning>& out) {
  PointSpread points{dims};
  forEachPoint([&](const glm::dvec3& p) { points.add(p); });
  SmallestAlpha smallest;
  smallest.add(alpha.data(), alpha.size());
  floatWarnings(points, smallest, name, out);
}

}  // namespace

namespace {
void print(const std::vector<Warning>& warnings) {
  for (const auto& w : warnings) std::fprintf(stderr, "shapespline: %s\n", formatWarning(w).c_str());
}
}  // namespace

void printPrecisionWarnings(const CurveModel& model, bool gpuFloat, bool quiet) {
  CurveWarningScan scan(model);
  scan.points(model.points.data(), model.points.size());
  scan.alphas(model.alpha.data(), model.alpha.size());
  printPrecisionWarnings(scan, gpuFloat, quiet);
}

void printPrecisionWarnings(const CurveWarningScan& scan, bool gpuFloat, bool quiet) {
  if (quiet) return;
  std::vector<Warning> warnings = scan.warnings();
  if (gpuFloat)
    floatWarnings(scan.spread(), scan.smallestAlpha(), [](size_t k) { return "[" + std::to_string(k) + "]"; }, warnings);
  print(warnings);
}

void printPrecisionWarnings(const SurfaceWarningScan& scan, int cols, bool gpuFloat, bool quiet) {
  if (quiet) return;
  std::vector<Warning> warnings = scan.warnings();
  const size_t n = static_cast<size_t>(std::max(cols, 1));
  if (gpuFloat)
    floatWarnings(scan.spread(), scan.smallestAlpha(),
                  [n](size_t k) { return "[" + std::to_string(k / n) + "][" + std::to_string(k % n) + "]"; }, warnings);
  print(warnings);
}

void printPrecisionWarnings(const Surface& surface, bool gpuFloat, bool quiet) {
  if (quiet) return;
  std::vector<Warning> warnings = precisionWarnings(surface);
  const SurfaceShape& model = surface.model();
  const size_t cols = static_cast<size_t>(std::max(model.cols, 1));
  if (gpuFloat) {
    floatWarnings([&](auto&& f) { surface.forEachControlPoint(f); }, 3, model.alpha,
                  [cols](size_t k) { return "[" + std::to_string(k / cols) + "][" + std::to_string(k % cols) + "]"; },
                  warnings);
  }
  print(warnings);
}

void requireFloatRange(const std::vector<glm::dvec3>& points, Precision precision) {
  if (precision != Precision::Float) return;
  requireFloatRange(sampling::largestCoordinate(points), precision);
}

void requireFloatRange(double largest, Precision precision) {
  if (precision != Precision::Float) return;
  if (largest > kMaxFloatNet) {
    throw InputError("--precision", "float",
                     "the control net reaches " + num3(largest) + " but fp32 output holds at most 3.4e38 "
                     "(coordinates above " + num3(kMaxFloatNet) + " leave no headroom for derivatives): use "
                     "--precision double");
  }
}

namespace {
bool& nanFault() {
  static bool on = false;
  return on;
}
}  // namespace

void takeCliFault() {
  const char* env = std::getenv("SHAPESPLINE_FAULT");
  if (env && std::string_view(env) == "nan") {
    nanFault() = true;
    ::unsetenv("SHAPESPLINE_FAULT");
  }
}

bool nanFaultInjected() { return nanFault(); }

Progress::Progress(uint64_t total, bool quiet) : total_(total) {
  enabled_ = !quiet && total >= 4'000'000 && ::isatty(STDERR_FILENO);
  last_ = std::chrono::steady_clock::now();
}

Progress::~Progress() {
  if (enabled_) {
    draw(true);
    std::fputc('\n', stderr);
  }
}

void Progress::add(uint64_t done) {
  done_ += done;
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ < std::chrono::milliseconds(200)) return;
  last_ = now;
  draw(false);
}

void Progress::draw(bool) {
  const double f = total_ ? static_cast<double>(done_) / static_cast<double>(total_) : 1.0;
  const int width = 40, full = static_cast<int>(f * width);
  std::string bar(static_cast<size_t>(full), '#');
  bar.resize(width, ' ');
  std::fprintf(stderr, "\r[%s] %5.1f%%  %llu / %llu points", bar.c_str(), 100.0 * f,
               static_cast<unsigned long long>(done_), static_cast<unsigned long long>(total_));
  std::fflush(stderr);
}

std::string number17(double v) {
  char buf[io::kMaxNumberChars];
  return std::string(buf, io::writeNumber17(buf, v));
}

std::string numberText(double v, Precision precision) {
  char buf[io::kMaxNumberChars];
  return std::string(buf, io::writeValue(buf, v, precision));
}

std::string vectorText(const glm::dvec3& v, int dims, Precision precision) {
  std::string s = "[" + numberText(v.x, precision) + ", " + numberText(v.y, precision);
  if (dims == 3) s += ", " + numberText(v.z, precision);
  return s + "]";
}

std::string vector17(const glm::dvec3& v, int dims) {
  std::string s = "[" + number17(v.x) + ", " + number17(v.y);
  if (dims == 3) s += ", " + number17(v.z);
  return s + "]";
}

}  // namespace shapespline::cli

#include <shapespline/core/grid_sampler.h>
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/svg_writer.h>

namespace shapespline::cli {

std::string curveSvg(const Curve& curve, const std::vector<glm::dvec3>& dataPoints, const std::string& title,
                     int samplesPerSpan) {
  io::SvgPlot plot(true, title);
  io::SvgPolyline poly;
  for (const auto& p : curve.model().points) poly.points.emplace_back(p.x, p.y);
  poly.color = "#888888";
  poly.width = 1.0;
  poly.dashed = true;
  poly.closed = curve.model().closed;
  io::SvgMarkers ctrl;
  ctrl.points = poly.points;
  ctrl.color = "#555555";
  ctrl.radius = 3.0;
  ctrl.filled = false;
  plot.add(std::move(poly));
  plot.add(std::move(ctrl));
  for (int s : curveGridItems(curve)) {
    io::SvgPolyline line;
    for (int i = 0; i < samplesPerSpan; ++i) {
      const auto p = curve.evaluate(s, static_cast<double>(i) / (samplesPerSpan - 1)).point;
      line.points.emplace_back(p.x, p.y);
    }
    plot.add(std::move(line));
  }
  io::SvgMarkers data;
  for (const auto& p : dataPoints) data.points.emplace_back(p.x, p.y);
  plot.add(std::move(data));
  try {
    return plot.render();  // checks every number it writes
  } catch (const io::SvgValueError& e) {
    throw RuntimeError("--svg", "", e.what());
  }
}

void writeModelFile(const io::Model& model, const std::string& path, const std::string& option) {
  io::AtomicFile out(path, option);
  out.write(io::toJson(model).dump(2));
  out.write("\n");
  out.commit();
}

FieldMask parseFields(const std::string& text, bool surface, bool withFlags) {
  if (withFlags) throw InputError("--fields", text, "give either --fields or --derivatives/--normals");
  const FieldMask allowed = surface ? kSurfaceFields : kCurveFields;
  FieldMask mask = fieldBit(Field::Point);
  size_t pos = 0;
  while (pos <= text.size()) {
    const size_t comma = text.find(',', pos);
    const std::string name = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    int found = -1;
    for (int f = 0; f < kFieldCount; ++f) {
      if (io::fieldName(static_cast<Field>(f)) == name) found = f;
    }
    if (found < 0 || !(allowed & fieldBit(static_cast<Field>(found)))) {
      throw InputError("--fields", text,
                       std::string("expected a comma-separated list of ") +
                           (surface ? "point, du, dv, duu, duv, dvv, normal (surfaces)" : "point, d1, d2 (curves)") +
                           "; '" + name + "' is not one");
    }
    mask |= fieldBit(static_cast<Field>(found));
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  return mask;
}

}  // namespace shapespline::cli
