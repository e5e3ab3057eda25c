#pragma once
// The `sample` command's arguments and entry point, also used by `demo`; the pieces of a job that
// sampling a whole part (cli/part_sample.cpp) shares.
#include <shapespline/core/sample_grid.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/cli/part_mesh_options.h>
#include <shapespline/sampling/report.h>

#include <functional>
#include <string>
#include <vector>

namespace shapespline {
class Surface;
}
namespace shapespline::io {
class OutputSet;
}
namespace shapespline::sampling {
class Session;
}

namespace shapespline::cli {

struct SampleArgs {
  std::vector<std::string> models;  // MODEL... as given (files, or folders of *.json)
  std::string model;                // the one model of a job
  std::string modelName;  // the model's path as the outputs record it ("" = model); see demo
  std::string out, grid, device = "auto", precision = "double", shard;
  std::string samples;  // --samples as given ("" = not given: the default)
  std::string shardCount;  // --shard-count as given ("" = not given; --shard auto only)
  std::string meshLayout = "welded";
  std::string fields;  // --fields as given ("" = from --derivatives / --normals)  // --mesh-layout: welded or per-item (OBJ, PLY)
  int threads = 0;
  long long chunkPoints = 0;  // 0 = default (CPU sampler and GPU evaluator defaults)
  bool derivatives = false, normals = false, quiet = false, requireDevice = false;
  bool allowOutsideArrays = false;  // the model's .npy arrays may lie outside its folder
  std::string saveModel;            // --save-model PATH.json ("" = not given; {stem} with several models)
  bool failFast = false;            // several models: stop at the first that fails
  bool trim = false;                // --trim: only the samples inside the model's trim loops
  bool meshLayoutGiven = false;  // --mesh-layout given (it applies to mesh outputs only)
  // A trimmed mesh (a part or a face with --trim to .ply, .obj, .stl, .glb, .gltf): as given.
  PartMeshArgs mesh;
};

// Samples one job and commits its files (data, sidecar, shard record) as one output set; with
// several models (or a folder, or {stem} in -o), one job per model on one session: each model's
// set is committed on its own, a model that fails is reported and the rest still run, and the
// command then fails with BatchFailure (exit 1), or at the first failure with --fail-fast.
void runSample(const SampleArgs& args);

// The same job with its files added to `outputs`, which the caller commits (demo commits every job
// of its folder as one set). Returns false when nothing was sampled because a shard's record
// verified (resume: the caller discards the set); `summary` receives the "wrote ..." line.
// `session`: the one to sample with (a batch keeps one: one device, pipelines compiled once), or
// nullptr for a new one.
bool sampleInto(const SampleArgs& args, io::OutputSet& outputs, std::string& summary,
                sampling::Session* session = nullptr);

// What `sample` parsed for a job, handed to the part sampler.
struct PartJob {
  io::OutputFormat format;
  sampling::DeviceRequest request;
  int samplesU, samplesV;
  FieldMask fields;
  Precision precision;
  SliceConsumer check;  // the finiteness check of every slice (sample's requireFinite)
  Precision storedPrecision = Precision::Double;  // what the file stores (the job metadata's)
  int shardK = 1, shardN = 1;                     // --shard K/N (1/1 unsharded)
};

// A sharded trimmed job (a face with --trim, a part) writes a format that carries its shard's
// identity: InputError naming --shard otherwise (CSV).
void requireTrimmedShardFormat(const SampleArgs& args, io::OutputFormat format);

// Samples every converted face of the part, each trimmed, into one point cloud with a `face` column
// (cli/part_sample.cpp); as sampleInto.
bool samplePartInto(const SampleArgs& args, const PartJob& job, io::OutputSet& outputs, std::string& summary,
                    sampling::Session* session);

// Whether this job is a trimmed mesh (a part, or a face with --trim, to a mesh format without a
// grid: cli/part_mesh.cpp); InputError for a grid asked of a mesh format other than PLY.
bool meshesTrimmed(const SampleArgs& args, io::OutputFormat format, bool part);

// The part's (or the trimmed face's) watertight mesh into one file; as sampleInto.
bool meshPartInto(const SampleArgs& args, io::OutputFormat format, const sampling::DeviceRequest& request,
                  io::OutputSet& outputs, std::string& summary, sampling::Session& session);

}  // namespace shapespline::cli
