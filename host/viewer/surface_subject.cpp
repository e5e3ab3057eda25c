#include <shapespline/viewer/surface_subject.h>

#include <shapespline/core/validate.h>
#include <shapespline/render/renderer.h>
#include <shapespline/viewer/errors.h>
#include <shapespline/viewer/picking.h>

#include <imgui.h>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <span>

namespace shapespline::viewer {
namespace {

using Kind = ScriptCommand::Kind;

constexpr float kPointPx = 6.0f, kPickedPx = 11.0f;
const glm::vec4 kNetColour{0.45f, 0.45f, 0.5f, 1.0f};
const glm::vec4 kPointColour{0.2f, 0.2f, 0.25f, 1.0f};
const glm::vec4 kPickedColour{0.9f, 0.1f, 0.1f, 1.0f};

// One element of GUBP's half vector μ moved, the nearest element of the same parity takes up the
// difference so that the full symmetric vector keeps its even and odd sums (docs/math.md §9).
// Returns false when there is no such element (μ_i cannot move alone).
bool moveMu(std::vector<double>& mu, int order, size_t i, double value) {
  auto weight = [&](size_t j) { return 2 * int(j) == order ? 1.0 : 2.0; };  // copies in the full vector
  for (size_t d = 2; d < mu.size() + 2; d += 2)
    for (size_t j : {i + d, i - d}) {
      if (j >= mu.size()) continue;  // i - d wrapped below zero as well
      mu[j] -= (value - mu[i]) * weight(i) / weight(j);
      mu[i] = value;
      return true;
    }
  return false;
}

}  // namespace

SurfaceSubject::SurfaceSubject(std::shared_ptr<vk::Context> ctx, const SurfaceModel& model, float tolerancePx,
                               bool triangleWireframe)
    : ctx_(std::move(ctx)),
      traits_(familyOf(model.family.construction)),
      cpu_(Surface::create(model)),
      gpuSurface_(ctx_, cpu_, Precision::Float) {
  controls_.family = model.family;
  controls_.alpha = model.alpha;
  controls_.tolerancePx = tolerancePx;
  applied_ = controls_;
  mesh_ = makeSurfaceMesh(ctx_, gpuSurface_, tolerancePx, triangleWireframe);
  uploadOverlay();
}

std::pair<glm::dvec3, glm::dvec3> SurfaceSubject::bounds() const {
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  cpu_.forEachControlPoint([&](const glm::dvec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  });
  return {lo, hi};
}

// The control net and its points (the picked one larger, red): rebuilt when the pick changes,
// after the frames in flight that read the old buffers.
void SurfaceSubject::uploadOverlay() {
  ctx_->waitIdle();
  const SurfaceShape& m = cpu_.model();
  std::vector<render::OverlayVertex> lines, markers;
  for (int i = 0; i < m.rows; ++i) {
    std::vector<glm::dvec3> row;
    for (int j = 0; j < m.cols; ++j) row.push_back(cpu_.controlPoint(i, j));
    if (m.closedV) row.push_back(cpu_.controlPoint(i, 0));
    render::addPolyline(lines, row, kNetColour);
  }
  for (int j = 0; j < m.cols; ++j) {
    std::vector<glm::dvec3> col;
    for (int i = 0; i < m.rows; ++i) col.push_back(cpu_.controlPoint(i, j));
    if (m.closedU) col.push_back(cpu_.controlPoint(0, j));
    render::addPolyline(lines, col, kNetColour);
  }
  int k = 0;
  cpu_.forEachControlPoint([&](const glm::dvec3& p) {
    const bool picked = k++ == controls_.picked;
    render::addMarker(markers, p, picked ? kPickedPx : kPointPx, picked ? kPickedColour : kPointColour);
  });
  auto upload = [&](const std::vector<render::OverlayVertex>& v, const char* label) {
    vk::Buffer b = vk::Buffer::create(*ctx_, std::max<size_t>(1, v.size()) * sizeof(render::OverlayVertex),
                                      VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                      vk::MemoryUse::Upload, label);
    if (!v.empty()) b.uploadSpan(std::span<const render::OverlayVertex>(v));
    return b;
  };
  netLines_ = upload(lines, "viewer.net");
  netMarkers_ = upload(markers, "viewer.points");
  lineCount_ = uint32_t(lines.size());
  markerCount_ = uint32_t(markers.size());
}

// λ/μ through setParameters, α point by point. The setters write memory the frames in flight
// read: they wait first.
std::string SurfaceSubject::apply(float tolerancePx, const View&) {
  std::string error;
  const bool familyChanged = controls_.family.lambda != applied_.family.lambda || controls_.family.mu != applied_.family.mu;
  const bool alphaChanged = controls_.alpha != applied_.alpha;
  if (familyChanged || alphaChanged) {
    ctx_->waitIdle();
    try {
      if (familyChanged) gpuSurface_.setParameters(controls_.family);
      applied_.family = controls_.family;
      const int cols = cpu_.model().cols;
      for (size_t k = 0; k < controls_.alpha.size(); ++k)
        if (controls_.alpha[k] != applied_.alpha[k]) {
          gpuSurface_.setAlpha(int(k) / cols, int(k) % cols, controls_.alpha[k]);
          applied_.alpha[k] = controls_.alpha[k];
        }
    } catch (const ModelError& e) {
      error = e.what();
      controls_.family = applied_.family;
      controls_.alpha = applied_.alpha;
    }
  }
  if (tolerancePx != applied_.tolerancePx) {
    mesh_->setTolerance(tolerancePx);
    applied_.tolerancePx = controls_.tolerancePx = tolerancePx;
  }
  if (controls_.picked != applied_.picked) {
    applied_.picked = controls_.picked;
    uploadOverlay();
  }
  applied_.net = controls_.net;
  return error;
}

render::OverlayDraw SurfaceSubject::overlay() const {
  if (!applied_.net) return {};
  return {netLines_.handle(), lineCount_, netMarkers_.handle(), markerCount_};
}

// The nearest control point within kPickRadiusPx, or none.
std::string SurfaceSubject::pick(double x, double y, const View& view) {
  controls_.picked = pickPoint(cpu_.controlPoints(), view.camera, int(view.extent.width), int(view.extent.height), x, y);
  if (controls_.picked < 0) return "";
  const int cols = cpu_.model().cols;
  return "control point (" + std::to_string(controls_.picked / cols) + ", " + std::to_string(controls_.picked % cols) + ")";
}

std::string SurfaceSubject::pickMiss() const {
  return "no control point projects within " + std::to_string(int(kPickRadiusPx)) + " px of the pixel";
}

void SurfaceSubject::setPickedAlpha(double a) {
  if (controls_.picked >= 0 && size_t(controls_.picked) < controls_.alpha.size()) controls_.alpha[controls_.picked] = a;
}

std::string SurfaceSubject::execute(const ScriptCommand& c, const View& view) {
  const SurfaceShape& m = cpu_.model();
  auto fail = [&](const std::string& rule) { throw ScriptError(c.line, c.text, rule); };
  std::string notice;
  switch (c.kind) {
    case Kind::Lambda:
      if (!traits_.usesLambda) fail(std::string(traits_.name) + " has no lambda");
      controls_.family.lambda = c.numbers[0];
      break;
    case Kind::Mu:
      if (!traits_.usesMu) fail(std::string(traits_.name) + " has no mu");
      controls_.family.mu = c.numbers;
      break;
    case Kind::Alpha:
      if (!traits_.usesAlpha) fail(std::string(traits_.name) + " has no per-point alpha");
      if (c.numbers.size() == 3) {
        const int i = int(c.numbers[0]), j = int(c.numbers[1]);
        if (i >= m.rows || j >= m.cols)
          fail("point (" + std::to_string(i) + ", " + std::to_string(j) + ") is outside the " +
               std::to_string(m.rows) + " x " + std::to_string(m.cols) + " net");
        controls_.picked = i * m.cols + j;
        setPickedAlpha(c.numbers[2]);
      } else {
        if (controls_.picked < 0) fail("no point is picked (pick X Y first)");
        setPickedAlpha(c.numbers[0]);
      }
      break;
    case Kind::PickPoint: {
      const int i = int(c.numbers[0]), j = int(c.numbers[1]);
      if (i >= m.rows || j >= m.cols)
        fail("the point is outside the " + std::to_string(m.rows) + " x " + std::to_string(m.cols) + " net");
      const glm::dvec2 at(
          view.camera.toPixel(cpu_.controlPoint(i, j), int(view.extent.width), int(view.extent.height)));
      const std::string picked = pick(at.x, at.y, view);
      if (picked.empty()) fail(pickMiss());
      notice = "picked " + picked;
      break;
    }
    case Kind::Net: controls_.net = c.on; break;
    default: fail("a surface model has no such control (pick-face and edges are a part's)");
  }
  if (const std::string error = apply(applied_.tolerancePx, view); !error.empty()) fail(error);
  return notice;
}

void SurfaceSubject::panelTitle(const PanelNote& note) {
  const SurfaceShape& m = cpu_.model();
  ImGui::Text("%s, %d x %d net", std::string(traits_.name).c_str(), m.rows, m.cols);
  note();
}

void SurfaceSubject::panelControls(const PanelNote& note) {
  const SurfaceShape& m = cpu_.model();
  if (traits_.usesLambda) {
    const LambdaDomain d = lambdaDomain(controls_.family);
    const double hi = std::isfinite(d.hi) ? d.hi : d.lo + 16.0;  // GB: no upper bound, the slider needs one
    ImGui::SliderScalar("lambda", ImGuiDataType_Double, &controls_.family.lambda, &d.lo, &hi, "%.3f");
    note();
  }
  if (traits_.usesMu) {
    std::vector<double>& mu = controls_.family.mu;
    for (size_t i = 0; i < mu.size(); ++i) {
      double v = mu[i];
      const double lo = 0.0, hi = 1.0;
      if (ImGui::SliderScalar(("mu" + std::to_string(i)).c_str(), ImGuiDataType_Double, &v, &lo, &hi, "%.4f"))
        moveMu(mu, controls_.family.order, i, v);
      note();
    }
  }
  if (traits_.usesAlpha) {
    if (controls_.picked >= 0) {
      ImGui::Text("point (%d, %d)", controls_.picked / m.cols, controls_.picked % m.cols);
      note();
      double a = controls_.alpha[controls_.picked];
      const double lo = 0.001, hi = 1.0;
      if (ImGui::SliderScalar("alpha", ImGuiDataType_Double, &a, &lo, &hi, "%.3f")) setPickedAlpha(a);
      note();
    } else {
      ImGui::TextDisabled("click a control point to edit its alpha");
      note();
    }
  }
}

void SurfaceSubject::panelToggles(const PanelNote& note) {
  ImGui::Checkbox("control net", &controls_.net);
  note();
}

bool SurfaceSubject::wireframeAvailable(const render::ScenePipelines& pipelines) const {
  return pipelines.triangleWireframe() || mesh_->name().rfind("fixed", 0) == 0;
}

}  // namespace shapespline::viewer
