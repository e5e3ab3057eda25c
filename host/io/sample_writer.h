#pragma once
// Streaming writers of sampled grids (core/sample_grid.h): each consumes GridChunks in item order
// and never holds more than one chunk plus a fixed-size buffer, so 10^9 points stream through
// in bounded memory. Formats: OBJ and PLY (binary little endian) meshes, welded (io/welded_mesh.h;
// surfaces: two triangles per grid cell with normals and uv; curves: one polyline) or per item,
// CSV, raw f32/f64 with a JSON sidecar, NumPy .npy (the raw records as a structured array, with the
// raw sidecar beside it),
// SVG (curves only, 2-D projection; buffers its points, so the caller caps the count), and glTF 2.0
// (.glb, or .gltf + OUT.bin: a welded mesh held in memory by tinygltf, so the caller caps the
// vertex count at kMaxGltfVertices and never shards it; io/gltf_writer.cpp).
#include <shapespline/core/curve.h>
#include <shapespline/core/sample_grid.h>
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/job_metadata.h>

#include <glm/vec3.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace shapespline::io {

class WeldGrid;

// Stl: binary STL, written for part meshes only (io/triangle_mesh.h); the grid writers refuse it.
enum class OutputFormat { Obj, Ply, Csv, RawF32, RawF64, Npy, Svg, Glb, Gltf, Stl };

// glTF output holds its welded mesh in memory (fp32 positions re-centred on the bounding box): at
// most this many vertices (distinct grid points, io/welded_mesh.h WeldGrid::pointCount).
inline constexpr uint64_t kMaxGltfVertices = uint64_t{1} << 24;
inline bool isGltf(OutputFormat f) { return f == OutputFormat::Glb || f == OutputFormat::Gltf; }
// The buffer file a .gltf refers to: the same path with the extension .bin (OUT.gltf -> OUT.bin).
std::filesystem::path gltfBufferPath(const std::filesystem::path& gltf);

// Format from the file extension (case-insensitive); throws OutputPathError(option, ...) otherwise.
OutputFormat outputFormatFromPath(const std::filesystem::path& path, const std::string& option = "-o");
std::string_view outputFormatName(OutputFormat format);
// Throws OutputPathError(option, path, ...) for a format only part meshes are written in (.stl),
// for the commands that sample grids, merge or shard.
void requireGridFormat(OutputFormat format, const std::filesystem::path& path, const std::string& option = "-o");

// "point", "d1", "du", ..., "normal" (the golden / eval field names).
std::string_view fieldName(Field field);

// Everything a writer needs to know about the job before the first chunk arrives.
struct SampleLayout {
  bool surface = false;
  int dimension = 3;                  // coordinates per vector in text formats (2-D curves: 2)
  int samplesU = 2, samplesV = 1;     // per item (span / patch)
  size_t firstItem = 0;               // this job's items: [firstItem, firstItem + itemCount)
  size_t itemCount = 0;
  size_t totalItems = 0;              // items of the whole model
  size_t itemsV = 1;                  // items along v: item k is patch row k / itemsV, column k % itemsV
  // Model span/patch index of each item row (u) and column (v); curves: spanV = {0}.
  std::vector<int> spanU, spanV;
  // Global parameter interval [start, end] of each item row (u) and column (v); curves: paramV = {{0,0}}.
  std::vector<std::pair<double, double>> paramU, paramV;
  // A curve streamed from its file (millions of spans): its item rows are spans spanRows->first on,
  // their intervals from `spanKnots` (core uniformSpanParameter), computed when asked rather than
  // listed in spanU and paramU (left empty). Read the rows through rowSpan and rowParameter.
  std::optional<SpanRange> spanRows;
  std::vector<double> spanKnots;
  FieldMask fields = 0;               // fields present in every chunk
  Precision precision = Precision::Double;  // of the chunk data; PLY stores this precision
  int shardIndex = 1, shardCount = 1; // 1-based K of N (1/1 when not sharded)
  std::string source;                 // model file, for headers and the sidecar
  std::string job;                    // io/shard_info.h jobFingerprint: the same for every shard of a job
  // Where the values were computed (sampling/report.h): "cpu" or the Vulkan device's name, and the
  // precision of the arithmetic (the CPU path computes fp64 whatever `precision` is).
  std::string device = "cpu";
  Precision computedPrecision = Precision::Double;
  // Tool, model file and SHA-256, parameters, device, precisions, grid (io/job_metadata.h); the same
  // for every shard of the job. Written into every format that can carry it.
  JobMetadata metadata;
  // Mesh formats (OBJ, PLY, glTF): welded (io/welded_mesh.h: every grid point once, shared by
  // index) or per item as the chunks come (each patch/span on its own, shared edges repeated).
  // Closed directions (surfaces; curves use `closed`) share their seam. `reversed`: the winding
  // and the normals are flipped so that a closed surface's normals point outwards.
  bool welded = true;
  bool closedU = false, closedV = false;
  bool reversed = false;
  // SVG only: the control polygon (closed = drawn as a loop) and marked data points.
  std::vector<glm::dvec3> controlPoints;
  bool closed = false;
  std::vector<glm::dvec3> dataPoints;

  // The model span of item row `row`, and its parameter interval (the lists or spanRows).
  int rowSpan(size_t row) const;
  std::pair<double, double> rowParameter(size_t row) const;
  size_t rowCount() const { return spanRows ? static_cast<size_t>(spanRows->last - spanRows->first + 1) : spanU.size(); }

  size_t pointsPerItem() const { return static_cast<size_t>(samplesU) * static_cast<size_t>(samplesV); }
  size_t pointCount() const { return itemCount * pointsPerItem(); }
  bool sharded() const { return shardCount > 1; }
  // Model span/patch indices and global parameter of sample (a, b) of item k (inside the item's
  // interval). Throws DerivedValueError if it is not finite.
  std::pair<int, int> itemIndex(size_t item) const;
  std::pair<double, double> parameter(size_t item, int a, int b) const;
  // Parameters normalised to [0,1] over the whole model (OBJ/PLY texture coordinates); throws
  // DerivedValueError if they are not finite.
  std::pair<double, double> texCoord(size_t item, int a, int b) const;
  // The job's global point grid (io/welded_mesh.h): totalItems as patch rows x itemsV (curves: x 1).
  WeldGrid weldGrid() const;
  // Throws DerivedValueError unless every interval end, interval width and the model's whole range
  // are finite, which makes every parameter() and texCoord() finite (checked before any byte).
  void checkDerivedValues() const;
};

// The grid items of a surface job: its patch indices and parameter intervals per row and column
// (the non-empty knot intervals of a knot-vector surface), into `layout`.
void setSurfaceItems(const SurfaceShape& shape, SampleLayout& layout);

// A value a writer derives itself (global parameter, texture coordinate, SVG coordinate) is not
// finite. The writers of makeSampleWriter rethrow it as OutputWriteError (exit 3, nothing written);
// model validation (knot differences must be finite) keeps valid models from reaching it.
class DerivedValueError : public std::range_error {
 public:
  using std::range_error::range_error;
};

class SampleWriter {
 public:
  virtual ~SampleWriter() = default;
  virtual void begin(const SampleLayout& layout) = 0;
  virtual void consume(const GridChunk& chunk) = 0;
  // Points [first, first + count) of `chunk`, from the sampler's workers (core/grid_sampler.h
  // SliceConsumer), concurrently and in any order, before consume(chunk). A writer whose records
  // sit at offsets known from the point index (raw, .npy) writes them here, on every core, and
  // consume() then has nothing left to write; the others ignore it. A caller may skip it: then
  // consume() writes everything.
  // Returns true when the writer also checked every value of the slice while it had it in hand,
  // and each lies in the finite range of the file's precision (|v| <= FLT_MAX for an fp32 file or
  // fp32 planes, else finite): the caller need not read the slice again to check it. False: not
  // checked, or a value is out of range (the caller finds and reports it; the file is discarded).
  virtual bool writeSlice(const GridChunk& chunk, size_t first, size_t count) {
    (void)chunk;
    (void)first;
    (void)count;
    return false;
  }
  // Where a CPU sampler may write this file's records itself, encoding and checking them as it
  // computes them (core/sample_grid.h RecordSink, after begin()): the raw and .npy writers, whose
  // records sit at offsets known from the point index. With it the sampler hands neither slices
  // nor planes for the points it encoded. None for the other formats.
  virtual std::optional<RecordSink> recordSink() { return std::nullopt; }
  // The job fingerprint and metadata for a writer that first writes them in finish()
  // (identityWrittenAtFinish): a caller that learns them only once the samples are written (a net
  // streamed in bands, cli sample) gives them here before finish(). The other formats write them
  // in begin() and refuse this.
  virtual void setIdentity(const std::string& job, const JobMetadata& metadata) {
    (void)job;
    (void)metadata;
    throw std::logic_error("SampleWriter::setIdentity: this format writes the job's identity in begin()");
  }
  // Writes trailing data (PLY faces, SVG body, sidecar); the caller then commits the files.
  virtual void finish() = 0;
};

// `out` must outlive the writer. `sidecar` (raw formats and .npy; glTF: the .bin) receives the JSON
// layout description; for .gltf it is the buffer file (gltfBufferPath).
// The writer checks the layout's derived values in begin() and turns a DerivedValueError of any
// call into OutputWriteError(out.option(), out.target(), ...).
std::unique_ptr<SampleWriter> makeSampleWriter(OutputFormat format, AtomicFile& out, AtomicFile* sidecar = nullptr);

// The formats whose OUT.json sidecar describes their records (raw .f32/.f64 and .npy).
inline bool hasLayoutSidecar(OutputFormat f) {
  return f == OutputFormat::RawF32 || f == OutputFormat::RawF64 || f == OutputFormat::Npy;
}

// The formats that write the layout's job fingerprint and metadata only in finish() (the raw and
// .npy sidecar; CSV carries neither), so that SampleWriter::setIdentity may give them late.
inline bool identityWrittenAtFinish(OutputFormat f) { return hasLayoutSidecar(f) || f == OutputFormat::Csv; }

// The formats that write meshes (OBJ, PLY, glTF), welded when layout.welded (io/welded_mesh.h).
inline bool isMesh(OutputFormat f) { return f == OutputFormat::Obj || f == OutputFormat::Ply || isGltf(f); }
// The item ranges [a, b) a writer of `format` must be given, in this order: a welded shard's
// context before its items, its items, its context after (the outside items that share its
// points); otherwise its items alone.
std::vector<std::pair<size_t, size_t>> streamedItemRanges(OutputFormat format, const SampleLayout& layout);

// Fields every writer of `format` needs for the given kind (e.g. OBJ/PLY surfaces need normals).
FieldMask requiredFields(OutputFormat format, bool surface);

std::unique_ptr<SampleWriter> makeObjWriter(AtomicFile& out);
std::unique_ptr<SampleWriter> makePlyWriter(AtomicFile& out);
std::unique_ptr<SampleWriter> makeCsvWriter(AtomicFile& out);
std::unique_ptr<SampleWriter> makeRawWriter(AtomicFile& out, AtomicFile& sidecar, Precision filePrecision);
std::unique_ptr<SampleWriter> makeSvgWriter(AtomicFile& out);
// `sidecar` (OUT.npy.json: the job, its items and its metadata) may be null for a library caller
// that wants the .npy alone.
std::unique_ptr<SampleWriter> makeNpyWriter(AtomicFile& out, AtomicFile* sidecar);
// `bin` null: .glb; else .gltf whose buffer goes to `bin` (committed in the same io::OutputSet).
std::unique_ptr<SampleWriter> makeGltfWriter(AtomicFile& out, AtomicFile* bin);

}  // namespace shapespline::io
