#pragma once
// Small SVG plots: curves in 2-D projection (x, y; equal aspect, y up) with their control polygon
// and data points, and function plots (basis functions and derivatives, free aspect, axes, legend).
#include <shapespline/io/atomic_file.h>

#include <glm/vec2.hpp>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace shapespline::io {

// A number of the plot is not finite (exit 3 at the command line; nothing is written).
class SvgValueError : public std::range_error {
 public:
  using std::range_error::range_error;
};

struct SvgPolyline {
  std::vector<glm::dvec2> points;
  std::string color = "#1f5fbf";
  double width = 2.0;      // in pixels
  bool closed = false;
  bool dashed = false;
  std::string label;       // legend entry (function plots); empty: none
};

struct SvgMarkers {
  std::vector<glm::dvec2> points;
  std::string color = "#d62728";
  double radius = 4.0;     // in pixels
  bool filled = true;
  std::string label;
};

class SvgPlot {
 public:
  // equalAspect: one unit is the same length in x and y (geometry); otherwise fill the frame.
  explicit SvgPlot(bool equalAspect, std::string title = {}) : equal_(equalAspect), title_(std::move(title)) {}
  void add(SvgPolyline line) { lines_.push_back(std::move(line)); }
  void add(SvgMarkers markers) { markers_.push_back(std::move(markers)); }
  // Draw x/y axes with the data range printed at the ends (function plots).
  void setAxes(bool axes) { axes_ = axes; }
  // Text for a <metadata> element right after the <svg> tag (`sample`: the job metadata as JSON,
  // io/job_metadata.h); XML-escaped when written. Empty (the default): no element.
  void setMetadata(std::string text) { metadata_ = std::move(text); }
  // Throws SvgValueError if a coordinate or label would not be finite (a non-finite input point).
  std::string render(int widthPx = 800, int heightPx = 600) const;
  // render() into `out`; an SvgValueError becomes OutputWriteError(out.option(), out.target(), ...).
  void write(AtomicFile& out) const;

 private:
  bool equal_ = true, axes_ = false;
  std::string title_, metadata_;
  std::vector<SvgPolyline> lines_;
  std::vector<SvgMarkers> markers_;
};

// A colour of a fixed qualitative palette (basis function r gets colour r).
const char* paletteColor(int index);

}  // namespace shapespline::io
