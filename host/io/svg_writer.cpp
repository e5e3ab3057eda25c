#include <shapespline/io/svg_writer.h>

#include <shapespline/io/job_metadata.h>
#include <shapespline/io/number_text.h>
#include <shapespline/io/sample_writer.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace shapespline::io {

const char* paletteColor(int index) {
  static const char* kPalette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                   "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  return kPalette[static_cast<unsigned>(index) % 10];
}

namespace {

std::string num(double v) {
  char buf[kMaxNumberChars];
  // Pixel coordinates: 2 decimals are plenty and keep files small.
  const double r = std::round(v * 100.0) / 100.0;
  // Every number written is checked: the pixel arithmetic below keeps finite input finite, so this
  // is reached only by a non-finite input point (SvgPlot::write reports it as an output failure).
  if (!std::isfinite(r)) throw SvgValueError("an SVG coordinate is not finite; nothing was written (got " +
                                             std::string(buf, writeNumber(buf, v)) + ")");
  return std::string(buf, writeNumber(buf, r == 0.0 ? 0.0 : r));
}

std::string escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '&') o += "&amp;";
    else o += c;
  }
  return o;
}

}  // namespace

std::string SvgPlot::render(int widthPx, int heightPx) const {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  auto grow = [&](const glm::dvec2& p) {
    x0 = std::min(x0, p.x);
    x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y);
    y1 = std::max(y1, p.y);
  };
  for (const auto& l : lines_) for (const auto& p : l.points) grow(p);
  for (const auto& m : markers_) for (const auto& p : m.points) grow(p);
  if (!(x0 <= x1)) x0 = y0 = 0.0, x1 = y1 = 1.0;
  // Pixel arithmetic on coordinates scaled by a power of two (exact) to magnitude ~1, so that
  // nets near 1e300 cannot overflow x1 - x0 and nets near 1e-300 cannot underflow it. The scale is
  // an exponent: for a subnormal extent (a curve 4e-320 wide) 2^k itself is beyond the fp64 range.
  const double mag = std::max({std::abs(x0), std::abs(x1), std::abs(y0), std::abs(y1)});
  const int k = mag > 0.0 && std::isfinite(mag) ? -std::ilogb(mag) : 0;
  x0 = std::ldexp(x0, k), x1 = std::ldexp(x1, k), y0 = std::ldexp(y0, k), y1 = std::ldexp(y1, k);
  // An extent below rounding noise (coincident points, an axis-parallel line) is widened relative
  // to the other axis or to the magnitude, never by an absolute amount that vanishes next to 1e30.
  const double noise = 1e-12 * std::ldexp(mag, k);
  double e = std::max(x1 - x0, y1 - y0);
  if (!(e > noise)) e = 1.0;  // all points coincide: a unit frame (scaled magnitude is in [1, 2))
  if (!(x1 - x0 > noise)) {
    const double c = x0 / 2 + x1 / 2;
    x0 = c - e / 2, x1 = c + e / 2;
  }
  if (!(y1 - y0 > noise)) {
    const double c = y0 / 2 + y1 / 2;
    y0 = c - e / 2, y1 = c + e / 2;
  }

  const double margin = 40.0, top = title_.empty() ? margin : margin + 20.0;
  const double legend = axes_ ? 110.0 : 0.0;
  const double w = widthPx - 2 * margin - legend, h = heightPx - margin - top;
  double sx = w / (x1 - x0), sy = h / (y1 - y0);
  if (equal_) sx = sy = std::min(sx, sy);
  const double ox = margin + (w - sx * (x1 - x0)) / 2, oy = top + (h - sy * (y1 - y0)) / 2;
  // XS/YS take scaled coordinates, X/Y model coordinates.
  auto XS = [&](double x) { return ox + (x - x0) * sx; };
  auto YS = [&](double y) { return oy + (y1 - y) * sy; };
  auto X = [&](double x) { return XS(std::ldexp(x, k)); };
  auto Y = [&](double y) { return YS(std::ldexp(y, k)); };

  std::string s = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
                  std::to_string(widthPx) + "\" height=\"" + std::to_string(heightPx) + "\" viewBox=\"0 0 " +
                  std::to_string(widthPx) + " " + std::to_string(heightPx) + "\">\n" +
                  "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  if (!metadata_.empty()) s += "<metadata id=\"shapespline-job\">" + escape(metadata_) + "</metadata>\n";
  if (!title_.empty()) {
    s += "<text x=\"" + num(widthPx / 2.0) + "\" y=\"24\" text-anchor=\"middle\" font-family=\"sans-serif\" "
         "font-size=\"16\">" + escape(title_) + "</text>\n";
  }
  if (axes_) {
    const double ax = (x0 <= 0 && 0 <= x1) ? 0.0 : x0, ay = (y0 <= 0 && 0 <= y1) ? 0.0 : y0;
    s += "<g stroke=\"#888\" stroke-width=\"1\"><line x1=\"" + num(XS(x0)) + "\" y1=\"" + num(YS(ay)) + "\" x2=\"" +
         num(XS(x1)) + "\" y2=\"" + num(YS(ay)) + "\"/><line x1=\"" + num(XS(ax)) + "\" y1=\"" + num(YS(y0)) +
         "\" x2=\"" + num(XS(ax)) + "\" y2=\"" + num(YS(y1)) + "\"/></g>\n";
    auto label = [&](double x, double y, const std::string& text, const char* anchor) {
      s += "<text x=\"" + num(x) + "\" y=\"" + num(y) + "\" text-anchor=\"" + anchor +
           "\" font-family=\"sans-serif\" font-size=\"11\" fill=\"#444\">" + escape(text) + "</text>\n";
    };
    char b[kMaxNumberChars];
    auto txt = [&](double v) {
      v = std::ldexp(v, -k);
      if (!std::isfinite(v)) throw SvgValueError("an SVG axis label is not finite; nothing was written");
      return std::string(b, std::to_chars(b, b + sizeof b, v, std::chars_format::general, 4).ptr);
    };
    label(XS(x0), YS(ay) + 14, txt(x0), "start");
    label(XS(x1), YS(ay) + 14, txt(x1), "end");
    label(XS(ax) - 4, YS(y1) + 4, txt(y1), "end");
    label(XS(ax) - 4, YS(y0) + 4, txt(y0), "end");
  }
  for (const auto& l : lines_) {
    if (l.points.empty()) continue;
    s += std::string(l.closed ? "<polygon" : "<polyline") + " fill=\"none\" stroke=\"" + l.color +
         "\" stroke-width=\"" + num(l.width) + "\" stroke-linejoin=\"round\"" +
         (l.dashed ? " stroke-dasharray=\"6 4\"" : "") + " points=\"";
    for (const auto& p : l.points) s += num(X(p.x)) + "," + num(Y(p.y)) + " ";
    s += "\"/>\n";
  }
  for (const auto& m : markers_) {
    for (const auto& p : m.points) {
      s += "<circle cx=\"" + num(X(p.x)) + "\" cy=\"" + num(Y(p.y)) + "\" r=\"" + num(m.radius) + "\" " +
           (m.filled ? "fill=\"" + m.color + "\"" : "fill=\"white\" stroke=\"" + m.color + "\" stroke-width=\"1.5\"") +
           "/>\n";
    }
  }
  if (axes_) {
    double ly = top + 10;
    for (const auto& l : lines_) {
      if (l.label.empty()) continue;
      const double lx = widthPx - legend - margin + 60;
      s += "<line x1=\"" + num(lx) + "\" y1=\"" + num(ly) + "\" x2=\"" + num(lx + 24) + "\" y2=\"" + num(ly) +
           "\" stroke=\"" + l.color + "\" stroke-width=\"" + num(l.width) + "\"" +
           (l.dashed ? " stroke-dasharray=\"6 4\"" : "") + "/><text x=\"" + num(lx + 30) + "\" y=\"" +
           num(ly + 4) + "\" font-family=\"sans-serif\" font-size=\"12\">" + escape(l.label) + "</text>\n";
      ly += 18;
    }
  }
  s += "</svg>\n";
  return s;
}

void SvgPlot::write(AtomicFile& out) const {
  std::string text;
  try {
    text = render();
  } catch (const SvgValueError& e) {
    throw OutputWriteError(out.option(), out.target().string(), e.what());
  }
  out.write(text);
}

namespace {

// The `sample` SVG: every span a polyline (x, y projection), the control polygon dashed, the data
// points as red dots. Buffers the projected points (the CLI caps SVG jobs).
class SvgSampleWriter final : public SampleWriter {
 public:
  explicit SvgSampleWriter(AtomicFile& out) : out_(out) {}
  void begin(const SampleLayout& layout) override {
    layout_ = layout;
    if (layout.surface) throw std::invalid_argument("SVG output is for curves only (2-D projection)");
  }
  void consume(const GridChunk& chunk) override {
    // One polyline per span; a span larger than a chunk arrives in several (its first sample opens it).
    const size_t n = chunk.pointCount();
    for (size_t p = 0; p < n; ++p) {
      if (chunk.pointInItem(p) == 0) spans_.emplace_back();
      spans_.back().points.emplace_back(chunk.coord(Field::Point, p, 0), chunk.coord(Field::Point, p, 1));
    }
  }
  void finish() override {
    SvgPlot plot(true, layout_.source);
    plot.setMetadata(metadataJson(layout_.metadata).dump());
    SvgPolyline poly;
    for (const auto& p : layout_.controlPoints) poly.points.emplace_back(p.x, p.y);
    poly.color = "#888888";
    poly.width = 1.0;
    poly.dashed = true;
    poly.closed = layout_.closed;
    plot.add(poly);
    SvgMarkers ctrl;
    ctrl.points = poly.points;
    ctrl.color = "#555555";
    ctrl.radius = 3.0;
    ctrl.filled = false;
    plot.add(ctrl);
    for (auto& l : spans_) plot.add(std::move(l));
    SvgMarkers data;
    for (const auto& p : layout_.dataPoints) data.points.emplace_back(p.x, p.y);
    plot.add(data);
    plot.write(out_);
  }

 private:
  AtomicFile& out_;
  SampleLayout layout_;
  std::vector<SvgPolyline> spans_;
};

}  // namespace

std::unique_ptr<SampleWriter> makeSvgWriter(AtomicFile& out) { return std::make_unique<SvgSampleWriter>(out); }

}  // namespace shapespline::io
