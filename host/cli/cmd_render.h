#pragma once
// The `render` command's arguments and its work, also used by `demo` (its contact sheet).
#include <shapespline/cli/common.h>
#include <shapespline/cli/part_mesh_options.h>
#include <shapespline/io/model_json.h>
#include <shapespline/render/renderer.h>

#include <optional>
#include <string>
#include <vector>

namespace shapespline::io {
class OutputSet;
}
namespace shapespline::render {
class Painter;
}

namespace shapespline::cli {

struct RenderArgs {
  std::string model, output, size = "800x600", view, sweep, title;
  std::string deviation;  // a cloud drawn over the model, coloured by its distance to it (deviation_map.h)
  std::optional<double> lambda;
  bool wireframe = false, controlNet = false, overlay = false, distance = false, quiet = false;
  int rate = 16;
  PartMeshArgs mesh;   // a part or a trimmed face: the mesh drawn (default: half a pixel's deflection)
  bool edges = false;  // a part or a trimmed face: draw its edges (where faces meet, or a face ends)
  GivenOptions given;  // the options given on the command line (refused where they do not apply)
};

// A render's inputs read and checked: bad input is an InputError before anything is drawn.
struct RenderPlan {
  io::Model model;                 // unless `part` is set
  std::optional<part::Part> part;  // a part manifest, or a surface model with trim loops as a part of one face
  bool alphaSweep = false;     // the sweep's values are α (else λ)
  std::vector<double> values;  // empty: one frame at the model's parameters
  int width = 0, height = 0;   // of one tile
  double az = 0.0, el = 0.0;   // the camera's direction in degrees
};
RenderPlan planRender(const RenderArgs& a);

// The plan's tiles, each of the painter's size: one per sweep value, or one (a single render, every
// value of an --overlay in one tile, or a --distance map). The caller's painter serves several plans (the demo).
std::vector<render::Image> renderTiles(const RenderArgs& a, const RenderPlan& plan, render::Painter& painter);

// Tiles of one size left to right, top to bottom, `cols` to a row; white where none is left.
render::Image composeSheet(const std::vector<render::Image>& tiles, int cols);

// Reads the model, renders it (one view, one labelled tile per --sweep value, or the values
// overlaid) and writes the PNG into `outputs` (added there, with the model as an input); the
// caller commits.
void renderModel(const RenderArgs& a, io::OutputSet& outputs);

}  // namespace shapespline::cli
