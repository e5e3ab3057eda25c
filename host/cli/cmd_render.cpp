// `shapespline render`: draws a model headlessly with the Vulkan graphics pipeline (host/render) and
// writes a PNG. Surfaces are tessellated on the GPU (render/painter.h) and shaded with normal-based
// lighting; curves are drawn as wide lines with their control polygon and data points. --sweep
// writes a contact sheet of the same model at several λ or α values, each tile labelled with its
// value in a header band (tile_labels.h), with one camera for every tile; --overlay draws a curve's
// values into one tile instead, a colour each, named in a legend. The camera fits what is drawn
// tightly into the tile (render::Camera::fit), below the header band. `demo` composes its sheet from
// several plans (planRender, renderTiles, composeSheet) with one painter.
#include "deviation_map.h"
#include "distance_map.h"
#include "tile_labels.h"

#include <shapespline/cli/cmd_render.h>
#include <shapespline/cli/common.h>
#include <shapespline/core/family.h>
#include <shapespline/core/curve.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/surface.h>
#include <shapespline/core/tess_topology.h>
#include <shapespline/core/value_text.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/png_writer.h>
#include <shapespline/part/projection_tree.h>
#include <shapespline/part/shaded_mesh.h>
#include <shapespline/render/painter.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace shapespline::cli {
namespace {

struct Sweep {
  bool alpha = false;              // else λ
  std::vector<double> values;      // empty: one frame at the model's parameters
};

Sweep parseSweep(const std::string& text) {
  Sweep s;
  if (text.empty()) return s;
  const auto eq = text.find('=');
  const std::string key = text.substr(0, eq);
  if (eq == std::string::npos || (key != "lambda" && key != "alpha"))
    throw InputError("--sweep", text, "expected lambda=v1,v2,... or alpha=v1,v2,...");
  s.alpha = key == "alpha";
  s.values = parseNumbers(text.substr(eq + 1), "--sweep");
  if (s.values.empty() || s.values.size() > 64) throw InputError("--sweep", text, "expected 1 to 64 values");
  return s;
}

// The part of a tile the model is fitted into: a margin of 3% of the tile's smaller side (at least
// 4 px, room for the 6 px point markers and for bulges between the fitted samples), below the
// label band.
render::PixelRect fitTarget(int w, int h, int labelBand) {
  const double margin = std::max(4.0, std::round(0.03 * std::min(w, h)));
  return {margin, labelBand + margin, w - margin, h - margin};
}

// Samples of every patch for the camera to fit: (n+1)^2 per patch, n from 8 down to 2 as the patch
// count grows, so that a tile costs at most about 2^14 CPU evaluations.
void addSurfaceSamples(const Surface& s, std::vector<glm::dvec3>& out) {
  const auto patches = surfaceGridItems(s);  // knot vectors: the non-empty interval pairs
  const int n = std::clamp(int(std::sqrt(16384.0 / double(patches.size()))) - 1, 2, 8);
  for (const auto& [i, j] : patches)
    for (int a = 0; a <= n; ++a)
      for (int b = 0; b <= n; ++b) out.push_back(s.evaluate(i, j, double(a) / n, double(b) / n).point);
}

// Model with the sweep value applied (validated when the Surface/Curve is created).
template <typename Model>
Model withValue(Model m, const Sweep& s, size_t k) {
  if (s.values.empty()) return m;
  if (s.alpha) {
    if (m.family.construction != Construction::AlphaEB)
      throw InputError("--sweep", "alpha", "alpha sweeps need an alpha_eb model");
    std::fill(m.alpha.begin(), m.alpha.end(), s.values[k]);
  } else {
    m.family.lambda = s.values[k];
  }
  return m;
}

const glm::vec4 kNetColour{0.45f, 0.45f, 0.5f, 1.0f};
const glm::vec4 kDataColour{0.85f, 0.1f, 0.1f, 1.0f};
const glm::vec4 kCurveColour{0.1f, 0.25f, 0.75f, 1.0f};
const glm::vec3 kLabelInk{0.1f, 0.1f, 0.1f};
constexpr float kCurveWidthPx = 2.5f;  // curves drawn wide enough to tell their colours apart
constexpr int kCurveSamplesPerSpan = 64;

// The colours of an --overlay's curves, one per value in order (Okabe and Ito's palette, which
// readers with the common colour-vision deficiencies also tell apart; no red, the data points' colour).
struct PaletteColour {
  const char* name;
  glm::vec4 colour;
};
constexpr PaletteColour kOverlayPalette[] = {{"blue", {0.0f, 0.45f, 0.70f, 1.0f}},
                                             {"orange", {0.90f, 0.60f, 0.0f, 1.0f}},
                                             {"green", {0.0f, 0.62f, 0.45f, 1.0f}},
                                             {"purple", {0.80f, 0.47f, 0.65f, 1.0f}},
                                             {"sky blue", {0.34f, 0.71f, 0.91f, 1.0f}},
                                             {"yellow", {0.85f, 0.75f, 0.0f, 1.0f}}};
constexpr size_t kMaxOverlay = std::size(kOverlayPalette);

std::string parameterName(const RenderPlan& p) { return p.alphaSweep ? "alpha" : "lambda"; }

// The header of every tile of a plan (the same number of lines in each, so one camera target fits
// them all), its layout and font; no band for a single render without a title.
class TileHeaders {
 public:
  TileHeaders(const RenderArgs& a, const RenderPlan& p, std::optional<ColourBar> bar = std::nullopt)
      : args_(a), plan_(p), bar_(std::move(bar)) {
    if (header(0).lines() > 0) layout_ = labelLayout(p.width, p.height);
    if (layout_.fontPx > 0) font_.emplace(layout_.fontPx);
  }
  // Rows at the top of each tile the model must leave free.
  int band() const { return font_ ? header(0).lines() * layout_.lineHeight() : 0; }
  // "lambda = 0.5": what tile k of a sweep shows.
  std::string value(size_t k) const { return sweepLabel(parameterName(plan_), plan_.values[k]); }
  TileHeader header(size_t k) const {
    TileHeader h{args_.title, {}, bar_};
    if (plan_.values.empty()) return h;
    if (bar_) {  // the surface at the second value, coloured by its distance from the first
      h.title = args_.title.empty() ? value(1) : args_.title + ": " + value(1);
    } else if (args_.overlay) {
      for (size_t i = 0; i < plan_.values.size(); ++i)
        h.legend.push_back({value(i), glm::vec3(kOverlayPalette[i].colour)});
    } else {
      h.title = args_.title.empty() ? value(k) : args_.title + ": " + value(k);
    }
    return h;
  }
  render::Image apply(render::Image tile, size_t k, double marginX) const {
    if (font_) drawHeader(tile, *font_, layout_, header(k), int(marginX), kLabelInk);
    return tile;
  }

 private:
  const RenderArgs& args_;
  const RenderPlan& plan_;
  std::optional<ColourBar> bar_;
  LabelLayout layout_;
  std::optional<LabelFont> font_;
};

// A --deviation cloud's markers: small enough that neighbours stay apart in a dense scan.
constexpr float kDeviationMarkerPx = 3.0f;

// `deviation` (optional): a cloud drawn over the surface, coloured up to `scaleTop`.
std::vector<render::Image> surfaceTiles(const RenderArgs& a, const RenderPlan& p, const Sweep& sweep,
                                        render::Painter& painter, const TileHeaders& headers,
                                        const DeviationCloud* deviation = nullptr, double scaleTop = 0.0) {
  const int w = p.width, h = p.height;
  const render::PixelRect target = fitTarget(w, h, headers.band());
  const SurfaceModel& base = std::get<SurfaceModel>(p.model);
  const size_t count = std::max<size_t>(1, sweep.values.size());
  // One camera for every tile, so that tiles compare at one scale: it fits what any tile draws
  // (the CPU-evaluated shapes of every value, and the net where it is drawn).
  std::vector<glm::dvec3> fitted;
  if (a.controlNet) fitted = base.points;
  for (size_t k = 0; k < count; ++k) addSurfaceSamples(Surface::create(withValue(base, sweep, k)), fitted);
  if (deviation) fitted.insert(fitted.end(), deviation->points.begin(), deviation->points.end());
  const Surface first = Surface::create(withValue(base, sweep, 0));
  std::unique_ptr<render::SurfaceDrawing> drawing = painter.tessellate(first, a.rate, a.wireframe);
  const render::Camera cam = render::Camera::fit(fitted, p.az, p.el, w, h, target);
  render::Scene net;
  if (a.controlNet) {
    for (int i = 0; i < base.rows; ++i) {
      std::vector<glm::dvec3> row;
      for (int j = 0; j < base.cols; ++j) row.push_back(base.at(i, j));
      if (base.closedV) row.push_back(base.at(i, 0));
      render::addPolyline(net.lines, row, kNetColour);
    }
    for (int j = 0; j < base.cols; ++j) {
      std::vector<glm::dvec3> col;
      for (int i = 0; i < base.rows; ++i) col.push_back(base.at(i, j));
      if (base.closedU) col.push_back(base.at(0, j));
      render::addPolyline(net.lines, col, kNetColour);
    }
    for (const auto& q : base.points) render::addMarker(net.markers, q, 5.0f, kDataColour);
  }
  if (deviation) addDeviationMarkers(net, *deviation, scaleTop, kDeviationMarkerPx, cam);
  std::vector<render::Image> tiles;
  for (size_t k = 0; k < count; ++k) {
    if (!sweep.values.empty()) {
      if (sweep.alpha) {
        drawing->setAlphas(std::vector<double>(base.alpha.size(), sweep.values[k]));
      } else {
        drawing->setLambda(sweep.values[k]);
      }
    }
    tiles.push_back(headers.apply(painter.draw(*drawing, net, cam), k, target.x0));
    if (!a.quiet && !sweep.values.empty())
      std::fprintf(stderr, "shapespline: tile %zu: %s\n", k + 1, headers.value(k).c_str());
  }
  return tiles;
}

// Segments per patch edge of a distance map: about 2^16 points in all, 2 to 32 per patch edge.
int distanceMeshRate(size_t patches) { return std::clamp(int(std::sqrt(65536.0 / double(patches))) - 1, 2, 32); }

// --distance: one tile, the surface at the second value coloured by its distance from the first.
render::Image distanceTile(const RenderPlan& p, const DistanceMesh& mesh, render::Painter& painter,
                           const TileHeaders& headers) {
  const render::PixelRect target = fitTarget(p.width, p.height, headers.band());
  const render::Camera cam = render::Camera::fit(mesh.points, p.az, p.el, p.width, p.height, target);
  render::Scene scene;
  addDistanceMesh(scene, mesh, cam);
  return headers.apply(painter.draw(scene, cam), 0, target.x0);
}

std::vector<render::Image> curveTiles(const RenderArgs& a, const RenderPlan& p, const Sweep& sweep,
                                      render::Painter& painter, const TileHeaders& headers) {
  const int w = p.width, h = p.height;
  const render::PixelRect target = fitTarget(w, h, headers.band());
  const CurveModel& base = std::get<CurveModel>(p.model);
  const size_t count = std::max<size_t>(1, sweep.values.size());
  std::vector<std::vector<glm::dvec3>> polylines(count);
  std::vector<glm::dvec3> fitted = base.points;  // the control polygon and the data points are always drawn
  for (size_t k = 0; k < count; ++k) {
    const Curve c = Curve::create(withValue(base, sweep, k));
    const SpanRange r = c.spans();
    for (int s = r.first; s <= r.last; ++s)
      for (int q = (s == r.first ? 0 : 1); q <= kCurveSamplesPerSpan; ++q)
        polylines[k].push_back(c.evaluate(s, double(q) / kCurveSamplesPerSpan).point);
    fitted.insert(fitted.end(), polylines[k].begin(), polylines[k].end());
  }
  const render::Camera cam = render::Camera::fit(fitted, p.az, p.el, w, h, target);
  const auto scene = [&](size_t first, size_t last) {  // the curves first..last-1 over the polygon
    render::Scene s;
    std::vector<glm::dvec3> polygon = base.points;
    if (base.closed && !polygon.empty()) polygon.push_back(polygon.front());
    render::addPolyline(s.lines, polygon, kNetColour);
    for (size_t k = first; k < last; ++k) {
      const glm::vec4 colour = a.overlay ? kOverlayPalette[k].colour : kCurveColour;
      render::addWidePolyline(s.markers, polylines[k], kCurveWidthPx, colour, cam, w, h);
    }
    for (const auto& q : base.points) render::addMarker(s.markers, q, 6.0f, kDataColour);
    return s;
  };
  if (a.overlay) {
    if (!a.quiet)
      for (size_t k = 0; k < count; ++k)
        std::fprintf(stderr, "shapespline: %s: %s\n", headers.value(k).c_str(), kOverlayPalette[k].name);
    return {headers.apply(painter.draw(scene(0, count), cam), 0, target.x0)};
  }
  std::vector<render::Image> tiles;
  for (size_t k = 0; k < count; ++k) {
    tiles.push_back(headers.apply(painter.draw(scene(k, k + 1), cam), k, target.x0));
    if (!a.quiet && !sweep.values.empty())
      std::fprintf(stderr, "shapespline: tile %zu: %s\n", k + 1, headers.value(k).c_str());
  }
  return tiles;
}

// A part (or a trimmed face): its mesh at about half a pixel's deflection unless one is given, shaded
// with each face's own normals, with its edges and the triangles' edges where asked.
// `deviation` (optional): a cloud drawn over the part, coloured up to `scaleTop`.
render::Image partTile(const RenderArgs& a, const RenderPlan& p, render::Painter& painter, const TileHeaders& headers,
                       const DeviationCloud* deviation = nullptr, double scaleTop = 0.0) {
  const part::Part& part = *p.part;
  // The camera fits the part into the smaller side, so the diagonal spans at most that many pixels.
  const double halfPixel = 0.5 / double(std::min(p.width, p.height));
  PartMeshSettings settings = partMeshSettings(a.mesh, part, halfPixel, a.model);
  settings.options.cornerNormals = true;
  part::CpuFaceEvaluator evaluator;
  const part::PartMesh mesh = meshOrRefuse(part, settings, a.mesh, evaluator);
  const part::ShadedMesh shaded = part::shadedMesh(mesh);
  std::vector<uint32_t> lines;
  if (a.edges) lines = shaded.edgeLines;
  if (a.wireframe) {
    const std::vector<uint32_t> wire = triangleEdges(shaded.triangles);
    lines.insert(lines.end(), wire.begin(), wire.end());
  }
  const auto drawing = painter.upload(shaded.positions, shaded.normals, shaded.triangles, lines);
  const render::PixelRect target = fitTarget(p.width, p.height, headers.band());
  std::vector<glm::dvec3> fitted = mesh.mesh.positions;
  if (deviation) fitted.insert(fitted.end(), deviation->points.begin(), deviation->points.end());
  const render::Camera cam = render::Camera::fit(fitted, p.az, p.el, p.width, p.height, target);
  render::Scene scene;
  if (deviation) addDeviationMarkers(scene, *deviation, scaleTop, kDeviationMarkerPx, cam);
  render::MeshDraw draw = drawing->draw();
  draw.color = render::kPartColour;
  draw.wireColor = render::kPartEdgeColour;
  scene.meshes.push_back(draw);
  if (!a.quiet)
    std::fprintf(stderr, "shapespline: %d faces, %zu triangles, deflection %s, %lld open edges\n", mesh.faces,
                 mesh.mesh.triangles.size(), shortestText(settings.options.deflection).c_str(),
                 static_cast<long long>(mesh.boundaryEdges));
  return headers.apply(painter.draw(scene, cam), 0, target.x0);
}

// --deviation: the cloud projected onto the part or surface and drawn over it, coloured by distance
// from 0 to the largest, with the colour bar in the header.
render::Image deviationTile(const RenderArgs& a, const RenderPlan& p, render::Painter& painter) {
  std::optional<Surface> surface;
  if (!p.part) surface.emplace(Surface::create(std::get<SurfaceModel>(p.model)));
  const part::ProjectionTree tree =
      p.part ? part::ProjectionTree::ofPart(*p.part) : part::ProjectionTree::ofFaces({{&*surface, 0, false}});
  const DeviationCloud cloud = deviationCloud(a.deviation, "--deviation", tree);
  char top[32];
  std::snprintf(top, sizeof top, "%.3g", cloud.maxDistance);
  const TileHeaders headers(a, p, ColourBar{"distance:", "0", top});
  if (!a.quiet)
    std::fprintf(stderr, "shapespline: %llu points, distance max %.6g, mean %.6g; every %llu%s drawn\n",
                 static_cast<unsigned long long>(cloud.count), cloud.maxDistance, cloud.meanDistance,
                 static_cast<unsigned long long>(cloud.stride), cloud.stride == 1 ? "" : "th");
  if (p.part) return partTile(a, p, painter, headers, &cloud, cloud.maxDistance);
  return surfaceTiles(a, p, Sweep{}, painter, headers, &cloud, cloud.maxDistance).front();
}

// Up to 4 tiles in one row, else ceil(sqrt(n)) columns.
int sheetColumns(size_t tiles) { return tiles <= 4 ? int(tiles) : int(std::ceil(std::sqrt(double(tiles)))); }

}  // namespace

RenderPlan planRender(const RenderArgs& a) {
  RenderPlan p;
  std::tie(p.width, p.height) = parseImageSize(a.size, "--size", 16);
  const Sweep sweep = parseSweep(a.sweep);
  p.alphaSweep = sweep.alpha;
  p.values = sweep.values;
  if (a.rate < 1 || a.rate > 256) throw InputError("--rate", std::to_string(a.rate), "expected 1..256 segments per patch edge");
  if (!std::all_of(a.title.begin(), a.title.end(), [](char c) { return c >= ' ' && c <= '~'; }) || a.title.size() > 80)
    throw InputError("--title", a.title, "expected up to 80 printable ASCII characters (the label font has no others)");
  p.part = partToDraw(a.model, p.model);
  const std::string partOnly = "a model that is not a part or a trimmed face (it applies to their meshes)";
  for (const char* o : {"--deflection", "--relative-deflection", "--angle", "--max-triangles", "--edges"})
    if (!p.part) refuseOption(a.given, o, partOnly);
  if (p.part) {
    const std::string what = "a part or a trimmed face (drawn as its mesh; --deflection sets how fine)";
    for (const char* o : {"--rate", "--control-net", "--lambda", "--overlay", "--distance"}) refuseOption(a.given, o, what);
    if (!p.values.empty()) throw InputError("--sweep", a.sweep, "does not apply to " + what);
  }
  if (a.lambda && !p.part) std::visit([&](auto& m) { m.family.lambda = *a.lambda; }, p.model);
  const bool isSurface = p.part || std::holds_alternative<SurfaceModel>(p.model);
  if (!isSurface) {
    for (const char* o : {"--rate", "--wireframe", "--control-net"})
      refuseOption(a.given, o, "curves (drawn as lines with their control polygon and data points)");
  }
  if (a.overlay) {
    if (isSurface) throw InputError("--overlay", a.model, "overlays draw curves; a surface sweep has one tile per value");
    if (p.values.empty()) throw InputError("--overlay", a.sweep, "needs --sweep with the values to overlay");
    if (p.values.size() > kMaxOverlay)
      throw InputError("--overlay", a.sweep, "an overlay draws at most " + std::to_string(kMaxOverlay) + " values");
  }
  if (!a.deviation.empty()) {
    if (!isSurface) throw InputError("--deviation", a.model, "a deviation map draws a cloud over a surface or a part, not a curve");
    if (!p.values.empty()) throw InputError("--sweep", a.sweep, "does not apply to a deviation map (one tile)");
    refuseOption(a.given, "--distance", "a deviation map (the cloud is coloured, not the surface)");
  }
  if (a.distance) {
    if (!isSurface) throw InputError("--distance", a.model, "distance maps colour surfaces; curves take --overlay");
    if (p.values.size() != 2)
      throw InputError("--distance", a.sweep, "needs --sweep with two values: the surface at the second is coloured by its distance from the first");
    for (const char* o : {"--rate", "--wireframe", "--control-net"})
      refuseOption(a.given, o, "a distance map (the surface is evaluated on the CPU, its patch lines drawn)");
  }
  const Construction construction = std::visit([](const auto& m) { return m.family.construction; }, p.model);
  if (!p.part && !familyOf(construction).usesLambda) {
    const std::string what = "a '" + std::string(constructionName(construction)) + "' model, which has no lambda";
    refuseOption(a.given, "--lambda", what);
    if (!p.values.empty() && !p.alphaSweep) throw InputError("--sweep", a.sweep, "lambda sweeps do not apply to " + what);
  }
  p.az = isSurface ? 35.0 : -90.0;
  p.el = isSurface ? 30.0 : 90.0;
  if (!isSurface && std::get<CurveModel>(p.model).dimension == 3) p.az = 35.0, p.el = 30.0;
  if (!a.view.empty()) {
    const auto v = parseNumbers(a.view, "--view");
    if (v.size() != 2 || v[1] < -90.0 || v[1] > 90.0)
      throw InputError("--view", a.view, "expected az,el in degrees with -90 <= el <= 90");
    p.az = v[0];
    p.el = v[1];
  }
  return p;
}

std::vector<render::Image> renderTiles(const RenderArgs& a, const RenderPlan& plan, render::Painter& painter) {
  if (painter.width() != plan.width || painter.height() != plan.height)
    throw std::logic_error("renderTiles: the painter's size is not the plan's tile size");
  const Sweep sweep{plan.alphaSweep, plan.values};
  if (a.distance) {
    const SurfaceModel& base = std::get<SurfaceModel>(plan.model);
    const Surface from = Surface::create(withValue(base, sweep, 0)), to = Surface::create(withValue(base, sweep, 1));
    const DistanceMesh mesh = distanceMesh(from, to, distanceMeshRate(surfaceGridItems(to).size()));
    char top[32];
    std::snprintf(top, sizeof top, "%.2g", mesh.scaleTop);
    const std::string fromText = sweepLabel(plan.alphaSweep ? "alpha" : "lambda", plan.values[0]);
    const TileHeaders headers(a, plan, ColourBar{"distance from " + fromText + ":", "0", top});
    if (!a.quiet)
      std::fprintf(stderr, "shapespline: %s, coloured by its distance from %s: at most %.17g, the scale up to %.17g\n",
                   headers.value(1).c_str(), fromText.c_str(), mesh.maxDistance, mesh.scaleTop);
    return {distanceTile(plan, mesh, painter, headers)};
  }
  if (!a.deviation.empty()) return {deviationTile(a, plan, painter)};
  const TileHeaders headers(a, plan);
  if (plan.part) return {partTile(a, plan, painter, headers)};
  if (std::holds_alternative<SurfaceModel>(plan.model)) return surfaceTiles(a, plan, sweep, painter, headers);
  return curveTiles(a, plan, sweep, painter, headers);
}

render::Image composeSheet(const std::vector<render::Image>& tiles, int cols) {
  const int w = tiles.at(0).width, h = tiles.at(0).height;
  const int rows = int((tiles.size() + size_t(cols) - 1) / size_t(cols));
  render::Image sheet{cols * w, rows * h, std::vector<uint8_t>(size_t(cols) * w * size_t(rows) * h * 4, 255)};
  for (size_t k = 0; k < tiles.size(); ++k) {
    const int cx = int(k) % cols, cy = int(k) / cols;
    for (int y = 0; y < h; ++y)
      std::copy_n(tiles[k].rgba.data() + size_t(y) * w * 4, size_t(w) * 4,
                  sheet.rgba.data() + ((size_t(cy) * h + y) * size_t(sheet.width) + size_t(cx) * w) * 4);
  }
  return sheet;
}

void renderModel(const RenderArgs& a, io::OutputSet& outputs) {
  const RenderPlan plan = planRender(a);
  if (!io::pngSupported()) throw std::runtime_error("this build has no libpng; render cannot write PNG files");
  // Opened before any rendering: a bad -o is bad input (exit 2), and the old PNG is replaced only
  // by a complete new one.
  outputs.reads(a.model, "MODEL");
  if (!a.deviation.empty()) outputs.reads(a.deviation, "--deviation");
  if (plan.part)
    for (const part::PartFace& face : plan.part->faces)
      if (face.model != std::filesystem::path(a.model)) outputs.reads(face.model, "MODEL's face");
  io::AtomicFile& png = outputs.add(a.output, "-o");
  render::Painter painter(plan.width, plan.height);
  const std::vector<render::Image> tiles = renderTiles(a, plan, painter);
  const render::Image sheet = composeSheet(tiles, sheetColumns(tiles.size()));
  // Opaque output: the background colour was cleared with alpha 0 (the coverage mask).
  io::writePng(png, sheet.width, sheet.height, sheet.rgba, false);
  if (!a.quiet) std::fprintf(stderr, "shapespline: wrote %s (%d x %d)\n", a.output.c_str(), sheet.width, sheet.height);
}

namespace {

void runRender(const RenderArgs& a) {
  io::OutputSet outputs;
  renderModel(a, outputs);
  outputs.commit();
}

}  // namespace

void registerRender(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* sub = app.add_subcommand(
      "render", "Render a model headlessly (Vulkan graphics pipeline) to a PNG: shaded surfaces, curves as lines.");
  sub->add_option("MODEL", args->model, "model file (docs/format.md), or a part's part.json (`import`)")->required();
  sub->add_option("-o,--output", args->output, "PNG file to write")->required();
  sub->add_option("--size", args->size, "image (tile) size WxH")->capture_default_str();
  sub->add_option("--lambda", args->lambda, "override the model's lambda");
  sub->add_option("--rate", args->rate, "tessellation: segments per patch edge")->capture_default_str();
  sub->add_flag("--wireframe", args->wireframe, "draw the tessellation's (or the part mesh's) edges over the surface");
  sub->add_flag("--control-net", args->controlNet, "draw the control net and its points");
  sub->add_option("--view", args->view, "camera azimuth,elevation in degrees (surfaces 35,30; 2-D curves -90,90)");
  sub->add_option("--sweep", args->sweep, "contact sheet: lambda=v1,v2,... or alpha=v1,v2,... (one tile per value)");
  sub->add_flag("--overlay", args->overlay, "curves: draw every --sweep value into one tile, a colour each, with a legend");
  sub->add_flag("--distance", args->distance,
                "surfaces: with --sweep of two values, the surface at the second coloured by its distance from the first");
  sub->add_option("--deviation", args->deviation,
                  "a surface or a part: a cloud (as `project` reads) drawn over it, coloured by its distance to it");
  sub->add_option("--title", args->title, "a title over the picture (over each tile of a --sweep)");
  sub->add_flag("--edges", args->edges, "a part or a trimmed face: draw its edges (where faces meet, or a face ends)");
  addPartMeshOptions(sub, args->mesh, "half a pixel: 0.5 / the image's smaller side");
  addQuietFlag(sub, args->quiet, "no notices on stderr");
  sub->footer(kExitCodeHelp);
  sub->callback([args, sub] {
    args->given = givenOptions(*sub);
    runRender(*args);
  });
}

}  // namespace shapespline::cli
