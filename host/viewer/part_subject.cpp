#include <shapespline/viewer/part_subject.h>

#include <shapespline/core/tess_topology.h>
#include <shapespline/core/value_text.h>
#include <shapespline/part/face_evaluator.h>
#include <shapespline/part/face_triangulation.h>
#include <shapespline/viewer/errors.h>

#include <imgui.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace shapespline::viewer {
namespace {

using Kind = ScriptCommand::Kind;
using Range = render::StaticMesh::Range;

// The deflection a view asks for stays within these fractions of the diagonal: finer is past what
// fp32 coordinates show, coarser no longer shows the part's shape.
constexpr double kFinest = 1e-6, kCoarsest = 0.02;
// The mesh follows the view when the deflection it asks for is this factor away from the mesh's
// (zooming), or a tenth away when the tolerance itself moved.
constexpr double kZoomFactor = 2.0, kSliderFactor = 1.1;

}  // namespace

PartSubject::PartSubject(std::shared_ptr<vk::Context> ctx, part::Part part)
    : ctx_(std::move(ctx)), part_(std::move(part)), lo_(INFINITY), hi_(-INFINITY) {
  diagonal_ = part::partDiagonal(part_);  // what `sample` takes a relative deflection of
  if (part_.faces.empty() || !(diagonal_ > 0.0) || !std::isfinite(diagonal_))
    throw std::invalid_argument("the part has no converted face with an extent to draw");
  asked_ = 1e-3 * diagonal_;
  if (!remesh(asked_).empty())
    throw std::invalid_argument("the part's mesh at 1e-3 of its diagonal needs more than " +
                                std::to_string(kViewTriangleBudget) + " triangles");
  // The camera frames the mesh: the faces' control nets may reach far beyond what is trimmed.
  for (const glm::dvec3& p : mesh_.mesh.positions) {
    lo_ = glm::min(lo_, p);
    hi_ = glm::max(hi_, p);
  }
}

std::string PartSubject::remesh(double deflection) {
  part::MeshOptions options;
  options.deflection = deflection;
  options.maxTriangles = kViewTriangleBudget;
  options.cornerNormals = true;
  part::CpuFaceEvaluator cpu;
  part::PartMesh mesh;
  try {
    mesh = part::meshPart(part_, options, cpu);
  } catch (const part::TriangleBudgetExceeded&) {
    return "deflection " + shortestText(deflection) + " needs more than " + std::to_string(kViewTriangleBudget) +
           " triangles; the mesh at " + shortestText(deflection_) + " stays";
  }
  part::ShadedMesh shaded = part::shadedMesh(mesh);
  // The part's edges first, then every triangle's (the wireframe): one buffer, two ranges.
  std::vector<uint32_t> lines = shaded.edgeLines;
  const std::vector<uint32_t> wire = triangleEdges(shaded.triangles);
  lines.insert(lines.end(), wire.begin(), wire.end());
  ctx_->waitIdle();  // the frames in flight read the mesh before it
  drawing_ = std::make_unique<render::StaticMesh>(*ctx_, shaded.positions, shaded.normals, shaded.triangles, lines);
  edgeLines_ = static_cast<uint32_t>(shaded.edgeLines.size() / 2);
  faceTriangles_.clear();
  for (uint32_t t = 0; t < shaded.faceIds.size(); ++t) {  // a face's triangles are consecutive
    Range& r = faceTriangles_.try_emplace(shaded.faceIds[t], Range{t, 0}).first->second;
    ++r.count;
  }
  mesh_ = std::move(mesh);
  shaded_ = std::move(shaded);
  deflection_ = deflection;
  return "";
}

std::string PartSubject::apply(float tolerancePx, const View& view) {
  const glm::dvec3 centre = 0.5 * (lo_ + hi_);
  const double depth = std::max(glm::length(centre - glm::dvec3(view.camera.eye)), kFinest * diagonal_);
  const double wanted = std::clamp(tolerancePx * view.pixelSize(depth), kFinest * diagonal_, kCoarsest * diagonal_);
  const double factor = tolerancePx != tolerancePx_ ? kSliderFactor : kZoomFactor;
  tolerancePx_ = tolerancePx;
  if (wanted < factor * asked_ && wanted > asked_ / factor) return "";
  asked_ = wanted;
  return remesh(wanted);
}

std::vector<render::MeshDraw> PartSubject::meshes(bool wireframe) const {
  const uint32_t all = drawing_->lineCount();
  const Range lines = edges_ && wireframe ? Range{0, all}
                      : edges_            ? Range{0, edgeLines_}
                      : wireframe         ? Range{edgeLines_, all - edgeLines_}
                                          : Range{};
  const auto draw = [&](Range triangles, Range withLines, glm::vec3 colour) {
    render::MeshDraw d = drawing_->draw(triangles, withLines);
    d.color = colour;
    d.wireColor = render::kPartEdgeColour;
    return d;
  };
  const auto picked = faceTriangles_.find(picked_);
  if (picked == faceTriangles_.end()) return {draw({0, drawing_->triangleCount()}, lines, render::kPartColour)};
  // The picked face's triangles are one run: the runs before and after it, and it in its colour.
  const Range face = picked->second;
  const uint32_t after = face.first + face.count;
  return {draw({0, face.first}, lines, render::kPartColour),
          draw({after, drawing_->triangleCount() - after}, {}, render::kPartColour),
          draw(face, {}, render::kPickedFaceColour)};
}

int PartSubject::faceAt(double x, double y, const View& view) const {
  const int w = int(view.extent.width), h = int(view.extent.height);
  std::vector<glm::dvec3> px(shaded_.positions.size());
  for (size_t v = 0; v < px.size(); ++v) px[v] = view.camera.toPixel(glm::dvec3(shaded_.positions[v]), w, h);
  double nearest = INFINITY;
  int face = -1;
  for (size_t t = 0; t < shaded_.faceIds.size(); ++t) {
    const glm::dvec3& a = px[shaded_.triangles[3 * t]];
    const glm::dvec3& b = px[shaded_.triangles[3 * t + 1]];
    const glm::dvec3& c = px[shaded_.triangles[3 * t + 2]];
    const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (area == 0.0) continue;
    // Barycentric weights of (x, y); all of one sign inside, whichever way the triangle faces.
    const double wa = ((b.x - x) * (c.y - y) - (b.y - y) * (c.x - x)) / area;
    const double wb = ((c.x - x) * (a.y - y) - (c.y - y) * (a.x - x)) / area;
    const double wc = 1.0 - wa - wb;
    if (wa < 0.0 || wb < 0.0 || wc < 0.0) continue;
    const double depth = wa * a.z + wb * b.z + wc * c.z;
    if (depth < 0.0 || depth > 1.0 || depth >= nearest) continue;
    nearest = depth;
    face = shaded_.faceIds[t];
  }
  return face;
}

std::string PartSubject::describe(int faceId) const {
  for (const part::PartFace& face : part_.faces)
    if (face.id == faceId)
      return "face " + std::to_string(faceId) + (face.surfaceClass.empty() ? "" : " (" + face.surfaceClass + ")");
  return "face " + std::to_string(faceId);
}

std::string PartSubject::pick(double x, double y, const View& view) {
  picked_ = faceAt(x, y, view);
  return picked_ < 0 ? "" : describe(picked_);
}

std::string PartSubject::execute(const ScriptCommand& c, const View& view) {
  auto fail = [&](const std::string& rule) { throw ScriptError(c.line, c.text, rule); };
  switch (c.kind) {
    case Kind::Edges: edges_ = c.on; return "";
    case Kind::PickFace: {
      const int id = int(c.numbers[0]);
      const auto run = faceTriangles_.find(id);
      if (run == faceTriangles_.end()) fail("the part has no face " + std::to_string(id) + " in its mesh");
      // A click at the centroid of the face's largest triangle on screen that shows the face.
      const int w = int(view.extent.width), h = int(view.extent.height);
      std::vector<std::pair<double, glm::dvec2>> candidates;
      for (uint32_t t = run->second.first; t < run->second.first + run->second.count; ++t) {
        glm::dvec3 p[3];
        for (int j = 0; j < 3; ++j) p[j] = view.camera.toPixel(glm::dvec3(shaded_.positions[shaded_.triangles[3 * t + j]]), w, h);
        const double area = std::abs((p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x));
        candidates.push_back({area, glm::dvec2(p[0] + p[1] + p[2]) / 3.0});
      }
      std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
      for (const auto& [area, at] : candidates)
        if (area > 0.0 && faceAt(at.x, at.y, view) == id) return "picked " + pick(at.x, at.y, view);
      fail("face " + std::to_string(id) + " is not visible from this view");
      return "";
    }
    default: fail("a part has no such control (lambda, mu, alpha, pick-point and net are a surface model's)");
  }
  return "";
}

void PartSubject::panelTitle(const PanelNote& note) {
  ImGui::Text("part: %zu faces, %d edges, %lld open", part_.faces.size(), mesh_.edges,
              static_cast<long long>(mesh_.boundaryEdges));
  note();
}

void PartSubject::panelControls(const PanelNote& note) {
  if (picked_ >= 0) {
    ImGui::Text("%s", describe(picked_).c_str());
    note();
    for (const part::PartFace& face : part_.faces)
      if (face.id == picked_) {
        ImGui::Text("file %s", face.model.filename().string().c_str());
        note();
      }
  } else {
    ImGui::TextDisabled("click a face to see its id and surface class");
    note();
  }
}

void PartSubject::panelToggles(const PanelNote& note) {
  ImGui::Checkbox("edges", &edges_);
  note();
}

std::string PartSubject::meshName() const {
  char text[48];
  std::snprintf(text, sizeof text, "deflection %.3g", deflection_);
  return text;
}

}  // namespace shapespline::viewer
