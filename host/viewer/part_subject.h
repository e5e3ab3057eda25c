#pragma once
// PartSubject: a part (or one trimmed face) in the viewer. Meshed on the host by host/part to a
// deflection of the pixel tolerance at the part's depth (re-meshed when the slider moves, or when
// zooming halves or doubles a pixel), drawn with each face's own normals and the part's edges; a
// click picks the face under the cursor, shown in another colour with its id and surface class.
#include <shapespline/part/part_mesher.h>
#include <shapespline/part/part_model.h>
#include <shapespline/part/shaded_mesh.h>
#include <shapespline/render/static_mesh.h>
#include <shapespline/viewer/subject.h>
#include <shapespline/vk/context.h>

#include <map>
#include <memory>

namespace shapespline::viewer {

// The most triangles a view's mesh may have: a finer one is refused (the panel says so) and the
// mesh before it stays.
inline constexpr int64_t kViewTriangleBudget = 8'000'000;

class PartSubject final : public Subject {
 public:
  // Meshes the part at 1e-3 of its diagonal first: a part the mesher refuses (crossing trim loops,
  // a face without coedges) is a ModelError here, before the first frame.
  PartSubject(std::shared_ptr<vk::Context> ctx, part::Part part);

  std::pair<glm::dvec3, glm::dvec3> bounds() const override { return {lo_, hi_}; }
  std::string apply(float tolerancePx, const View& view) override;
  void record(VkCommandBuffer, const View&) override {}
  std::vector<render::MeshDraw> meshes(bool wireframe) const override;
  render::OverlayDraw overlay() const override { return {}; }
  std::string pick(double x, double y, const View& view) override;
  std::string pickMiss() const override { return "no face of the part is drawn at the pixel"; }
  std::string execute(const ScriptCommand& c, const View& view) override;
  void panelTitle(const PanelNote& note) override;
  void panelControls(const PanelNote& note) override;
  void panelToggles(const PanelNote& note) override;
  std::string meshName() const override;
  uint64_t triangleCount() const override { return shaded_.faceIds.size(); }
  bool wireframeAvailable(const render::ScenePipelines&) const override { return true; }

 private:
  // Meshes at `deflection` and uploads the mesh (after the frames in flight); returns "" or why the
  // mesh was refused (over the budget: the mesh before it stays).
  std::string remesh(double deflection);
  // The face id drawn at pixel (x, y), -1 where none is.
  int faceAt(double x, double y, const View& view) const;
  std::string describe(int faceId) const;

  std::shared_ptr<vk::Context> ctx_;
  part::Part part_;
  glm::dvec3 lo_, hi_;
  double diagonal_ = 0.0;
  part::PartMesh mesh_;  // the welded mesh (counts) of the shaded one drawn
  part::ShadedMesh shaded_;
  std::unique_ptr<render::StaticMesh> drawing_;  // triangles; lines: the edges, then the triangles' edges
  std::map<int, render::StaticMesh::Range> faceTriangles_;  // face id -> its triangles in the mesh
  uint32_t edgeLines_ = 0;
  double deflection_ = 0.0;  // of the mesh drawn
  double asked_ = 0.0;       // the deflection last tried (a refused one is not tried again each frame)
  float tolerancePx_ = 0.0f;
  int picked_ = -1;  // face id, -1: none
  bool edges_ = true;
};

}  // namespace shapespline::viewer
