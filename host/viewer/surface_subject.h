#pragma once
// SurfaceSubject: a surface model in the viewer. Tessellated on the GPU for each frame's camera
// (SurfaceMesh) at the pixel tolerance; its control net and points drawn over it; λ, GUBP's μ and
// each point's α edited from the panel or the script (a click picks the control point nearest to
// the cursor).
#include <shapespline/core/family.h>
#include <shapespline/core/model.h>
#include <shapespline/core/surface.h>
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/viewer/subject.h>
#include <shapespline/viewer/surface_mesh.h>
#include <shapespline/vk/buffer.h>
#include <shapespline/vk/context.h>

#include <memory>

namespace shapespline::viewer {

class SurfaceSubject final : public Subject {
 public:
  // Throws std::invalid_argument for a surface the GPU tessellators do not take.
  SurfaceSubject(std::shared_ptr<vk::Context> ctx, const SurfaceModel& model, float tolerancePx, bool triangleWireframe);

  std::pair<glm::dvec3, glm::dvec3> bounds() const override;
  std::string apply(float tolerancePx, const View& view) override;
  void record(VkCommandBuffer cmd, const View& view) override { mesh_->record(cmd, view.camera, view.extent); }
  std::vector<render::MeshDraw> meshes(bool wireframe) const override { return {mesh_->draw(wireframe)}; }
  render::OverlayDraw overlay() const override;
  std::string pick(double x, double y, const View& view) override;
  std::string pickMiss() const override;
  std::string execute(const ScriptCommand& c, const View& view) override;
  void panelTitle(const PanelNote& note) override;
  void panelControls(const PanelNote& note) override;
  void panelToggles(const PanelNote& note) override;
  std::string meshName() const override { return mesh_->name(); }
  uint64_t triangleCount() const override { return mesh_->triangleCount(); }
  bool wireframeAvailable(const render::ScenePipelines& pipelines) const override;

 private:
  // What the panel and the script edit.
  struct Controls {
    FamilySpec family;
    std::vector<double> alpha;  // rows * cols (α-EB), row-major
    int picked = -1;            // control point index, -1: none
    float tolerancePx = 1.0f;
    bool net = true;
  };
  void uploadOverlay();
  void setPickedAlpha(double a);

  std::shared_ptr<vk::Context> ctx_;
  const FamilyTraits& traits_;
  Surface cpu_;
  gpu::GpuSurface gpuSurface_;
  std::unique_ptr<SurfaceMesh> mesh_;
  Controls controls_, applied_;
  vk::Buffer netLines_, netMarkers_;
  uint32_t lineCount_ = 0, markerCount_ = 0;
};

}  // namespace shapespline::viewer
