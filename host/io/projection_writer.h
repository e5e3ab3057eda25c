#pragma once
// The output of `shapespline project` (docs/cli.md "project"): for every query point, in the
// cloud's order, the query point, its closest point, the face (a part), the parameters ((u, v) of
// a surface, t of a curve), the distance, the signed distance and the unit normal (surfaces).
// Formats: .npy (a structured array of fp64 fields by name), .f64 (the same records without a
// header: the .npy's data), .csv (a header line, 17 significant digits) and binary PLY (the query
// points as the vertices, the rest as vertex properties, so that a viewer colours the cloud by
// `distance`). The count is written in the header first, so it must be known.
#include <shapespline/io/atomic_file.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace shapespline::io {

enum class ProjectionTarget { Surface, Part, Curve };

struct ProjectionRecord {
  glm::dvec3 query{0.0}, point{0.0}, normal{0.0};
  int face = 0;
  double u = 0.0, v = 0.0;  // a curve: t in u
  double distance = 0.0, signedDistance = 0.0;
};

class ProjectionWriter {
 public:
  virtual ~ProjectionWriter() = default;
  virtual void write(std::span<const ProjectionRecord> records) = 0;
};

enum class ProjectionFormat { Npy, F64, Csv, Ply };

// The format of `path`'s extension (.npy, .f64, .csv, .ply); OutputPathError naming `option` otherwise.
ProjectionFormat projectionFormat(const std::filesystem::path& path, const std::string& option);

// What a file of `count` records starts with ("" for .f64; a CSV's header line whatever the count):
// every file is this header and then its records, so shards merge by joining their records under
// the whole job's header (jobs/projection_merge.h).
std::string projectionHeader(ProjectionFormat format, ProjectionTarget target, std::uint64_t count);

// The bytes of one record (0 for CSV, whose rows vary).
std::uint64_t projectionRecordBytes(ProjectionFormat format, ProjectionTarget target);

// The writer for `path`'s extension (.npy, .f64, .csv, .ply; OutputPathError naming `option`
// otherwise), its header written now.
std::unique_ptr<ProjectionWriter> makeProjectionWriter(AtomicFile& out, const std::filesystem::path& path,
                                                       const std::string& option, ProjectionTarget target,
                                                       std::uint64_t count);

// The fields of a record, by name and width (the .npy, CSV and PLY names).
std::vector<std::pair<std::string, int>> projectionFields(ProjectionTarget target);

}  // namespace shapespline::io
