// libFuzzer target over model parsing, validation and CPU evaluation (issue 7).
//
// Each input is the text of a model file. The contract checked here:
//  * io::parseModelText either returns a validated model or throws ModelError; nothing else escapes;
//  * a parsed model round-trips exactly through io::toJson;
//  * Curve::create / Surface::create accept every model the parser accepted, but for the one rule
//    that needs the built net: an α-EB vertex whose α is so small that V overflows fp64
//    (docs/math.md §4.2), refused there with a ModelError naming alpha[...] (the CLI's exit 2);
//  * evaluating a bounded part of it on a small grid (every field, normals included) and at the
//    ends of the parameter range never crashes, and gives only finite numbers whenever
//    core/diagnostics.h reports no precision warning for the model.
// Sanitizers (address, undefined, leak) and libFuzzer's -timeout turn everything else into a finding.
// The same function is linked into `model_fuzz_replay` (replay_main.cpp) for builds without libFuzzer.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>

#include <glm/geometric.hpp>

#include <shapespline/core/diagnostics.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/io/model_json.h>

namespace {

using namespace shapespline;

// Caps that keep one input well under libFuzzer's per-input time limit.
constexpr size_t kMaxInputBytes = 1 << 16;
constexpr size_t kMaxPoints = 4096;
constexpr size_t kMaxItems = 16;  // spans / patches evaluated per input

[[noreturn]] void finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "model_fuzzer: %s: %s\n", what, detail.c_str());
  std::abort();
}

// Every requested field of every chunk must be finite (when `mustBeFinite`).
ChunkConsumer finiteChecker(bool mustBeFinite, const char* kind) {
  return [mustBeFinite, kind](const GridChunk& chunk) {
    for (int f = 0; f < kFieldCount; ++f) {
      if (!chunk.planes[f]) continue;
      for (size_t p = 0; p < chunk.pointCount(); ++p)
        for (int axis = 0; axis < 3; ++axis) {
          const double x = chunk.coord(static_cast<Field>(f), p, axis);
          if (mustBeFinite && !std::isfinite(x))
            finding("non-finite output without a precision warning",
                    std::string(kind) + " field " + std::to_string(f) + " point " + std::to_string(p) +
                        " axis " + std::to_string(axis) + " = " + std::to_string(x));
        }
    }
  };
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Built::create(model), or nothing when it refuses the model by the V-overflow rule of the contract
// above; any other exception escapes and is a finding.
template <class Built, class Model>
std::optional<Built> build(const Model& model) {
  try {
    return Built::create(model);
  } catch (const ModelError& e) {
    const bool vOverflow =
        e.field().rfind("alpha[", 0) == 0 &&
        e.rule().find("V = P + ((1-alpha)/alpha)(P - node) exceeds the fp64 range") != std::string::npos;
    if (vOverflow) return std::nullopt;
    throw;
  }
}

void checkRoundTrip(const io::Model& model) {
  const io::Model again = io::parseModel(io::toJson(model));
  if (io::toJson(again).dump() != io::toJson(model).dump()) finding("toJson round trip", io::toJson(model).dump());
}

void evaluateCurve(const CurveModel& model) {
  const bool quiet = precisionWarnings(model).empty();
  const std::optional<Curve> built = build<Curve>(model);
  if (!built) return;
  const Curve& curve = *built;
  const std::vector<int> items = curveGridItems(curve);
  GridSpec grid;
  grid.samplesU = 5;
  grid.itemCount = std::min(items.size(), kMaxItems);
  if (grid.itemCount == 0) return;
  const FieldMask fields = fieldBit(Field::Point) | fieldBit(Field::D1) | fieldBit(Field::D2);
  sampleCurveGrid(curve, grid, fields, finiteChecker(quiet, "curve"), {.threads = 1});
  const auto [lo, hi] = curve.parameterRange();
  for (double u : {lo, hi}) {
    const CurvePoint p = curve.evaluateAt(u);
    if (quiet && !(finite(p.point) && finite(p.d1) && finite(p.d2)))
      finding("non-finite evaluateAt without a precision warning", std::to_string(u));
  }
}

void evaluateSurface(const SurfaceModel& model) {
  const bool quiet = precisionWarnings(model).empty();
  const std::optional<Surface> built = build<Surface>(model);
  if (!built) return;
  const Surface& surface = *built;
  const auto items = surfaceGridItems(surface);
  GridSpec grid;
  grid.samplesU = 3;
  grid.samplesV = 3;
  grid.itemCount = std::min(items.size(), kMaxItems);
  if (grid.itemCount == 0) return;
  FieldMask fields = 0;
  for (Field f : {Field::Point, Field::Du, Field::Dv, Field::Duu, Field::Duv, Field::Dvv, Field::Normal})
    fields |= fieldBit(f);
  sampleSurfaceGrid(surface, grid, fields, finiteChecker(quiet, "surface"), {.threads = 1});
  const auto [u0, u1] = surface.parameterRangeU();
  const auto [v0, v1] = surface.parameterRangeV();
  for (double u : {u0, u1})
    for (double v : {v0, v1}) {
      const SurfacePoint p = surface.evaluateAt(u, v);
      if (!finite(p.normal) || std::abs(glm::length(p.normal) - 1.0) > 1e-6)
        finding("surface normal not a unit vector", std::to_string(u) + ", " + std::to_string(v));
      if (quiet && !(finite(p.point) && finite(p.du) && finite(p.dv) && finite(p.duu) && finite(p.duv) &&
                     finite(p.dvv)))
        finding("non-finite evaluateAt without a precision warning", std::to_string(u) + ", " + std::to_string(v));
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > kMaxInputBytes) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  io::Model model;
  try {
    model = io::parseModelText(text);
  } catch (const ModelError&) {
    return 0;  // the expected way to reject input
  }
  const size_t points = std::visit([](const auto& m) { return m.points.size(); }, model);
  if (points > kMaxPoints) return 0;
  checkRoundTrip(model);
  // Past this point the model is valid (build() lets the contract's V-overflow refusal through): any
  // exception is a finding (libFuzzer reports it as a crash).
  std::visit(
      [](const auto& m) {
        if constexpr (std::is_same_v<std::decay_t<decltype(m)>, CurveModel>)
          evaluateCurve(m);
        else
          evaluateSurface(m);
      },
      model);
  return 0;
}
