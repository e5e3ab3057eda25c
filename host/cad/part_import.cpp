#include <shapespline/cad/occt_part.h>
#include <shapespline/cad/part_import.h>
#include <shapespline/core/parallel_for.h>
#include <shapespline/io/job_metadata.h>
#include <shapespline/io/model_json.h>
#include <shapespline/version.h>

#include <BRep_Tool.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <exception>
#include <optional>

namespace shapespline::cad {
namespace {

using nlohmann::json;

std::string numbered(const char* stem, int id) {
  char name[32];
  std::snprintf(name, sizeof name, "%s_%04d.json", stem, id);
  return name;
}

// The ids (1-based, in TopExp::MapShapes order) of the sub-shapes of `shape` of type `type`.
json idsIn(const TopoDS_Shape& shape, TopAbs_ShapeEnum type, const TopTools_IndexedMapOfShape& all) {
  TopTools_IndexedMapOfShape inside;
  TopExp::MapShapes(shape, type, inside);
  json ids = json::array();
  for (int i = 1; i <= inside.Extent(); ++i) ids.push_back(all.FindIndex(inside(i)));
  return ids;
}

// A face's coedges as part.json writes them: per loop, [{"edge": id, "start": K, "t": [...]}, ...].
json coedgesJson(const std::vector<std::vector<TrimCoedge>>& loops, const TopTools_IndexedMapOfShape& edges) {
  json out = json::array();
  for (const std::vector<TrimCoedge>& loop : loops) {
    json list = json::array();
    for (const TrimCoedge& coedge : loop) {
      const int id = edges.FindIndex(coedge.edge);
      if (id == 0) throw ConversionError("an edge of the face's wires is not an edge of the part");
      list.push_back({{"edge", id}, {"start", coedge.start}, {"t", coedge.t}});
    }
    out.push_back(std::move(list));
  }
  return out;
}

// A face converted, with its model file's text, or what stopped it.
struct FaceResult {
  std::optional<ConvertedFace> face;
  std::string text;
  std::exception_ptr error;
};

// Every face converted on every core the process may use. Each conversion reads its own face and
// the geometry it shares with others (OCCT's geometry is read-only here, as BRepMesh reads it in
// parallel: its handles count references atomically) and builds its own B-spline, map and loops.
std::vector<FaceResult> convertFaces(const TopTools_IndexedMapOfShape& faces, double trimTolerance) {
  std::vector<FaceResult> results(static_cast<size_t>(faces.Extent()));
  // Each face's failure is kept for its turn in the manifest (a face that does not convert is
  // listed, not fatal), so no exception leaves the loop.
  parallelFor(results.size(), 0, [&](size_t i) {
    try {
      results[i].face.emplace(convertFace(TopoDS::Face(faces(static_cast<int>(i) + 1)), trimTolerance));
      results[i].text = io::toJson(results[i].face->model).dump(1) + "\n";
    } catch (...) {
      results[i].error = std::current_exception();
    }
  });
  return results;
}

}  // namespace

ConvertedPart convertPart(const std::filesystem::path& part, const ImportOptions& options) {
  if (!std::isfinite(options.trimTolerance) || options.trimTolerance <= 0.0 || options.trimTolerance > 0.01)
    throw std::invalid_argument("--trim-tolerance: must lie in (0, 0.01] (got " + std::to_string(options.trimTolerance) + ")");
  const PartShape shape = readPart(part, options.maxFileBytes);
  TopTools_IndexedMapOfShape faces, edges, shells;
  TopExp::MapShapes(shape.shape, TopAbs_FACE, faces);
  TopExp::MapShapes(shape.shape, TopAbs_EDGE, edges);
  TopExp::MapShapes(shape.shape, TopAbs_SHELL, shells);

  ConvertedPart result;
  ImportSummary& summary = result.summary;
  std::vector<std::pair<std::string, std::string>>& files = result.files;
  summary.format = shape.format;
  summary.units = shape.units;
  json faceList = json::array(), edgeList = json::array(), shellList = json::array();
  // A face or edge that did not convert: listed with the reason, in part.json and the summary.
  auto skip = [&](json& entry, const std::string& what, int id, const ConversionError& e, int& count) {
    entry["model"] = nullptr;
    entry["skipped"] = e.what();
    summary.skipped.push_back(what + " " + std::to_string(id) + ": " + e.what());
    ++count;
  };
  std::vector<FaceResult> convertedFaces = convertFaces(faces, options.trimTolerance);
  for (int i = 1; i <= faces.Extent(); ++i) {
    const TopoDS_Face& face = TopoDS::Face(faces(i));
    json entry = {{"id", i}, {"edges", idsIn(face, TopAbs_EDGE, edges)}};
    FaceResult& result = convertedFaces[static_cast<size_t>(i) - 1];
    try {
      if (result.error) std::rethrow_exception(result.error);
      const ConvertedFace& converted = *result.face;
      json coedges = coedgesJson(converted.coedges, edges);
      const std::string name = numbered("face", i);
      files.push_back({name, std::move(result.text)});
      entry["model"] = name;
      entry["surface"] = converted.surfaceType;
      entry["reversed"] = converted.reversed;
      entry["bounds"] = {converted.bounds[0], converted.bounds[1], converted.bounds[2], converted.bounds[3]};
      entry["loops"] = converted.model.trim.loops.size();
      entry["coedges"] = std::move(coedges);
      if (converted.clampedTrimPoints > 0) entry["clamped_trim_points"] = converted.clampedTrimPoints;
      if (!converted.mapFailure.empty())
        entry["projected"] = {{"why", converted.mapFailure}, {"gap", converted.projectionGap}};
      ++summary.faces;
    } catch (const ConversionError& e) {
      skip(entry, "face", i, e, summary.facesSkipped);
    }
    faceList.push_back(std::move(entry));
  }
  for (int i = 1; i <= edges.Extent(); ++i) {
    const TopoDS_Edge& edge = TopoDS::Edge(edges(i));
    json entry = {{"id", i}};
    if (BRep_Tool::Degenerated(edge)) {  // a sphere's pole, a cone's apex: a point, not a curve
      entry["model"] = nullptr;
      entry["degenerate"] = true;
    } else {
      try {
        const ConvertedEdge converted = convertEdge(edge);
        const std::string name = numbered("edge", i);
        files.push_back({name, io::toJson(converted.model).dump(1) + "\n"});
        entry["model"] = name;
        entry["curve"] = converted.curveType;
        ++summary.edges;
      } catch (const ConversionError& e) {
        skip(entry, "edge", i, e, summary.edgesSkipped);
      }
    }
    edgeList.push_back(std::move(entry));
  }
  for (int i = 1; i <= shells.Extent(); ++i)
    shellList.push_back({{"id", i}, {"faces", idsIn(shells(i), TopAbs_FACE, faces)}});
  summary.shells = shells.Extent();
  if (summary.faces == 0 && summary.edges == 0)
    throw CadError(part.string(), "(part)",
                   "no face or edge could be converted (" + (summary.skipped.empty() ? "none found" : summary.skipped[0]) + ")");

  const json manifest = {
      {"format", "shapespline-part"},
      {"version", 1},
      {"tool", {{"name", "shapespline"}, {"version", SHAPESPLINE_VERSION_STRING}}},
      {"source",
       {{"file", part.filename().string()},
        {"format", shape.format},
        {"bytes", std::filesystem::file_size(part)},
        {"sha256", io::sha256OfFile(part)}}},
      {"units", shape.units},
      {"trim_tolerance", options.trimTolerance},
      {"faces", std::move(faceList)},
      {"edges", std::move(edgeList)},
      {"shells", std::move(shellList)}};

  files.emplace_back("part.json", manifest.dump(1) + "\n");
  return result;
}

ImportSummary importPart(const std::filesystem::path& part, const std::filesystem::path& outDir,
                         const ImportOptions& options) {
  const ConvertedPart converted = convertPart(part, options);
  writePart(converted, part, outDir);
  return converted.summary;
}

}  // namespace shapespline::cad
