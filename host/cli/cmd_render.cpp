// `shapespline render`: draws a model headlessly with the Vulkan graphics pipeline (host/render) and
// writes a PNG. Surfaces are tessellated on the GPU (render/painter.h) and shaded with normal-based
// lighting; curves are drawn as lines with their control polygon and data points. --sweep writes a
// contact sheet of the same model at several λ or α values, each tile labelled with its value
// (tile_labels.h), with one camera for every tile. The camera fits what is drawn tightly into the
// tile (render::Camera::fit), below the label band.
#include "tile_labels.h"

#include <shapespline/cli/cmd_render.h>
#include <shapespline/cli/common.h>
#include <shapespline/core/family.h>
#include <shapespline/core/curve.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/png_writer.h>
#include <shapespline/render/painter.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
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

// One tile per sweep value, composed left to right, top to bottom.
struct Sheet {
  int cols = 1, rows = 1, w = 0, h = 0;
  std::vector<uint8_t> rgba;
  void place(const render::Image& img, size_t k) {
    const int cx = int(k) % cols, cy = int(k) / cols;
    for (int y = 0; y < h; ++y)
      std::copy_n(img.rgba.data() + size_t(y) * w * 4, size_t(w) * 4,
                  rgba.data() + ((size_t(cy) * h + y) * size_t(cols) * w + size_t(cx) * w) * 4);
  }
};

// The sweep's tile labels ("lambda = 0.5"), drawn into each tile image before it is placed; none
// for a single render or tiles too small for text.
class TileLabeller {
 public:
  TileLabeller(const Sweep& sweep, int w, int h)
      : sweep_(sweep), layout_(sweep.values.empty() ? LabelLayout{} : labelLayout(w, h)) {
    if (layout_.fontPx > 0) font_.emplace(layout_.fontPx);
  }
  // Rows at the top of each tile the model must leave free.
  int band() const { return font_ ? layout_.bandHeight() : 0; }
  std::string text(size_t k) const { return sweepLabel(sweep_.alpha ? "alpha" : "lambda", sweep_.values[k]); }
  render::Image apply(render::Image tile, size_t k, const glm::vec3& background, double marginX) const {
    if (font_) font_->draw(tile, int(marginX), 0, layout_.pad, text(k), kLabelInk, background);
    return tile;
  }

 private:
  const Sweep& sweep_;
  LabelLayout layout_;
  std::optional<LabelFont> font_;
};

}  // namespace

void renderModel(const RenderArgs& a, io::OutputSet& outputs) {
  const auto [w, h] = parseImageSize(a.size, "--size", 16);
  const Sweep sweep = parseSweep(a.sweep);
  if (a.rate < 1 || a.rate > 256) throw InputError("--rate", std::to_string(a.rate), "expected 1..256 segments per patch edge");
  io::Model model = loadModel(a.model);
  if (a.lambda) std::visit([&](auto& m) { m.family.lambda = *a.lambda; }, model);
  const bool isSurface = std::holds_alternative<SurfaceModel>(model);
  if (!isSurface) {
    for (const char* o : {"--rate", "--wireframe", "--control-net"})
      refuseOption(a.given, o, "curves (drawn as lines with their control polygon and data points)");
  }
  const Construction construction = std::visit([](const auto& m) { return m.family.construction; }, model);
  if (!familyOf(construction).usesLambda) {
    const std::string what = "a '" + std::string(constructionName(construction)) + "' model, which has no lambda";
    refuseOption(a.given, "--lambda", what);
    if (!sweep.values.empty() && !sweep.alpha) throw InputError("--sweep", a.sweep, "lambda sweeps do not apply to " + what);
  }
  double az = isSurface ? 35.0 : -90.0, el = isSurface ? 30.0 : 90.0;
  if (!isSurface && std::get<CurveModel>(model).dimension == 3) az = 35.0, el = 30.0;
  if (!a.view.empty()) {
    const auto v = parseNumbers(a.view, "--view");
    if (v.size() != 2 || v[1] < -90.0 || v[1] > 90.0)
      throw InputError("--view", a.view, "expected az,el in degrees with -90 <= el <= 90");
    az = v[0];
    el = v[1];
  }
  if (!io::pngSupported()) throw std::runtime_error("this build has no libpng; render cannot write PNG files");
  // Opened before any rendering: a bad -o is bad input (exit 2), and the old PNG is replaced only
  // by a complete new one.
  outputs.reads(a.model, "MODEL");
  io::AtomicFile& png = outputs.add(a.output, "-o");

  render::Painter painter(w, h);
  const size_t tiles = std::max<size_t>(1, sweep.values.size());
  Sheet sheet;
  sheet.cols = tiles <= 4 ? int(tiles) : int(std::ceil(std::sqrt(double(tiles))));
  sheet.rows = int((tiles + sheet.cols - 1) / sheet.cols);
  sheet.w = w;
  sheet.h = h;
  sheet.rgba.assign(size_t(sheet.cols) * w * size_t(sheet.rows) * h * 4, 255);
  const TileLabeller labels(sweep, w, h);
  const render::PixelRect target = fitTarget(w, h, labels.band());
  const glm::vec3 background = render::Scene{}.background;

  // One camera for every tile, so that tiles compare at one scale: it fits what any tile draws
  // (the CPU-evaluated shapes of every value, and the nets where they are drawn).
  std::vector<glm::dvec3> fitted;
  if (isSurface) {
    const SurfaceModel& base = std::get<SurfaceModel>(model);
    if (a.controlNet) fitted = base.points;
    for (size_t k = 0; k < tiles; ++k) addSurfaceSamples(Surface::create(withValue(base, sweep, k)), fitted);
    const Surface first = Surface::create(withValue(base, sweep, 0));
    std::unique_ptr<render::SurfaceDrawing> drawing = painter.tessellate(first, a.rate, a.wireframe);
    const render::Camera cam = render::Camera::fit(fitted, az, el, w, h, target);
    for (size_t k = 0; k < tiles; ++k) {
      if (!sweep.values.empty()) {
        if (sweep.alpha) {
          drawing->setAlphas(std::vector<double>(base.alpha.size(), sweep.values[k]));
        } else {
          drawing->setLambda(sweep.values[k]);
        }
      }
      render::Scene scene;
      if (a.controlNet) {
        for (int i = 0; i < base.rows; ++i) {
          std::vector<glm::dvec3> row;
          for (int j = 0; j < base.cols; ++j) row.push_back(base.at(i, j));
          if (base.closedV) row.push_back(base.at(i, 0));
          render::addPolyline(scene.lines, row, kNetColour);
        }
        for (int j = 0; j < base.cols; ++j) {
          std::vector<glm::dvec3> col;
          for (int i = 0; i < base.rows; ++i) col.push_back(base.at(i, j));
          if (base.closedU) col.push_back(base.at(0, j));
          render::addPolyline(scene.lines, col, kNetColour);
        }
        for (const auto& p : base.points) render::addMarker(scene.markers, p, 5.0f, kDataColour);
      }
      sheet.place(labels.apply(painter.draw(*drawing, scene, cam), k, background, target.x0), k);
      if (!a.quiet && !sweep.values.empty())
        std::fprintf(stderr, "shapespline: tile %zu: %s\n", k + 1, labels.text(k).c_str());
    }
  } else {
    const CurveModel& base = std::get<CurveModel>(model);
    std::vector<std::vector<glm::dvec3>> polylines(tiles);
    fitted = base.points;  // the control polygon and the data points are always drawn
    for (size_t k = 0; k < tiles; ++k) {
      const Curve c = Curve::create(withValue(base, sweep, k));
      const SpanRange r = c.spans();
      for (int s = r.first; s <= r.last; ++s)
        for (int q = (s == r.first ? 0 : 1); q <= 64; ++q) polylines[k].push_back(c.evaluate(s, q / 64.0).point);
      fitted.insert(fitted.end(), polylines[k].begin(), polylines[k].end());
    }
    const render::Camera cam = render::Camera::fit(fitted, az, el, w, h, target);
    for (size_t k = 0; k < tiles; ++k) {
      render::Scene scene;
      std::vector<glm::dvec3> poly = base.points;
      if (base.closed && !poly.empty()) poly.push_back(poly.front());
      render::addPolyline(scene.lines, poly, kNetColour);
      render::addPolyline(scene.lines, polylines[k], kCurveColour);
      for (const auto& p : base.points) render::addMarker(scene.markers, p, 6.0f, kDataColour);
      sheet.place(labels.apply(painter.draw(scene, cam), k, background, target.x0), k);
      if (!a.quiet && !sweep.values.empty())
        std::fprintf(stderr, "shapespline: tile %zu: %s\n", k + 1, labels.text(k).c_str());
    }
  }
  // Opaque output: the background colour was cleared with alpha 0 (the coverage mask).
  io::writePng(png, sheet.cols * w, sheet.rows * h, sheet.rgba, false);
  if (!a.quiet) std::fprintf(stderr, "shapespline: wrote %s (%d x %d)\n", a.output.c_str(), sheet.cols * w, sheet.rows * h);
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
  sub->add_option("MODEL", args->model, "model file (docs/format.md)")->required();
  sub->add_option("-o,--output", args->output, "PNG file to write")->required();
  sub->add_option("--size", args->size, "image (tile) size WxH")->capture_default_str();
  sub->add_option("--lambda", args->lambda, "override the model's lambda");
  sub->add_option("--rate", args->rate, "tessellation: segments per patch edge")->capture_default_str();
  sub->add_flag("--wireframe", args->wireframe, "draw the tessellation's edges over the surface");
  sub->add_flag("--control-net", args->controlNet, "draw the control net and its points");
  sub->add_option("--view", args->view, "camera azimuth,elevation in degrees (surfaces 35,30; 2-D curves -90,90)");
  sub->add_option("--sweep", args->sweep, "contact sheet: lambda=v1,v2,... or alpha=v1,v2,... (one tile per value)");
  sub->add_flag("-q,--quiet", args->quiet, "no notices on stderr");
  sub->footer(kExitCodeHelp);
  sub->callback([args, sub] {
    args->given = givenOptions(*sub);
    runRender(*args);
  });
}

}  // namespace shapespline::cli
