#pragma once
// Subject: what `shapespline view` shows and edits (docs/viewer.md). The viewer (viewer.cpp) owns
// the window, the frames, the orbit camera and the controls every subject has (pixel tolerance,
// wireframe, panel); a subject owns its mesh, its overlay, its rows of the panel, its own script
// commands and what a click picks. Two kinds: a surface model, tessellated on the GPU for the view
// with its net and its λ, μ and α (surface_subject.h), and a part or a trimmed face, meshed on the
// host to the deflection the pixel tolerance gives (part_subject.h).
#include <shapespline/render/camera.h>
#include <shapespline/render/renderer.h>
#include <shapespline/render/scene_pipelines.h>
#include <shapespline/viewer/script.h>

#include <glm/vec3.hpp>
#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace shapespline::viewer {

// The frame's camera and image size.
struct View {
  render::Camera camera;
  VkExtent2D extent{};
  // The model-space length of one pixel at distance `depth` from the eye along the view.
  double pixelSize(double depth) const;
};

// Called after each panel item: the viewer keeps the corner of everything drawn (panel bounds).
using PanelNote = std::function<void()>;

class Subject {
 public:
  virtual ~Subject() = default;

  // The box the camera frames at the start.
  virtual std::pair<glm::dvec3, glm::dvec3> bounds() const = 0;
  // Brings the mesh and the overlay to the subject's controls and to the pixel tolerance for `view`,
  // between frames (may wait for the device to be idle). Returns the rule a value broke, after
  // putting the controls back, or "".
  virtual std::string apply(float tolerancePx, const View& view) = 0;
  // Before the frame's render pass: the compute passes of a GPU tessellation (nothing for a mesh
  // made on the host).
  virtual void record(VkCommandBuffer cmd, const View& view) = 0;
  // What the frame draws; `wireframe`: the triangles' edges as well.
  virtual std::vector<render::MeshDraw> meshes(bool wireframe) const = 0;
  virtual render::OverlayDraw overlay() const = 0;

  // A click at pixel (x, y): what it picked ("control point (2, 2)", "face 7 (plane)"), or "" when
  // it picked nothing; and why a script's `pick` may find nothing.
  virtual std::string pick(double x, double y, const View& view) = 0;
  virtual std::string pickMiss() const = 0;
  // The script commands that belong to the subject (lambda, mu, alpha, pick-point, net, pick-face,
  // edges): ScriptError for one it does not take. Returns a notice for stderr, or "".
  virtual std::string execute(const ScriptCommand& c, const View& view) = 0;

  // Panel rows: the first lines (what it is), the subject's sliders (before the tolerance slider)
  // and its check boxes (after the wireframe one).
  virtual void panelTitle(const PanelNote& note) = 0;
  virtual void panelControls(const PanelNote& note) = 0;
  virtual void panelToggles(const PanelNote& note) = 0;

  // "adaptive", "fixed rate 16", "deflection 0.0123".
  virtual std::string meshName() const = 0;
  // Triangles of the last recorded frame; may wait for the queue to be idle (a few times a second).
  virtual uint64_t triangleCount() const = 0;
  // Whether the wireframe check box can draw anything with these pipelines.
  virtual bool wireframeAvailable(const render::ScenePipelines& pipelines) const = 0;
};

}  // namespace shapespline::viewer
