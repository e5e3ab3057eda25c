// `shapespline sample MODEL -o OUT`: a regular grid per span/patch, streamed chunk by chunk into
// the writer chosen by the output extension, through a temporary file renamed at the end.
#include <shapespline/cli/cmd_sample.h>
#include <shapespline/cli/common.h>
#include <shapespline/jobs/shard_files.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/orientation.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/shard_info.h>
#include <shapespline/io/streamed_bands.h>
#include <shapespline/io/streamed_net.h>
#include <shapespline/jobs/shard_record.h>
#include <shapespline/io/part_manifest.h>
#include <shapespline/io/trimmed_points.h>
#include <shapespline/io/welded_mesh.h>
#include <shapespline/sampling/gpu_limits.h>
#include <shapespline/sampling/net_scale.h>
#include <shapespline/sampling/session.h>

#include <algorithm>
#include <atomic>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <future>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string_view>
#include <thread>

namespace shapespline::cli {
namespace {

constexpr int kMaxSamplesPerDirection = 65536;
constexpr double kMaxTotalPoints = 1e12;
constexpr size_t kMaxSvgPoints = 2'000'000;

int parseCount(const std::string& text, const std::string& field) {
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE) {
    throw InputError(field, text, "expected a positive integer");
  }
  if (v < 2 || v > kMaxSamplesPerDirection) {
    throw InputError(field, text, "samples per direction must be in [2, " + std::to_string(kMaxSamplesPerDirection) + "]");
  }
  return static_cast<int>(v);
}

std::pair<int, int> parseShard(const std::string& text) {
  if (text.empty()) return {1, 1};
  const size_t slash = text.find('/');
  if (slash == std::string::npos) throw InputError("--shard", text, "expected K/N with 1 <= K <= N");
  char* e1 = nullptr;
  char* e2 = nullptr;
  const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
  const long long k = std::strtoll(a.c_str(), &e1, 10), n = std::strtoll(b.c_str(), &e2, 10);
  if (a.empty() || b.empty() || *e1 || *e2 || n < 1 || k < 1 || k > n || n > 1'000'000'000) {
    throw InputError("--shard", text, "expected K/N with 1 <= K <= N");
  }
  return {static_cast<int>(k), static_cast<int>(n)};
}

constexpr long long kMaxChunkPoints = 1LL << 22;

// Index of the first value of v[0, n) outside [-limit, limit] (NaN included), or n. SSE2 compares
// 8 values a step where the compiler keeps a scalar loop (it does not vectorise the early exit),
// so that the check costs a fraction of the writing.
size_t firstOutOfRange(const double* v, size_t n, double limit) {
  size_t i = 0;
#if defined(__SSE2__)
  const __m128d lim = _mm_set1_pd(limit);
  const __m128d abs = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffff));
  for (; i + 8 <= n; i += 8) {
    __m128d bad = _mm_setzero_pd();
    for (size_t j = 0; j < 8; j += 2) bad = _mm_or_pd(bad, _mm_cmpnle_pd(_mm_and_pd(_mm_loadu_pd(v + i + j), abs), lim));
    if (_mm_movemask_pd(bad)) break;
  }
#endif
  for (; i < n; ++i) {
    if (!(std::abs(v[i]) <= limit)) return i;
  }
  return n;
}

size_t firstOutOfRange(const float* v, size_t n, float limit) {
  size_t i = 0;
#if defined(__SSE2__)
  const __m128 lim = _mm_set1_ps(limit);
  const __m128 abs = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  for (; i + 16 <= n; i += 16) {
    __m128 bad = _mm_setzero_ps();
    for (size_t j = 0; j < 16; j += 4) bad = _mm_or_ps(bad, _mm_cmpnle_ps(_mm_and_ps(_mm_loadu_ps(v + i + j), abs), lim));
    if (_mm_movemask_ps(bad)) break;
  }
#endif
  for (; i < n; ++i) {
    if (!(std::abs(v[i]) <= limit)) return i;
  }
  return n;
}

// Every value must be finite in the precision the file stores (`fileFloat`: fp32 PLY/raw/CSV, where
// an fp64 value beyond 3.4e38 would become inf).
void requireFinite(const GridChunk& c, size_t firstPoint, size_t pointCount, bool fileFloat) {
  const size_t n = pointCount * 3, start = firstPoint * 3;
  const double limit = fileFloat ? static_cast<double>(std::numeric_limits<float>::max())
                                 : std::numeric_limits<double>::max();
  for (int f = 0; f < kFieldCount; ++f) {
    const void* p = c.planes[static_cast<size_t>(f)];
    if (!p) continue;
    const size_t k = c.precision == Precision::Double
                         ? firstOutOfRange(static_cast<const double*>(p) + start, n, limit)
                         : firstOutOfRange(static_cast<const float*>(p) + start, n, std::numeric_limits<float>::max());
    if (k == n) continue;
    const size_t i = start + k;
    const double v = c.coord(static_cast<Field>(f), i / 3, static_cast<int>(i % 3));
    const std::string field(io::fieldName(static_cast<Field>(f)));
    const std::string item = std::to_string(c.itemOf(i / 3));
    // ±inf from a sound evaluation is a value beyond the precision (derivatives of knot
    // intervals near 1e-310 grow like 1/h^r); NaN is an internal error.
    throw RuntimeError(field, number17(v) + " at item " + item,
                       std::isfinite(v) || (std::isinf(v) && c.precision == Precision::Float)
                           ? beyondRangeRule(Precision::Float)
                       : std::isinf(v) ? beyondRangeRule(Precision::Double)
                                       : "evaluation produced a non-finite value (internal error); nothing "
                                         "was written");
  }
}

// SHAPESPLINE_FAULT=nan: the checks and the writer see a copy of the job's first slice (its first
// `points` points) with a NaN in its first value.
GridChunk withInjectedNan(const GridChunk& c, size_t points, std::vector<double>& d, std::vector<float>& f) {
  GridChunk out = c;
  const size_t n = points * 3;
  const size_t k = static_cast<size_t>(Field::Point);
  if (c.precision == Precision::Double) {
    d.assign(static_cast<const double*>(c.planes[k]), static_cast<const double*>(c.planes[k]) + n);
    d[0] = std::numeric_limits<double>::quiet_NaN();
    out.planes[k] = d.data();
  } else {
    f.assign(static_cast<const float*>(c.planes[k]), static_cast<const float*>(c.planes[k]) + n);
    f[0] = std::numeric_limits<float>::quiet_NaN();
    out.planes[k] = f.data();
  }
  return out;
}

}  // namespace

void requireTrimmedShardFormat(const SampleArgs& args, io::OutputFormat format) {
  if (!args.shard.empty() && !io::trimmedShardFormat(format))
    throw InputError("--shard", args.shard,
                     "shards of trimmed faces and parts are written as .npy, .f32, .f64 or .ply, which carry the "
                     "shard's identity for merge (a CSV cannot)");
}

namespace {

// --trim (docs/cad.md): a surface with trim loops, a point-cloud output.
void requireTrimmable(const SampleArgs& args, const io::Model& model, io::OutputFormat format) {
  const auto* surface = std::get_if<SurfaceModel>(&model);
  if (!surface || surface->trim.empty())
    throw InputError("--trim", args.model, "the model has no trim loops (the faces `shapespline import` writes have them)");
  if (!io::trimmedPointFormat(format))
    throw InputError("-o", args.out,
                     "a trimmed face is written as a mesh (.ply, .obj, .stl, .glb or .gltf without --grid) or as a "
                     "point cloud (.npy, .f32, .f64, .csv or .ply)");
  requireTrimmedShardFormat(args, format);
  if (args.meshLayoutGiven) throw InputError("--mesh-layout", args.meshLayout, "does not apply to --trim (a point cloud)");
}

// The first item of shard k + 1 of n (io/shard_info.h).
size_t shardBound(size_t total, int k, int shards) {
  return io::shardBound(total, static_cast<uint64_t>(k), static_cast<uint64_t>(shards));
}

// Whether this job could stream its net: a shard (only a shard can have no items) or a job whose
// net may stream in bands (`bands`), that neither saves the model nor trims (both need the built
// surface).
bool mayStreamNet(const SampleArgs& args, int shards, bool bands) {
  return (shards > 1 || bands) && args.saveModel.empty() && !args.trim;
}

// Whether shard k of n of a surface of this (valid) shape has no items, and nothing else about it
// needs the net: a welded mesh of a closed surface takes its orientation from the net's volume.
bool shardHasNoItems(const SurfaceShape& shape, int k, int n, io::OutputFormat format, const SampleArgs& args) {
  if (io::isMesh(format) && args.meshLayout == "welded" && shape.closedU && shape.closedV) return false;
  const size_t total = surfaceGridItems(shape).size();
  return shardBound(total, k - 1, n) == shardBound(total, k, n);
}

// The spans of a curve whose points are a file (its outline), when it streams: it is first read
// that way only (`bands`: a job started again whole reads it whole), and its SVG picture needs
// its points.
std::optional<SpanRange> streamedCurveSpans(const CurveModel& shape, const io::ModelArrays& arrays,
                                            io::OutputFormat format, bool bands) {
  if (!bands || format == io::OutputFormat::Svg || !io::curveSpansCanStream(shape, arrays)) return std::nullopt;
  return uniformCurveSpans(shape, static_cast<int>(io::outlineCounts(shape, arrays).points));
}

// A job sampled while its net streams in bands (io/streamed_bands.h), never holding it whole: a
// uniform-span net in files (`canStream`), a format that takes the job's identity last, and no
// shard record of an earlier run (resuming compares the fingerprint, which needs the whole net first).
bool streamsInBands(bool canStream, io::OutputFormat format, const SampleArgs& args) {
  return canStream && io::identityWrittenAtFinish(format) &&
         (args.shard.empty() || !std::filesystem::exists(jobs::shardRecordPath(args.out)));
}

// The layout of a streamed curve's grid from its spans (its points not held): one item a span,
// computed when asked (io::SampleLayout::spanRows).
void setCurveItems(const CurveModel& shape, SpanRange spans, io::SampleLayout& layout) {
  layout.spanRows = spans;
  layout.spanKnots = shape.knots;
  layout.spanV = {0};
  layout.paramV = {{0.0, 0.0}};
  layout.totalItems = layout.rowCount();
  layout.dimension = shape.dimension;
  layout.closed = shape.closed;
}

// The patch rows the items [first, first + count) of a surface's grid lie in (none for no items).
SpanRange patchRowsOf(const io::SampleLayout& layout, size_t first, size_t count) {
  if (count == 0) return {0, -1};
  return {layout.rowSpan(first / layout.itemsV), layout.rowSpan((first + count - 1) / layout.itemsV)};
}

// `options` for a band whose item 0 is item `offset` of the job: its slices and records see the
// job's item numbers, as the writer places them.
sampling::GridOptions bandOptions(const sampling::GridOptions& options, size_t offset) {
  sampling::GridOptions o = options;
  auto shifted = [offset](const GridChunk& c) {
    GridChunk whole = c;
    whole.firstItem += offset;
    return whole;
  };
  if (options.slice)
    o.slice = [slice = options.slice, shifted](const GridChunk& c, size_t first, size_t count) {
      slice(shifted(c), first, count);
    };
  if (options.records.submit)
    o.records.submit = [submit = options.records.submit, shifted](RecordBlock block, const GridChunk& c, size_t first,
                                                                   size_t count) {
      submit(std::move(block), shifted(c), first, count);
    };
  return o;
}

// The items of the job `grid` (whole-job numbers) in patch rows (a curve's spans) first..last of
// `band`, sampled as `request` asks and delivered with the job's item numbers (a band's item 0 is
// its first row's first item).
template <class Band>
void sampleBand(sampling::Session& session, const Band& band, int first, int last, const io::SampleLayout& layout,
                const GridSpec& grid, FieldMask fields, const ChunkConsumer& sink, const sampling::GridOptions& options,
                const sampling::DeviceRequest& request) {
  const size_t bandFirst = static_cast<size_t>(first - layout.rowSpan(0)) * layout.itemsV;
  const size_t bandEnd = static_cast<size_t>(last + 1 - layout.rowSpan(0)) * layout.itemsV;
  const size_t a = std::max(bandFirst, grid.firstItem), b = std::min(bandEnd, grid.firstItem + grid.itemCount);
  GridSpec g = grid;
  g.firstItem = a - bandFirst;
  g.itemCount = b - a;
  session.sampleGrid(
      band, request, g, fields,
      [&](const GridChunk& c) {
        GridChunk whole = c;
        whole.firstItem += bandFirst;
        sink(whole);
      },
      bandOptions(options, bandFirst));
}

// The α-EB vertex rule (§4.2) over a net that streamed, where the bound from its points could not
// clear every vertex: the built surface checks each (ModelError naming the first).
void requireFiniteVerticesOf(const SampleArgs& args) {
  (void)Surface::create(std::get<SurfaceModel>(loadModel(args.model, args.allowOutsideArrays, nullptr, nullptr)));
}

// Thrown by a job whose net streamed in bands when it must start again whole: the stream stopped
// at an error other than a failed write (the whole job names its own, which may be another
// value's: its rules run before any sample), or a band was planned otherwise than the whole net would be (another device,
// another scale). Not a std::exception: sampleInto catches it before anything reports it.
struct StartAgainWhole {};

}  // namespace

namespace {

// What a file of `format` stores of values computed for `precision`: the job metadata's precision.
Precision storedPrecisionOf(io::OutputFormat format, Precision precision) {
  if (format == io::OutputFormat::RawF32 || io::isGltf(format)) return Precision::Float;
  if (format == io::OutputFormat::RawF64) return Precision::Double;
  return precision;
}

// sampleInto's job (its arguments resolved) on `session`. `bands`: the net may stream in bands;
// `noticesShown`: an earlier try of the job printed the plan's notices.
bool sampleJob(const SampleArgs& args, io::OutputSet& outputs, std::string& summary, sampling::Session& session,
               bool bands, bool noticesShown) {
  const io::OutputFormat format = io::outputFormatFromPath(args.out, "-o");
  sampling::DeviceRequest request = parseDeviceRequest(args.device, args.precision, args.requireDevice);
  request.grid = true;  // the report before output is that of the grid job (bands of a large net)
  const Precision precision = request.precision;
  const auto [shardK, shardN] = parseShard(args.shard);
  if (io::isGltf(format) && shardN > 1) {
    throw InputError("--shard", args.shard,
                     "glTF files are re-centred fp32 meshes held in memory and are not merged; shard to .ply or .obj");
  }
  requireThreadCount(args.threads);
  if (args.chunkPoints < 0 || args.chunkPoints > kMaxChunkPoints) {
    throw InputError("--chunk-points", std::to_string(args.chunkPoints),
                     "must be in [1, " + std::to_string(kMaxChunkPoints) + "] (0 = default)");
  }

  // A part's manifest (`shapespline import`): its mesh (part_mesh.cpp), or every face, trimmed, into
  // one point cloud (part_sample.cpp).
  const bool part = io::isPartManifest(args.model);
  if (meshesTrimmed(args, format, part)) return meshPartInto(args, format, request, outputs, summary, session);
  for (const auto& [option, value] : {std::pair{"--deflection", args.mesh.deflection},
                                      {"--relative-deflection", args.mesh.relativeDeflection}, {"--angle", args.mesh.angle}})
    if (!value.empty())
      throw InputError(option, value, "applies to the mesh of a part or a trimmed face (.ply, .obj, .stl, .glb, .gltf)");
  std::vector<std::filesystem::path> arrayFiles;  // the .npy files the model read
  std::optional<io::ModelDigest> modelDigest;  // the metadata's SHA-256, hashed beside the parse and build
  if (!part) modelDigest.emplace(args.model);
  if (!part) session.prepare(request);  // the device, also beside the parse
  // A net in files need not be held: a shard with no items streams it through its rules and the
  // job's fingerprint (io/streamed_net.h), and a job on the CPU samples it in bands as it streams
  // (io/streamed_bands.h). The model is first read as an outline (its array files' headers), and
  // in full only when neither applies.
  io::ModelArrays outline;
  io::Model model;
  bool banded = false;
  if (!part && mayStreamNet(args, shardN, bands)) {
    bool whole = false;
    try {
      model = loadModelOutline(args.model, args.allowOutsideArrays, outline, &*modelDigest);
      arrayFiles = outline.files;
      const auto* shape = std::get_if<SurfaceModel>(&model);
      const auto* curveShape = std::get_if<CurveModel>(&model);
      const std::optional<SpanRange> spans = curveShape ? streamedCurveSpans(*curveShape, outline, format, bands)
                                                        : std::nullopt;
      const size_t spanCount = spans ? static_cast<size_t>(spans->last - spans->first + 1) : 0;
      const bool none = (shape && shardHasNoItems(*shape, shardK, shardN, format, args)) ||
                        (spans && shardBound(spanCount, shardK - 1, shardN) == shardBound(spanCount, shardK, shardN));
      banded = !outline.deferred.empty() && !none && bands &&
               streamsInBands(shape ? io::bandsCanStream(*shape, outline) : spans.has_value(), format, args);
      whole = !outline.deferred.empty() && !none && !banded;
    } catch (const ModelError&) {
      whole = true;  // the full parse names the error (its rules on the values come before the shape's)
    }
    if (whole) {
      outline = {};
      model = loadModel(args.model, args.allowOutsideArrays, &arrayFiles, nullptr);  // the digest has its files
    }
  } else if (!part) {
    model = loadModel(args.model, args.allowOutsideArrays, &arrayFiles, &*modelDigest);
  }
  const bool streamed = !outline.deferred.empty();
  const bool isSurface = part || std::holds_alternative<SurfaceModel>(model);
  if (!part && !streamed) std::visit([&](const auto& m) { requireFloatRange(m.points, precision); }, model);
  if (args.trim && !part) requireTrimmable(args, model, format);

  int su = 0, sv = 1;
  if (isSurface) {
    if (!args.grid.empty()) {
      const size_t x = args.grid.find_first_of("xX");
      su = parseCount(args.grid.substr(0, x), "--grid");
      sv = x == std::string::npos ? su : parseCount(args.grid.substr(x + 1), "--grid");
    } else if (!args.samples.empty()) {
      su = sv = parseCount(args.samples, "--samples");
    } else {
      su = sv = 16;
    }
  } else {
    if (!args.grid.empty()) throw InputError("--grid", args.grid, "curves take --samples N per span");
    su = !args.samples.empty() ? parseCount(args.samples, "--samples") : 32;
  }
  const std::string countField = isSurface ? "--grid" : "--samples";

  FieldMask fields = io::requiredFields(format, isSurface);
  if (args.derivatives) {
    fields |= isSurface ? fieldBit(Field::Du) | fieldBit(Field::Dv) | fieldBit(Field::Duu) | fieldBit(Field::Duv) |
                              fieldBit(Field::Dvv)
                        : fieldBit(Field::D1) | fieldBit(Field::D2);
  }
  if (args.normals) {
    if (!isSurface) throw InputError("--normals", "", "curves have no normals (surfaces only)");
    fields |= fieldBit(Field::Normal);
  }
  if (!args.fields.empty()) fields |= parseFields(args.fields, isSurface, args.derivatives || args.normals);
  if (format == io::OutputFormat::Svg && isSurface) {
    throw InputError("-o", args.out, "SVG output is for curves only (use .obj, .ply, .csv, .f32, .f64 or .npy)");
  }

  std::optional<Curve> curve;
  std::optional<Surface> surface;
  io::SampleLayout layout;
  layout.surface = isSurface;
  layout.samplesU = su;
  layout.samplesV = sv;
  layout.fields = fields;
  layout.precision = precision;
  const std::string& modelName = args.modelName.empty() ? args.model : args.modelName;
  layout.source = modelName;
  layout.shardIndex = shardK;
  layout.shardCount = shardN;
  // What the file stores: raw .f32, or PLY/CSV/OBJ/.npy after --precision float.
  const bool fileFloat = format == io::OutputFormat::RawF32 || io::isGltf(format) ||
                         (precision == Precision::Float && format != io::OutputFormat::RawF64 &&
                          format != io::OutputFormat::Svg);
  if (part) {
    PartJob job{format, request, su, sv, fields, precision, {}};
    job.storedPrecision = storedPrecisionOf(format, precision);
    job.shardK = shardK;
    job.shardN = shardN;
    job.check = [fileFloat](const GridChunk& c, size_t first, size_t count) { requireFinite(c, first, count, fileFloat); };
    return samplePartInto(args, job, outputs, summary, &session);
  }
  io::requireGridFormat(format, args.out, "-o");
  const bool meshFormat = io::isMesh(format);
  if (args.meshLayout != "welded" && args.meshLayout != "per-item") {
    throw InputError("--mesh-layout", args.meshLayout, "expected welded or per-item");
  }
  if (args.meshLayoutGiven && !meshFormat) {
    throw InputError("--mesh-layout", args.meshLayout,
                     "does not apply to " + std::string(io::outputFormatName(format)) +
                         " output (mesh outputs only: .obj, .ply, .glb, .gltf)");
  }
  if (args.meshLayout == "per-item" && (!meshFormat || io::isGltf(format))) {
    throw InputError("--mesh-layout", args.meshLayout, "per-item layouts are for .obj and .ply outputs");
  }
  layout.welded = meshFormat && args.meshLayout == "welded" && !args.trim;
  size_t bandCount = 0;  // bands sampled as the net streamed
  if (streamed && isSurface) {
    io::setSurfaceItems(std::get<SurfaceModel>(model), layout);
  } else if (streamed) {
    const CurveModel& shape = std::get<CurveModel>(model);
    setCurveItems(shape, *streamedCurveSpans(shape, outline, format, bands), layout);
  } else if (isSurface) {
    surface.emplace(Surface::create(std::get<SurfaceModel>(std::move(model))));
    io::setSurfaceItems(surface->model(), layout);
  } else {
    curve.emplace(Curve::create(std::get<CurveModel>(std::move(model))));
    layout.spanU = curveGridItems(*curve);
    layout.spanV = {0};
    layout.paramV = {{0.0, 0.0}};
    layout.totalItems = layout.spanU.size();
    layout.dimension = curve->dimension();
    for (int s : layout.spanU) layout.paramU.emplace_back(curve->parameterOf(s, 0.0), curve->parameterOf(s, 1.0));
    layout.controlPoints = curve->model().points;
    layout.closed = curve->model().closed;
    for (int s : layout.spanU) layout.dataPoints.push_back(curve->evaluate(s, 0.0).point);
    if (!layout.spanU.empty() && !layout.closed) layout.dataPoints.push_back(curve->evaluate(layout.spanU.back(), 1.0).point);
  }

  const double totalPoints = static_cast<double>(layout.totalItems) * su * sv;
  if (totalPoints > kMaxTotalPoints) {
    throw InputError(countField, isSurface ? std::to_string(su) + "x" + std::to_string(sv) : std::to_string(su),
                     "the job would produce " + std::to_string(static_cast<long long>(totalPoints)) +
                         " points; at most 1e12 are allowed");
  }
  // A trimmed face's shards balance the samples inside its loops (io::balancedTrimmedShard).
  std::optional<io::TrimmedShard> trimShard;
  if (args.trim && !args.shard.empty()) {
    layout.firstItem = 0;
    layout.itemCount = layout.totalItems;
    trimShard = io::balancedTrimmedShard(io::samplesInsideByItem(layout, surface->model().trim), shardK, shardN);
    trimShard->index = shardK;
    trimShard->count = shardN;
    layout.firstItem = trimShard->firstItem;
    layout.itemCount = trimShard->items;
  } else {
    layout.firstItem = shardBound(layout.totalItems, shardK - 1, shardN);
    layout.itemCount = shardBound(layout.totalItems, shardK, shardN) - layout.firstItem;
  }
  // Every shard of this job (and the unsharded job) carries the same fingerprint; `merge` checks it.
  // A welded mesh of a closed surface faces outwards: flipped when du x dv encloses a negative volume.
  if (layout.welded && surface && layout.closedU && layout.closedV) layout.reversed = signedVolume(*surface) < 0.0;
  std::optional<io::StreamedNet> net;  // a streamed net's values, as the metadata needs them
  std::optional<CurveWarningScan> curveWarnings;  // a streamed curve's precision warnings
  if (streamed && !banded && !isSurface) {
    // A curve's values through its bands' rules (not in the full parse's order: the whole job
    // names the first error) into the fingerprint, its bands built and let go.
    const CurveModel& shape = std::get<CurveModel>(model);
    const SurfaceCounts counts = io::outlineCounts(shape, outline);
    io::CurveFingerprint fingerprint(shape, counts.points, counts.alpha, counts.weights, layout, format);
    curveWarnings.emplace(shape);
    try {
      net = io::streamCurveSpans(shape, outline, fingerprint, {0, -1}, {}, {}, io::kStreamWindowPoints, &*curveWarnings);
    } catch (const ModelError&) {
      throw StartAgainWhole{};
    }
    requireFloatRange(net->largestCoordinate, precision);
    layout.job = fingerprint.finish();
  } else if (streamed && !banded) {
    // The value rules in the full parse's order (a command that is also wrong in its options
    // reports those first here: the values are read only now, with the layout the hash needs).
    const SurfaceModel& shape = std::get<SurfaceModel>(model);
    const SurfaceCounts counts = io::outlineCounts(shape, outline);
    io::SurfaceFingerprint fingerprint(shape, counts.alpha, counts.weights, layout, format);
    net = io::streamSurfaceNet(shape, outline, fingerprint);
    requireFloatRange(net->largestCoordinate, precision);
    layout.job = fingerprint.finish();
    if (!net->verticesShown) requireFiniteVerticesOf(args);
  } else if (!streamed) {
    layout.job = curve ? io::jobFingerprint(curve->model(), layout, format)
                       : io::jobFingerprint(*surface, layout, format);
  }
  // A welded shard also holds the foreign vertices of its items; at most its points either way.
  if (format == io::OutputFormat::Ply && layout.pointCount() > std::numeric_limits<uint32_t>::max() &&
      (!layout.welded || io::WeldedNumbering(layout.weldGrid(), layout.firstItem,
                                             layout.firstItem + layout.itemCount)
                                 .vertexCount() > std::numeric_limits<uint32_t>::max())) {
    throw InputError(countField, std::to_string(layout.pointCount()) + " vertices",
                     "PLY holds at most 2^32-1 vertices; use --shard or a raw format");
  }
  if (io::isGltf(format) && layout.weldGrid().pointCount() > io::kMaxGltfVertices) {
    throw InputError(countField, isSurface ? std::to_string(su) + "x" + std::to_string(sv) : std::to_string(su),
                     "the mesh would have " + std::to_string(layout.weldGrid().pointCount()) +
                         " vertices; glTF output holds at most 2^24 = " + std::to_string(io::kMaxGltfVertices) +
                         " (distinct grid points; the whole mesh is held in memory): use fewer samples, or .ply or .npy");
  }
  if (format == io::OutputFormat::Svg && layout.pointCount() > kMaxSvgPoints) {
    throw InputError(countField, std::to_string(layout.pointCount()) + " points",
                     "SVG output holds at most " + std::to_string(kMaxSvgPoints) + " points");
  }

  // One set: the data and its sidecar appear together or not at all (io/output_set.h).
  outputs.reads(args.model, "MODEL");
  for (const std::filesystem::path& array : arrayFiles) outputs.reads(array, "MODEL's array");
  if (!args.saveModel.empty()) {
    if (std::filesystem::path(args.saveModel).extension() != ".json")
      throw InputError("--save-model", args.saveModel,
                       "must name a model file ending in .json (its arrays are written beside it as STEM.points.npy, ...)");
    if (curve) io::saveModelWithArrays(curve->model(), args.saveModel, outputs, "--save-model");
    else io::saveModelWithArrays(surface->toModel(), args.saveModel, outputs, "--save-model");
  }
  io::AtomicFile& out = outputs.add(args.out, "-o");
  io::AtomicFile* sidecar = nullptr;
  if (io::hasLayoutSidecar(format)) sidecar = &outputs.add(args.out + ".json", "-o");
  if (format == io::OutputFormat::Gltf) sidecar = &outputs.add(io::gltfBufferPath(args.out), "-o");  // OUT.bin
  // A shard (--shard given) also writes its record OUT.shard.json, last in the set (jobs/shard_files.h).
  io::AtomicFile* record = args.shard.empty() ? nullptr : &outputs.add(jobs::shardRecordPath(args.out), "-o");
  const std::string extraRole = format == io::OutputFormat::Gltf ? "buffer" : "sidecar";
  const sampling::Report report = streamed ? session.planDevice(request)
                                 : curve    ? session.plan(*curve, request)
                                            : session.plan(*surface, request);
  printNotices(report, args.quiet || noticesShown);
  layout.device = report.device;
  layout.computedPrecision = report.computedPrecision;
  // The job metadata (io/job_metadata.h), the same for every shard; every .npy gets OUT.npy.json for
  // it. A job whose net streams in bands knows it (and its fingerprint) only once it has sampled.
  auto identify = [&] {
    try {
      const Precision stored = storedPrecisionOf(format, precision);
      layout.metadata = curve ? io::jobMetadataOf(curve->model(), args.model, modelDigest->get(), report.device,
                                                  report.computedPrecision, stored, su)
                        : net && !isSurface ? io::jobMetadataOf(std::get<CurveModel>(model), net->alpha, net->rational,
                                                                args.model, modelDigest->get(), report.device,
                                                                report.computedPrecision, stored, su)
                        : net ? io::jobMetadataOf(std::get<SurfaceModel>(model), net->alpha, net->rational,
                                                  args.model, modelDigest->get(), report.device,
                                                  report.computedPrecision, stored, su, sv)
                              : io::jobMetadataOf(*surface, args.model, modelDigest->get(), report.device,
                                                  report.computedPrecision, stored, su, sv);
    } catch (const std::runtime_error& e) {
      throw InputError("MODEL", args.model, std::string("cannot read the model file for its SHA-256: ") + e.what());
    }
    layout.metadata.modelFile = modelName;
  };
  if (!banded) identify();
  const bool gpuFloat = report.gpu && report.computedPrecision == Precision::Float;
  if (curve) printPrecisionWarnings(curve->model(), gpuFloat, args.quiet);
  if (curveWarnings) printPrecisionWarnings(*curveWarnings, gpuFloat, args.quiet);
  if (surface) printPrecisionWarnings(*surface, gpuFloat, args.quiet);

  // A shard's record; a trimmed face's counts its records inside the loops, under the trimmed job.
  jobs::ShardRecord want;
  if (record && !banded) {
    if (trimShard) trimShard->job = io::trimmedJobFingerprint(layout.job, surface->model().trim);
    want = trimShard ? jobs::trimmedShardRecordOf(layout, format, *trimShard, layout.pointCount())
                     : jobs::shardRecordOf(layout, format);
  }
  // Resume: a shard whose record and files verify is left as it is.
  if (record && !banded &&
      jobs::shardAlreadyDone(want, format, {args.out, sidecar ? sidecar->target().string() : "", extraRole}, args.quiet)) {
    return false;
  }
  std::unique_ptr<io::SampleWriter> writer;
  const io::TrimmedPointWriter* trimmed = nullptr;
  if (args.trim) {
    auto w = std::make_unique<io::TrimmedPointWriter>(format, out, sidecar, surface->model().trim);
    if (record) w->setShard(*trimShard);
    trimmed = w.get();
    writer = std::move(w);
  } else {
    writer = io::makeSampleWriter(format, out, sidecar ? &*sidecar : nullptr);
  }
  writer->begin(layout);
  if (layout.itemCount > 0) {
    Progress progress(layout.pointCount(), args.quiet);
    GridSpec grid;
    grid.samplesU = su;
    grid.samplesV = sv;
    grid.firstItem = layout.firstItem;
    grid.itemCount = layout.itemCount;
    sampling::GridOptions options;
    options.threads = args.threads;
    options.chunkPoints = static_cast<size_t>(args.chunkPoints);
    // Per slice, on the sampler's workers (sampling::GridOptions::slice): the finiteness check
    // and, for the raw and .npy writers, the records themselves, written at their offsets; then
    // per chunk, in order on this thread, the writer's sequential part.
    std::atomic<bool> injectNan = nanFaultInjected();
    options.slice = [&](const GridChunk& chunk, size_t first, size_t count) {
      std::vector<double> nanD;
      std::vector<float> nanF;
      const bool inject = first == 0 && chunk.firstItem == layout.firstItem && chunk.firstItemPoint() == 0 &&
                          injectNan.exchange(false);
      const GridChunk& c = inject ? withInjectedNan(chunk, count, nanD, nanF) : chunk;
      // The raw and .npy writers check the values as they convert them (one pass over the slice
      // instead of two); a slice they did not check, or found a value out of range in, is read
      // again here, which finds and reports the first such value.
      if (!writer->writeSlice(c, first, count)) requireFinite(c, first, count, fileFloat);
    };
    // The raw and .npy records, straight from the CPU sampler's rows (GPU chunks go through the
    // slices above). Not with the NaN fault injection, which lives in the slice path.
    if (auto records = writer->recordSink(); records && !injectNan) options.records = std::move(*records);
    const ChunkConsumer sink = [&](const GridChunk& c) {
      writer->consume(c);
      const bool context = c.firstItem < layout.firstItem || c.firstItem >= layout.firstItem + layout.itemCount;
      if (!context) progress.add(c.pointCount());
    };
    if (banded) {
      // Each band as its rows arrive: its items are the job's from (first - spanU[0]) x itemsV on.
      // Every band is planned as the whole net is (`report`): the device the job planned (a band on
      // the CPU is never offered the GPU), and one scale exponent (sampling/net_scale.h: a job
      // evaluates 2^k x net, k from the whole net's largest coordinate), checked against the whole
      // net's once it has streamed. A curve's bands are sampled at scale 1 only (a scaled curve is
      // built again whole from its points: sampling/net_scale.h scaledCurve).
      sampling::DeviceRequest bandRequest = request;
      if (!report.gpu) bandRequest.device = sampling::DeviceKind::Cpu;
      std::optional<int> exponent;
      auto sampleAsPlanned = [&](const auto& band, int first, int last) {
        ++bandCount;
        const sampling::Report planned = session.plan(band, bandRequest);
        if (planned.gpu != report.gpu || planned.netScaleExponent != exponent.value_or(planned.netScaleExponent))
          throw StartAgainWhole{};
        exponent = planned.netScaleExponent;
        sampleBand(session, band, first, last, layout, grid, fields, sink, options, bandRequest);
      };
      const SpanRange rows = patchRowsOf(layout, layout.firstItem, layout.itemCount);
      try {
        std::unique_ptr<io::NetFingerprint> fingerprint;
        std::optional<SurfaceWarningScan> warnings;
        if (const auto* curveShape = std::get_if<CurveModel>(&model)) {
          const SurfaceCounts counts = io::outlineCounts(*curveShape, outline);
          fingerprint = std::make_unique<io::CurveFingerprint>(*curveShape, counts.points, counts.alpha, counts.weights,
                                                               layout, format);
          if (!args.quiet) curveWarnings.emplace(*curveShape);
          net = io::streamCurveSpans(*curveShape, outline, *fingerprint, rows, sampleAsPlanned, {},
                                     io::kStreamWindowPoints, curveWarnings ? &*curveWarnings : nullptr);
          if (exponent.value_or(0) != 0) throw StartAgainWhole{};
        } else {
          const SurfaceModel& shape = std::get<SurfaceModel>(model);
          const SurfaceCounts counts = io::outlineCounts(shape, outline);
          fingerprint = std::make_unique<io::SurfaceFingerprint>(shape, counts.alpha, counts.weights, layout, format);
          if (!args.quiet) warnings.emplace(shape);
          net = io::streamSurfaceBands(shape, outline, *fingerprint, rows, sampleAsPlanned, {}, io::kStreamWindowPoints,
                                       warnings ? &*warnings : nullptr);
          // The GPU hands an α-EB net with a tiny α to the CPU (rows of a shard's other bands, too).
          if (report.gpu && sampling::gpuLimitation(shape, net->alpha.summary().min, report.computedPrecision))
            throw StartAgainWhole{};
        }
        requireFloatRange(net->largestCoordinate, precision);
        const int wholeExponent = report.gpu ? sampling::netScaleFor(net->largestCoordinate, report.computedPrecision)
                                             : sampling::cpuNetScaleFor(net->largestCoordinate);
        if (exponent != wholeExponent) throw StartAgainWhole{};
        layout.job = fingerprint->finish();
        if (!net->verticesShown) requireFiniteVerticesOf(args);  // outside this shard's bands
        identify();
        if (warnings)  // they need the whole net
          printPrecisionWarnings(*warnings, std::get<SurfaceModel>(model).cols, gpuFloat, args.quiet);
        if (curveWarnings) printPrecisionWarnings(*curveWarnings, gpuFloat, args.quiet);
      } catch (const StartAgainWhole&) {
        throw;
      } catch (const io::OutputWriteError&) {
        throw;  // the file system's failure (exit 3): sampling again would meet it again
      } catch (...) {
        throw StartAgainWhole{};
      }
      writer->setIdentity(layout.job, layout.metadata);
    } else {
      // A welded shard also samples its context (the outside items that share its points), in item
      // order around its own items, so that its vertices equal the unsharded file's (io/welded_mesh.h).
      for (const auto& [a, b] : io::streamedItemRanges(format, layout)) {
        GridSpec g = grid;
        g.firstItem = a;
        g.itemCount = b - a;
        if (curve) {
          session.sampleGrid(*curve, request, g, fields, sink, options);
        } else {
          session.sampleGrid(*surface, request, g, fields, sink, options);
        }
      }
    }
  }
  writer->finish();
  if (record) {
    out.flushToTemp();
    if (sidecar) sidecar->flushToTemp();
    if (banded) want = jobs::shardRecordOf(layout, format);  // its job known once the net has streamed
    jobs::writeShardRecord(*record, want, out, sidecar, extraRole);
  }
  summary = "wrote " + args.out + " (" + std::to_string(layout.itemCount) + (isSurface ? " patches, " : " spans, ") +
            std::to_string(layout.pointCount()) + " points" +
            (trimmed ? ", " + std::to_string(trimmed->kept()) + " inside the trim loops" : std::string()) +
            (banded ? ", the net read in " + std::to_string(bandCount) + " bands as they were sampled" : std::string()) +
            (sidecar ? (format == io::OutputFormat::Gltf ? ", buffer in " : ", layout in ") + sidecar->target().string()
                     : std::string()) +
            ")";
  return true;
}

}  // namespace

bool sampleInto(const SampleArgs& given, io::OutputSet& outputs, std::string& summary, sampling::Session* shared) {
  // --shard auto and a shard pattern in -o first (jobs/shard_files.h): the rest sees K/N and a path.
  SampleArgs args = given;
  const jobs::ShardOutput shardOut = jobs::resolveShardOutput(given.out, given.shard, given.shardCount);
  args.out = shardOut.out;
  args.shard = shardOut.shard;
  std::optional<sampling::Session> own;
  sampling::Session& session = shared ? *shared : own.emplace();
  try {
    return sampleJob(args, outputs, summary, session, true, false);
  } catch (const StartAgainWhole&) {
    // Whatever the bands wrote is discarded; the whole job then fails as it fails, or writes.
    outputs.clear();
    return sampleJob(args, outputs, summary, session, false, true);
  }
}

namespace {

// One job and its output set, committed (or discarded when a shard's record verified).
void sampleAndCommit(const SampleArgs& args) {
  io::OutputSet outputs;
  std::string summary;
  if (!sampleInto(args, outputs, summary, nullptr)) {
    outputs.discard();
    return;
  }
  outputs.commit();
  if (!args.quiet) std::fprintf(stderr, "shapespline: %s\n", summary.c_str());
}

constexpr const char* kStem = "{stem}";

// MODEL... with each folder replaced by its *.json files, in name order.
std::vector<std::string> expandModels(const std::vector<std::string>& given) {
  std::vector<std::string> models;
  for (const std::string& m : given) {
    std::error_code ec;
    if (!std::filesystem::is_directory(m, ec)) {
      models.push_back(m);
      continue;
    }
    std::vector<std::string> inFolder;
    for (const auto& entry : std::filesystem::directory_iterator(m, ec))
      if (entry.path().extension() == ".json" && !entry.is_directory()) inFolder.push_back(entry.path().string());
    if (ec) throw InputError("MODEL", m, "cannot list the folder: " + ec.message());
    if (inFolder.empty()) throw InputError("MODEL", m, "the folder holds no .json model");
    std::sort(inFolder.begin(), inFolder.end());
    models.insert(models.end(), inFolder.begin(), inFolder.end());
  }
  return models;
}

std::string withStem(std::string pattern, const std::string& stem) {
  for (size_t at = pattern.find(kStem); at != std::string::npos; at = pattern.find(kStem, at + stem.size()))
    pattern.replace(at, std::string_view(kStem).size(), stem);
  return pattern;
}

// A model's finished output set, committing on the CommitThread while the next model samples.
struct PendingCommit {
  std::string model, summary;
  std::unique_ptr<io::OutputSet> outputs;
  std::future<void> done;
};

// The thread a batch commits its output sets on, in order: one for the batch (a thread per model
// cost its start and join for every model). Destroyed, it first commits what it was given, so that
// no set is destroyed while it is being committed.
class CommitThread {
 public:
  CommitThread() : thread_([this] { run(); }) {}
  ~CommitThread() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    changed_.notify_one();
    thread_.join();
  }
  CommitThread(const CommitThread&) = delete;
  CommitThread& operator=(const CommitThread&) = delete;

  // `set` committed on the thread; the future holds its error.
  std::future<void> commit(io::OutputSet& set) {
    std::packaged_task<void()> task([&set] { set.commit(); });
    std::future<void> done = task.get_future();
    {
      std::lock_guard lock(mutex_);
      queue_.push_back(std::move(task));
    }
    changed_.notify_one();
    return done;
  }

 private:
  void run() {
    std::unique_lock lock(mutex_);
    while (true) {
      changed_.wait(lock, [&] { return stop_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stop_, and nothing left to commit
      std::packaged_task<void()> task = std::move(queue_.front());
      queue_.pop_front();
      lock.unlock();
      task();  // a failure goes to the task's future
      lock.lock();
    }
  }

  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::packaged_task<void()>> queue_;
  bool stop_ = false;
  std::thread thread_;
};

// Between models glibc hands the freed chunk buffers back to the kernel (it trims the heap's top
// beyond 128 KiB) and the next model faults them in again: a third of the user time of a batch of
// small models on a VM. A batch keeps up to 64 MiB of freed heap; blocks from 32 MiB (a big net)
// still come from and go back to the kernel.
void keepFreedMemory() {
#ifdef __GLIBC__
  ::mallopt(M_TRIM_THRESHOLD, 64 << 20);
  ::mallopt(M_MMAP_THRESHOLD, 32 << 20);
#endif
}

// Several models on one session: its device is set up and each pipeline compiled once. Model k's
// outputs are committed (flushed to disk and renamed, io::OutputSet) while model k + 1 is sampled;
// each model's line (its summary, or its error) is still printed in model order.
void sampleMany(const SampleArgs& args, const std::vector<std::string>& models) {
  if (args.out.find(kStem) == std::string::npos)
    throw InputError("-o", args.out, "several models need {stem} in the output name (e.g. out/{stem}.npy)");
  if (!args.shard.empty()) throw InputError("--shard", args.shard, "does not apply to several models");
  if (!args.saveModel.empty() && args.saveModel.find(kStem) == std::string::npos)
    throw InputError("--save-model", args.saveModel, "several models need {stem} in the saved model's name");
  std::set<std::string> outs;
  for (const std::string& m : models)
    if (!outs.insert(withStem(args.out, std::filesystem::path(m).stem().string())).second)
      throw InputError("MODEL", m, "another model has the same file stem: their outputs would be one file");
  keepFreedMemory();
  sampling::Session session;
  size_t failed = 0;
  auto failedOn = [&](const std::string& model, const std::exception& e) {  // only inside a catch
    if (args.failFast) throw;  // the exception being handled
    ++failed;
    std::fprintf(stderr, "shapespline: error: %s: %s\n", model.c_str(), e.what());
  };
  std::optional<PendingCommit> pending;
  CommitThread committer;  // after `pending`: destroyed first, it finishes the pending commit
  auto settle = [&] {  // waits for the previous model's commit and prints its line
    if (!pending) return;
    PendingCommit p = std::move(*pending);
    pending.reset();
    try {
      p.done.get();
      if (!args.quiet) std::fprintf(stderr, "shapespline: %s\n", p.summary.c_str());
    } catch (const std::exception& e) {
      failedOn(p.model, e);
    }
  };
  for (const std::string& m : models) {
    SampleArgs one = args;
    one.model = m;
    one.models = {m};
    one.out = withStem(args.out, std::filesystem::path(m).stem().string());
    if (!args.saveModel.empty()) one.saveModel = withStem(args.saveModel, std::filesystem::path(m).stem().string());
    auto outputs = std::make_unique<io::OutputSet>();
    std::string summary;
    bool wrote = false;
    try {
      wrote = sampleInto(one, *outputs, summary, &session);
    } catch (const std::exception& e) {
      outputs.reset();  // its temporary files go before anything is reported
      settle();
      failedOn(m, e);
      continue;
    }
    settle();
    if (!wrote) continue;  // (the set is discarded with `outputs`)
    std::future<void> done = committer.commit(*outputs);
    pending = PendingCommit{m, std::move(summary), std::move(outputs), std::move(done)};
  }
  settle();
  if (failed)
    throw BatchFailure(std::to_string(failed) + " of " + std::to_string(models.size()) +
                       " models failed (each reported above); the others were written");
}

}  // namespace

void runSample(const SampleArgs& args) {
  const std::vector<std::string> models = expandModels(args.models);
  // A folder, several files, or {stem} in -o: the batch form, even for one model.
  const bool several = models != args.models || models.size() > 1 || args.out.find(kStem) != std::string::npos;
  if (several) return sampleMany(args, models);
  SampleArgs one = args;
  one.model = models[0];
  sampleAndCommit(one);
}

void registerSample(CLI::App& app) {
  auto args = std::make_shared<SampleArgs>();
  CLI::App* sub = app.add_subcommand("sample", "Sample a model on a regular grid per span/patch and write a file.");
  sub->add_option("MODEL", args->models,
                  "model file (docs/format.md); several, or a folder of .json models, are sampled in one process "
                  "with -o naming each output by {stem} (the model's file name without .json)")
      ->required();
  sub->add_option("-o,--output", args->out,
                  "output file; format from the extension: .obj .ply .csv .svg .glb .gltf (+ OUT.bin) .f32 .f64 .npy "
                  "(each + OUT.json sidecar), .stl (part meshes only); a shard pattern names each shard: out-{shard:05d}-of-{count:05d}.f32")
      ->required();
  sub->add_option("--samples", args->samples, "samples per span (curves, default 32; both ends included)");
  sub->add_option("--mesh-layout", args->meshLayout,
                  "welded (default): .obj/.ply/.glb/.gltf list every grid point once, shared edges and closed seams "
                  "by index; per-item (.obj/.ply): each patch/span on its own, shared edges repeated");
  sub->add_option("--grid", args->grid, "samples per patch, U or UxV (surfaces, default 16x16)");
  sub->add_option("--device", args->device,
                  "auto (default) or vulkan: the GPU, falling back to the CPU with a notice; cpu: the CPU fp64 path");
  sub->add_option("--precision", args->precision, "float or double (default double)");
  sub->add_flag("--derivatives", args->derivatives, "also write derivatives (d1, d2 / du, dv, duu, duv, dvv)");
  sub->add_flag("--normals", args->normals, "also write unit normals (surfaces)");
  sub->add_option("--fields", args->fields,
                  "the sampled fields, comma-separated: point, du, dv, duu, duv, dvv, normal (surfaces) or point, d1, "
                  "d2 (curves); the point is always written (instead of --derivatives/--normals)");
  addShardOptions(sub, args->shard, args->shardCount, "sample the K-th (1-based) of N equal ranges of spans/patches");
  sub->add_option("--threads", args->threads, "CPU sampler threads (0 = one per CPU this process may use, less one beside a .f32/.f64/.npy writer; output is identical)");
  sub->add_option("--chunk-points", args->chunkPoints,
                  "points per streamed chunk: whole spans/patches while they fit, else rows of one (default 32768 "
                  "on the CPU, 4 MiB planes on the GPU; output is identical)");
  addPartMeshOptions(sub, args->mesh, "1e-3");
  sub->add_flag("--trim", args->trim,
                "keep only the samples inside the model's trim loops (a face from `import`), written as a point cloud "
                "(.npy, .f32, .f64, .csv, .ply with --grid) with each sample's (U, V), or as a mesh (.ply, .obj, .stl, "
                ".glb, .gltf without --grid)");
  sub->add_flag("--require-device", args->requireDevice,
                "with --device auto or vulkan: fail (exit 3) instead of falling back to the CPU");
  addQuietFlag(sub, args->quiet, "no notices and no progress bar");
  sub->add_flag("--fail-fast", args->failFast,
                "several models: stop at the first that fails (else each failure is reported, the rest written, exit 1)");
  sub->add_option("--save-model", args->saveModel,
                  "also write the model as PATH.json with its net (and per-vertex alpha, weights) as .npy arrays "
                  "beside it (PATH.points.npy, ...), committed with the samples");
  sub->add_flag("--allow-outside-arrays", args->allowOutsideArrays,
                "read .npy arrays the model references from outside its folder (absolute paths, .., links)");
  sub->footer(kExitCodeHelp);
  sub->callback([args, sub] {
    args->meshLayoutGiven = sub->count("--mesh-layout") > 0;
    runSample(*args);
  });
}

}  // namespace shapespline::cli
