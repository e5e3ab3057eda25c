#include <shapespline/io/model_json.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <shapespline/core/huge_pages.h>
#include <shapespline/core/validate.h>
#include <shapespline/core/value_scan.h>
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/named_file.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/raw_records.h>

namespace shapespline::io {

namespace {

using nlohmann::json;

// Integers that any field can meaningfully hold; larger ones are rejected before conversion to int.
constexpr double kMaxInteger = 1e6;
// The largest extent of a referenced array (rows, columns or points): an int, with room.
constexpr std::uint64_t kMaxArrayExtent = std::uint64_t{1} << 30;

std::string shortDump(const json& j) { return shortValue(j); }

std::string idx(const std::string& base, size_t i) { return base + "[" + std::to_string(i) + "]"; }

[[noreturn]] void failJson(std::string field, const json& value, std::string rule) {
  throw ModelError(std::move(field), shortDump(value), std::move(rule));
}

std::optional<Construction> constructionFromName(const std::string& s) {
  if (const FamilyTraits* f = familyNamed(s)) return f->construction;
  return std::nullopt;
}

// "extended_bspline, alpha_eb, ..., bspline": every name the family table knows.
std::string constructionNames() {
  std::string names;
  for (const FamilyTraits& f : families()) names += (names.empty() ? "" : ", ") + std::string(f.name);
  return names;
}

// Span knots exist for curves only (docs/math.md §1, R3); knot vectors for curves and surfaces.
bool hasKnots(const FamilyTraits& f, bool surface) { return f.knotVectors || (!surface && f.spanKnots); }

// docs/format.md "Fields": why a key that exists is not allowed here, or empty when it is.
std::string unusedKeyRule(const std::string& key, Construction c, bool surface) {
  const FamilyTraits& f = familyOf(c);
  const std::string name(f.name);
  bool used = true;
  if (key == "degree") used = f.usesDegree;
  else if (key == "order") used = f.usesOrder;
  else if (key == "lambda") used = f.usesLambda;
  else if (key == "mu") used = f.usesMu;
  else if (key == "alpha") used = f.usesAlpha;
  else if (key == "knots") used = hasKnots(f, surface);
  else if (key == "weights") used = f.knotVectors;
  else if (key == "trim") used = f.knotVectors && surface;
  if (used) return {};
  if (key == "trim") return "trim is only allowed on bspline surfaces (a CAD face's loops), not " + name + (surface ? "" : " curves");
  if (key == "weights") return "weights are only allowed for bspline (a rational B-spline), not " + name;
  if (key == "alpha") return "alpha is only allowed for alpha_eb, not " + name;
  if (key == "knots" && surface && f.spanKnots)
    return "span knots are only allowed for extended_bspline/gb curves, not surfaces";
  return key + " is not used by construction " + name;
}

double getNumber(const json& j, const std::string& field) {
  if (!j.is_number()) failJson(field, j, "must be a number");
  const double v = j.get<double>();
  // nlohmann cannot read NaN/inf from text, but a json built in code can hold them.
  if (!std::isfinite(v)) throw ModelError(field, shortDump(j), "must be a finite number");
  return v;
}

// docs/format.md: integers must be JSON integers; 5.0 is tolerated, 4.5 and "5" are not.
int getInteger(const json& j, const std::string& field) {
  double v = 0.0;
  if (j.is_number_unsigned()) {
    v = static_cast<double>(j.get<std::uint64_t>());
  } else if (j.is_number_integer()) {
    v = static_cast<double>(j.get<std::int64_t>());
  } else if (j.is_number_float()) {
    v = j.get<double>();
    if (!std::isfinite(v) || v != std::floor(v)) failJson(field, j, "must be an integer");
  } else {
    failJson(field, j, "must be an integer (a JSON number, not a string or other type)");
  }
  if (std::abs(v) > kMaxInteger) failJson(field, j, "integer out of range");
  return static_cast<int>(v);
}

bool getBool(const json& j, const std::string& field) {
  if (!j.is_boolean()) failJson(field, j, "must be true or false");
  return j.get<bool>();
}

std::vector<double> getNumberArray(const json& j, const std::string& field, const std::string& what) {
  if (!j.is_array()) failJson(field, j, "must be an array of " + what);
  std::vector<double> out;
  out.reserve(j.size());
  for (size_t i = 0; i < j.size(); ++i) out.push_back(getNumber(j[i], idx(field, i)));
  return out;
}

// A point [x, y] or [x, y, z] with the allowed sizes; returns its size.
size_t readPoint(const json& p, const std::string& field, bool surface, glm::dvec3& out) {
  const bool ok = p.is_array() && (p.size() == 3 || (!surface && p.size() == 2));
  if (!ok) failJson(field, p, surface ? "a surface point is [x, y, z]" : "a point is [x, y] or [x, y, z]");
  out = glm::dvec3(0.0);
  for (size_t c = 0; c < p.size(); ++c) out[static_cast<int>(c)] = getNumber(p[c], idx(field, c));
  return p.size();
}

// ---- Array references: "points": {"npy": "net.npy"} or, given in memory, {"array": "points"} ------

bool isArrayReference(const json& v) { return v.is_object(); }

// The file an array reference names, by the named-file rule (io/named_file.h).
std::filesystem::path referencedFile(const json& ref, const std::string& key, const ModelArrays* files) {
  if (ref.size() != 1 || !ref.contains("npy") || !ref.at("npy").is_string())
    failJson(key, ref, "an array reference is {\"npy\": \"FILE.npy\"}, a file name relative to the model file");
  const std::string name = ref.at("npy").get<std::string>();
  if (!files)
    throw ModelError(key, shortText(name), "array files are read only for a model file (the name is relative to its folder)");
  NamedFileRule rule;
  rule.folder = files->folder;
  rule.allowOutside = files->allowOutside;
  rule.allowHint = "allow arrays elsewhere with --allow-outside-arrays";
  return resolveNamedFile(rule, name, key);
}

// The array a reference names (given in memory or read from its file) and, for messages, its name.
NpyArray takeArray(const json& ref, const std::string& key, ModelArrays* arrays, std::string& name, NpyLayout layout) {
  if (ref.size() == 1 && ref.contains("array") && arrays) {
    const auto it = arrays->given.find(key);
    if (ref.at("array") == key && it != arrays->given.end()) {
      name = "NumPy array";
      NpyArray a = std::move(it->second);
      arrays->given.erase(it);
      return a;
    }
  }
  const std::filesystem::path file = referencedFile(ref, key, arrays);
  name = shortText(ref.at("npy").get<std::string>());
  try {
    if (arrays->onFile) arrays->onFile(file);
    NpyArray a = readNpyArray(file, arrays->maxValueBytes, layout);
    arrays->files.push_back(file);
    return a;
  } catch (const std::invalid_argument& e) {
    throw ModelError(key, name, e.what());
  } catch (const std::runtime_error& e) {
    throw ModelError(key, name, e.what());
  }
}

// An array's shape is one of `shapes` (0 = any extent) and no extent is over kMaxArrayExtent.
void checkArrayShape(const std::vector<std::uint64_t>& shape, const std::string& key, const std::string& name,
                     const std::vector<std::vector<std::uint64_t>>& shapes, const std::string& shapeRule) {
  auto fits = [&](const std::vector<std::uint64_t>& want) {
    if (want.size() != shape.size()) return false;
    for (size_t d = 0; d < want.size(); ++d)
      if (want[d] != 0 && want[d] != shape[d]) return false;
    return true;
  };
  if (std::none_of(shapes.begin(), shapes.end(), fits)) {
    std::string got = "(";
    for (size_t d = 0; d < shape.size(); ++d) got += (d ? ", " : "") + std::to_string(shape[d]);
    throw ModelError(key, name + " of shape " + got + (shape.size() == 1 ? ",)" : ")"), shapeRule);
  }
  for (std::uint64_t d : shape)
    if (d > kMaxArrayExtent) throw ModelError(key, name, "an extent of " + std::to_string(d) + " is over " + std::to_string(kMaxArrayExtent));
}

// The array a reference names, its shape one of `shapes` (0 = any extent) and every value finite.
NpyArray referencedArray(const json& ref, const std::string& key, ModelArrays* arrays,
                         const std::vector<std::vector<std::uint64_t>>& shapes, const std::string& shapeRule,
                         NpyLayout layout = NpyLayout::Values) {
  std::string name;
  NpyArray a = takeArray(ref, key, arrays, name, layout);
  checkArrayShape(a.shape, key, name, shapes, shapeRule);
  requireFiniteArrayValues(key, name, a.shape, a.data(), a.size(), 0);
  return a;
}

// Outline (ModelArrays::outline): the file a reference names, its header read and checked like
// referencedArray's, its values left unread.
void deferArray(const json& ref, const std::string& key, ModelArrays* arrays,
                const std::vector<std::vector<std::uint64_t>>& shapes, const std::string& shapeRule) {
  DeferredArray d;
  d.key = key;
  d.file = referencedFile(ref, key, arrays);
  d.name = shortText(ref.at("npy").get<std::string>());
  try {
    if (arrays->onFile) arrays->onFile(d.file);
    d.header = NpyReader(d.file, arrays->maxValueBytes).header();
  } catch (const std::invalid_argument& e) {
    throw ModelError(key, d.name, e.what());
  } catch (const std::runtime_error& e) {
    throw ModelError(key, d.name, e.what());
  }
  arrays->files.push_back(d.file);
  checkArrayShape(d.header.shape, key, d.name, shapes, shapeRule);
  arrays->deferred.push_back(std::move(d));
}

// Outline: a reference to a file (not an array given in memory) in a parse that defers them.
bool deferred(const json& ref, const ModelArrays* arrays) {
  return arrays && arrays->outline && isArrayReference(ref) && !ref.contains("array");
}

void readCommon(const json& doc, FamilySpec& f, bool surface) {
  const Construction c = f.construction;
  const FamilyTraits& traits = familyOf(c);
  if (traits.usesDegree) f.degree = getInteger(doc.at("degree"), "degree");
  if (traits.usesLambda && doc.contains("lambda")) f.lambda = getNumber(doc.at("lambda"), "lambda");
  if (traits.usesMu) f.mu = getNumberArray(doc.at("mu"), "mu", "numbers");
  if (traits.usesOrder && !(surface && traits.twoOrders)) {
    const json& o = doc.at("order");
    if (surface && o.is_array())
      failJson("order", o, std::string(constructionName(c)) + " surfaces take one integer order for both directions");
    f.order = getInteger(o, "order");
  }
}

// Scalar alpha: checked here so that the error names "alpha", the field the file actually has.
std::optional<double> scalarAlpha(const json& a) {
  if (!a.is_number()) return std::nullopt;
  const double v = getNumber(a, "alpha");
  if (!(v > 0.0 && v <= 1.0))
    throw ModelError("alpha", shortDump(a), v == 0.0 ? "alpha must be in (0,1]: alpha = 0 makes V_j undefined" : "alpha must be in (0,1]");
  return v;
}

// A curve's points written out: [[x, y], ...] or [[x, y, z], ...], one dimension for all.
void readCurvePoints(const json& pts, CurveModel& m) {
  if (!pts.is_array()) failJson("points", pts, "must be an array of points");
  size_t dim = 0;
  m.points.resize(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    const size_t d = readPoint(pts[i], idx("points", i), false, m.points[i]);
    if (dim == 0) dim = d;
    if (d != dim)
      failJson(idx("points", i), pts[i],
               "all points must share one dimension (points[0] has " + std::to_string(dim) + " coordinates)");
  }
  m.dimension = dim == 0 ? 2 : static_cast<int>(dim);
}

// One number per point of a curve (alpha, weights) from an array reference.
std::vector<double> referencedPerPoint(const json& ref, const std::string& key, ModelArrays* files, size_t n) {
  return referencedArray(ref, key, files, {{n}},
                         key + " must be an array of one number per point, shape (" + std::to_string(n) + ",)")
      .values;
}

CurveModel readCurve(const json& doc, Construction c, ModelArrays* files) {
  CurveModel m;
  m.family.construction = c;
  readCommon(doc, m.family, false);
  if (doc.contains("closed")) m.closed = getBool(doc.at("closed"), "closed");

  const json& pts = doc.at("points");
  // Outline: only a curve whose points are a file is left unread, as a surface's net.
  const bool outline = deferred(pts, files);
  size_t n = 0;
  if (outline) {
    deferArray(pts, "points", files, {{0, 2}, {0, 3}}, "curve points must be an (n, 2) or (n, 3) array");
    n = size_t(files->deferred.back().header.shape[0]);
    m.dimension = int(files->deferred.back().header.shape[1]);
  } else if (isArrayReference(pts)) {
    NpyArray a = referencedArray(pts, "points", files, {{0, 2}, {0, 3}}, "curve points must be an (n, 2) or (n, 3) array");
    const size_t n = size_t(a.shape[0]), d = size_t(a.shape[1]);
    m.points.assign(n, glm::dvec3(0.0));
    for (size_t i = 0; i < n; ++i)
      for (size_t k = 0; k < d; ++k) m.points[i][int(k)] = a.data()[i * d + k];
    m.dimension = int(d);
  } else {
    readCurvePoints(pts, m);
  }
  if (!outline) n = m.points.size();
  const std::string perPoint = "must be an array of one number per point, shape (" + std::to_string(n) + ",)";

  if (doc.contains("alpha")) {
    const json& a = doc.at("alpha");
    if (auto v = scalarAlpha(a)) {
      if (outline) files->uniformAlpha = *v;
      else reserveHuge(m.alpha, n), m.alpha.assign(n, *v);
    } else if (outline && deferred(a, files)) {
      deferArray(a, "alpha", files, {{n}}, "alpha " + perPoint);
    } else if (isArrayReference(a)) {
      m.alpha = referencedPerPoint(a, "alpha", files, n);
    } else {
      if (!a.is_array()) failJson("alpha", a, "alpha must be a number or an array of one number per point");
      if (a.size() != n)
        throw ModelError("alpha", std::to_string(a.size()) + " values",
             "alpha array length must equal the number of points (" + std::to_string(n) + ")");
      m.alpha = getNumberArray(a, "alpha", "numbers");
    }
  }
  if (doc.contains("knots")) m.knots = getNumberArray(doc.at("knots"), "knots", "numbers");
  if (doc.contains("weights")) {
    const json& w = doc.at("weights");
    if (outline && deferred(w, files)) {
      deferArray(w, "weights", files, {{n}}, "weights " + perPoint);
    } else if (isArrayReference(w)) {
      m.weights = referencedPerPoint(w, "weights", files, n);
    } else {
      if (!w.is_array() || w.size() != n)
        throw ModelError("weights", w.is_array() ? std::to_string(w.size()) + " values" : shortDump(w),
             "weights must be an array of one number per point (" + std::to_string(n) + ")");
      m.weights = getNumberArray(w, "weights", "numbers");
    }
  }
  return m;
}

// The shape rule of a surface's per-vertex array file (alpha, weights).
std::string perVertexRule(const std::string& key, int rows, int cols) {
  return key + " must be an array of one number per point, shape (" + std::to_string(rows) + ", " +
         std::to_string(cols) + ")";
}

// One number per vertex of a surface, as rows shaped like `points` (alpha, weights), row-major.
// `what`: the rule's start ("weights must be an array").
std::vector<double> readVertexRows(const json& a, const std::string& key, const std::string& what, int rows, int cols) {
  const std::string shape = std::to_string(rows) + " x " + std::to_string(cols);
  if (!a.is_array() || a.size() != static_cast<size_t>(rows))
    throw ModelError(key, a.is_array() ? std::to_string(a.size()) + " rows" : shortDump(a),
         what + " of rows shaped like points (" + shape + ")");
  std::vector<double> out;
  for (size_t i = 0; i < a.size(); ++i) {
    if (!a[i].is_array() || a[i].size() != static_cast<size_t>(cols))
      throw ModelError(idx(key, i), a[i].is_array() ? std::to_string(a[i].size()) + " values" : shortDump(a[i]),
           "each " + key + " row must have one number per column (" + std::to_string(cols) + ")");
    const auto row = getNumberArray(a[i], idx(key, i), "numbers");
    out.insert(out.end(), row.begin(), row.end());
  }
  return out;
}

// A surface's points written out: rows of [x, y, z] points, all rows of one length.
void readSurfacePoints(const json& pts, SurfaceModel& m) {
  if (!pts.is_array()) failJson("points", pts, "must be an array of rows, each an array of [x, y, z] points");
  m.rows = static_cast<int>(pts.size());
  m.cols = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const json& row = pts[i];
    const std::string rowField = idx("points", i);
    if (!row.is_array()) failJson(rowField, row, "each row must be an array of [x, y, z] points");
    if (i == 0) m.cols = static_cast<int>(row.size());
    if (row.size() != static_cast<size_t>(m.cols))
      throw ModelError(rowField, std::to_string(row.size()) + " points",
           "all rows must have equal length (points[0] has " + std::to_string(m.cols) + ")");
    for (size_t j = 0; j < row.size(); ++j) {
      glm::dvec3 p;
      readPoint(row[j], idx(rowField, j), true, p);
      m.points.push_back(p);
    }
  }
}

// One number per vertex of a surface (alpha, weights), written out or from an array reference.
std::vector<double> readPerVertex(const json& a, const std::string& key, const std::string& what, int rows, int cols,
                                  ModelArrays* files) {
  if (!isArrayReference(a)) return readVertexRows(a, key, what, rows, cols);
  return referencedArray(a, key, files, {{std::uint64_t(rows), std::uint64_t(cols)}}, perVertexRule(key, rows, cols))
      .values;
}

// docs/format.md "Trim": {"loops": [[[u, v], ...], ...], "tolerance": t}. The rules on the values
// (at least 3 points a loop, inside the knot domain) are core validateSurface's.
TrimLoops readTrim(const json& t) {
  if (!t.is_object() || !t.contains("loops") || !t.contains("tolerance"))
    failJson("trim", t, "trim must be an object {\"loops\": [[[u, v], ...], ...], \"tolerance\": t}");
  for (const auto& [key, value] : t.items())
    if (key != "loops" && key != "tolerance") failJson("trim." + key, value, "unknown key (trim takes loops and tolerance)");
  TrimLoops out;
  out.tolerance = getNumber(t.at("tolerance"), "trim.tolerance");
  const json& loops = t.at("loops");
  if (!loops.is_array() || loops.empty()) failJson("trim.loops", loops, "must be a non-empty array of loops");
  for (size_t l = 0; l < loops.size(); ++l) {
    const std::string field = idx("trim.loops", l);
    if (!loops[l].is_array()) failJson(field, loops[l], "a trim loop must be an array of [u, v] points");
    std::vector<glm::dvec2>& loop = out.loops.emplace_back();
    loop.reserve(loops[l].size());
    for (size_t p = 0; p < loops[l].size(); ++p) {
      const json& q = loops[l][p];
      if (!q.is_array() || q.size() != 2) failJson(idx(field, p), q, "a trim point must be [u, v]");
      loop.emplace_back(getNumber(q[0], idx(idx(field, p), 0)), getNumber(q[1], idx(idx(field, p), 1)));
    }
  }
  return out;
}

json trimJson(const TrimLoops& t) {
  json loops = json::array();
  for (const auto& loop : t.loops) {
    json l = json::array();
    for (const glm::dvec2& q : loop) l.push_back({q.x, q.y});
    loops.push_back(std::move(l));
  }
  return {{"loops", std::move(loops)}, {"tolerance", t.tolerance}};
}

SurfaceModel readSurface(const json& doc, Construction c, ModelArrays* files) {
  SurfaceModel m;
  m.family.construction = c;
  readCommon(doc, m.family, true);
  if (familyOf(c).twoOrders) {
    const json& o = doc.at("order");
    if (o.is_array()) {
      if (o.size() != 2) failJson("order", o, "a bspline surface order is [k, l] (u order, v order)");
      m.family.order = getInteger(o[0], "order[0]");
      m.orderV = getInteger(o[1], "order[1]");
    } else {
      // A single integer is read as the same order in both directions.
      m.family.order = m.orderV = getInteger(o, "order");
    }
  } else {
    m.orderV = m.family.order;
  }
  if (doc.contains("closed")) {
    const json& cl = doc.at("closed");
    if (!cl.is_array() || cl.size() != 2) failJson("closed", cl, "a surface takes closed = [closed_u, closed_v]");
    m.closedU = getBool(cl[0], "closed[0]");
    m.closedV = getBool(cl[1], "closed[1]");
  }

  const json& pts = doc.at("points");
  // Outline: only a net whose points are a file is left unread (written out, it is in memory anyway).
  const bool outline = deferred(pts, files);
  if (outline) {
    deferArray(pts, "points", files, {{0, 0, 3}}, "surface points must be a (rows, cols, 3) array");
    m.rows = int(files->deferred.back().header.shape[0]);
    m.cols = int(files->deferred.back().header.shape[1]);
  } else if (isArrayReference(pts)) {
    NpyArray a = referencedArray(pts, "points", files, {{0, 0, 3}}, "surface points must be a (rows, cols, 3) array",
                                 NpyLayout::Points);
    m.rows = int(a.shape[0]);
    m.cols = int(a.shape[1]);
    if (!a.points.empty()) {
      m.points = std::move(a.points);  // read as points, with room for the patch net
    } else {
      resizeHuge(m.points, a.size() / 3);
      std::copy(a.data(), a.data() + a.size(), &m.points.data()->x);
    }
  } else {
    readSurfacePoints(pts, m);
  }

  if (doc.contains("alpha")) {
    const json& a = doc.at("alpha");
    if (auto v = scalarAlpha(a)) {
      if (outline) files->uniformAlpha = *v;
      else reserveHuge(m.alpha, m.points.size()), m.alpha.assign(m.points.size(), *v);
    } else if (outline && deferred(a, files)) {
      deferArray(a, "alpha", files, {{std::uint64_t(m.rows), std::uint64_t(m.cols)}},
                 perVertexRule("alpha", m.rows, m.cols));
    } else {
      m.alpha = readPerVertex(a, "alpha", "alpha must be a number or an array", m.rows, m.cols, files);
    }
  }
  if (doc.contains("knots")) {
    const json& k = doc.at("knots");
    if (!k.is_array() || k.size() != 2 || !k[0].is_array() || !k[1].is_array())
      failJson("knots", k, "a bspline surface takes knots = [U, V], two arrays of numbers");
    m.knotsU = getNumberArray(k[0], "knots[0]", "numbers");
    m.knotsV = getNumberArray(k[1], "knots[1]", "numbers");
  }
  if (doc.contains("weights")) {
    const json& w = doc.at("weights");
    if (outline && deferred(w, files))
      deferArray(w, "weights", files, {{std::uint64_t(m.rows), std::uint64_t(m.cols)}},
                 perVertexRule("weights", m.rows, m.cols));
    else
      m.weights = readPerVertex(w, "weights", "weights must be an array", m.rows, m.cols, files);
  }
  if (doc.contains("trim")) m.trim = readTrim(doc.at("trim"));
  return m;
}


}  // namespace

void requireFiniteArrayValues(const std::string& key, const std::string& name, const std::vector<std::uint64_t>& shape,
                              const double* values, size_t count, std::uint64_t first) {
  const size_t k = firstNonFinite(values, count);
  if (k == count) return;
  std::vector<std::uint64_t> index(shape.size());
  for (size_t d = shape.size(), rest = first + k; d-- > 0; rest /= shape[d]) index[d] = rest % shape[d];
  std::string at;
  for (std::uint64_t i : index) at.append(1, '[').append(std::to_string(i)).append(1, ']');
  throw ModelError(key + at, name, "must be a finite number (the array holds " + std::to_string(values[k]) + ")");
}

SurfaceCounts outlineCounts(const SurfaceModel& m, const ModelArrays& arrays) {
  SurfaceCounts counts{m.points.size(), m.alpha.size(), m.weights.size()};
  for (const DeferredArray& a : arrays.deferred) {
    const size_t values = size_t(a.header.count);
    if (a.key == "points") counts.points = values / 3;
    if (a.key == "alpha") counts.alpha = values;
    if (a.key == "weights") counts.weights = values;
  }
  if (arrays.uniformAlpha) counts.alpha = counts.points;
  return counts;
}

SurfaceCounts outlineCounts(const CurveModel& m, const ModelArrays& arrays) {
  SurfaceCounts counts{m.points.size(), m.alpha.size(), m.weights.size()};
  for (const DeferredArray& a : arrays.deferred) {
    if (a.key == "points") counts.points = size_t(a.header.shape[0]);
    if (a.key == "alpha") counts.alpha = size_t(a.header.count);
    if (a.key == "weights") counts.weights = size_t(a.header.count);
  }
  if (arrays.uniformAlpha) counts.alpha = counts.points;
  return counts;
}

Model parseModel(const json& doc, ModelArrays* arrays) {
  if (!doc.is_object()) failJson("(document)", doc, "a model must be a JSON object");

  static const std::array<const char*, 14> kKnownKeys = {"kind",  "construction", "degree", "order",
                                                         "lambda", "mu",          "closed", "points",
                                                         "alpha", "knots",        "weights", "trim",
                                                         "name",  "comment"};
  for (const auto& [key, value] : doc.items()) {
    bool known = false;
    for (const char* k : kKnownKeys) known = known || key == k;
    if (!known) failJson(key, value, "unknown key (docs/format.md lists the allowed keys)");
  }
  for (const char* k : {"name", "comment"})
    if (doc.contains(k) && !doc.at(k).is_string()) failJson(k, doc.at(k), "must be a string");

  if (!doc.contains("kind")) throw ModelError("kind", "(missing)", "kind is required: \"curve\" or \"surface\"");
  const json& kindJ = doc.at("kind");
  if (!kindJ.is_string() || (kindJ != "curve" && kindJ != "surface"))
    failJson("kind", kindJ, "kind must be \"curve\" or \"surface\"");
  const bool surface = kindJ == "surface";

  if (!doc.contains("construction"))
    throw ModelError("construction", "(missing)", "construction is required: one of " + constructionNames());
  const json& consJ = doc.at("construction");
  const auto cons = consJ.is_string() ? constructionFromName(consJ.get<std::string>()) : std::nullopt;
  if (!cons)
    failJson("construction", consJ, "construction must be one of " + constructionNames());
  const Construction c = *cons;

  for (const auto& [key, value] : doc.items())
    if (auto rule = unusedKeyRule(key, c, surface); !rule.empty()) failJson(key, value, rule);

  const std::string cname(constructionName(c));
  auto require = [&](const char* key, bool needed) {
    if (needed && !doc.contains(key)) throw ModelError(key, "(missing)", std::string(key) + " is required for " + cname);
  };
  const FamilyTraits& traits = familyOf(c);
  require("degree", traits.usesDegree);
  require("order", traits.usesOrder);
  require("mu", traits.usesMu);
  require("alpha", traits.usesAlpha);
  require("points", true);

  if (surface) {
    SurfaceModel m = readSurface(doc, c, arrays);
    if (arrays && !arrays->deferred.empty()) {
      validateSurfaceShape(m, outlineCounts(m, *arrays));
    } else {
      validateSurface(m);
    }
    return m;
  }
  CurveModel m = readCurve(doc, c, arrays);
  if (arrays && !arrays->deferred.empty()) {
    validateCurveShape(m, outlineCounts(m, *arrays));
  } else {
    validateCurve(m);
  }
  return m;
}

Model parseModelText(std::string_view text, ModelArrays* arrays) {
  return parseModel(parseJsonText(text, "(document)"), arrays);
}

Model loadModelFile(const std::filesystem::path& path, bool allowOutside, std::uint64_t maxValueBytes) {
  ModelArrays arrays;
  arrays.folder = path.parent_path();
  arrays.allowOutside = allowOutside;
  arrays.maxValueBytes = maxValueBytes;
  return parseModelText(readInputFile(path, "(file)"), &arrays);
}

json toJson(const CurveModel& m) {
  const FamilySpec& f = m.family;
  const FamilyTraits& traits = familyOf(f.construction);
  json j;
  j["kind"] = "curve";
  j["construction"] = std::string(traits.name);
  if (traits.usesDegree) j["degree"] = f.degree;
  if (traits.usesOrder) j["order"] = f.order;
  if (traits.usesLambda) j["lambda"] = f.lambda;
  if (traits.usesMu) j["mu"] = f.mu;
  j["closed"] = m.closed;
  json pts = json::array();
  for (const auto& p : m.points)
    pts.push_back(m.dimension == 2 ? json::array({p.x, p.y}) : json::array({p.x, p.y, p.z}));
  j["points"] = std::move(pts);
  if (traits.usesAlpha) j["alpha"] = m.alpha;
  if (!m.knots.empty()) j["knots"] = m.knots;
  if (!m.weights.empty()) j["weights"] = m.weights;
  return j;
}

json toJson(const SurfaceModel& m) {
  const FamilySpec& f = m.family;
  const FamilyTraits& traits = familyOf(f.construction);
  json j;
  j["kind"] = "surface";
  j["construction"] = std::string(traits.name);
  if (traits.usesDegree) j["degree"] = f.degree;
  if (traits.twoOrders) j["order"] = json::array({f.order, m.orderV});
  else if (traits.usesOrder) j["order"] = f.order;
  if (traits.usesLambda) j["lambda"] = f.lambda;
  if (traits.usesMu) j["mu"] = f.mu;
  j["closed"] = json::array({m.closedU, m.closedV});
  json pts = json::array();
  for (int i = 0; i < m.rows; ++i) {
    json row = json::array();
    for (int c = 0; c < m.cols; ++c) {
      const auto& p = m.at(i, c);
      row.push_back(json::array({p.x, p.y, p.z}));
    }
    pts.push_back(std::move(row));
  }
  j["points"] = std::move(pts);
  if (traits.usesAlpha && m.alpha.size() != m.points.size()) {
    j["alpha"] = m.alpha;  // not a valid model; write what is there rather than index past it
  } else if (traits.usesAlpha) {
    json a = json::array();
    for (int i = 0; i < m.rows; ++i) {
      json row = json::array();
      for (int c = 0; c < m.cols; ++c) row.push_back(m.alpha[static_cast<size_t>(i) * m.cols + c]);
      a.push_back(std::move(row));
    }
    j["alpha"] = std::move(a);
  }
  if (!m.knotsU.empty() || !m.knotsV.empty()) j["knots"] = json::array({m.knotsU, m.knotsV});
  if (m.weights.size() == m.points.size() && !m.weights.empty()) {
    json w = json::array();
    for (int i = 0; i < m.rows; ++i)
      w.push_back(std::vector<double>(m.weights.begin() + static_cast<std::ptrdiff_t>(i) * m.cols,
                                      m.weights.begin() + static_cast<std::ptrdiff_t>(i + 1) * m.cols));
    j["weights"] = std::move(w);
  } else if (!m.weights.empty()) {
    j["weights"] = m.weights;  // not a valid model; write what is there
  }
  if (!m.trim.empty()) j["trim"] = trimJson(m.trim);
  return j;
}

json toJson(const Model& model) {
  return std::visit([](const auto& m) { return toJson(m); }, model);
}

namespace {

// STEM.KEY.npy beside `path`, added to `outputs`, holding `values` as a float64 array of `shape`;
// returns the reference the model file gives ({"npy": "STEM.KEY.npy"}).
json saveArray(const std::filesystem::path& path, const char* key, const double* values, const std::vector<uint64_t>& shape,
               OutputSet& outputs, const std::string& option) {
  const std::string name = path.stem().string() + "." + key + ".npy";
  AtomicFile& f = outputs.add(path.parent_path() / name, option);
  f.write(npyArrayHeader(shape));
  uint64_t count = 1;
  for (uint64_t d : shape) count *= d;
  f.write(values, count * sizeof(double));
  return {{"npy", name}};
}

// The per-vertex values as one number when they are all the same (α), else as an array file.
json saveVertexValues(const std::filesystem::path& path, const char* key, const std::vector<double>& values,
                      const std::vector<uint64_t>& shape, bool oneNumberIfSame, OutputSet& outputs,
                      const std::string& option) {
  if (oneNumberIfSame && std::all_of(values.begin(), values.end(), [&](double v) { return v == values.front(); }))
    return values.front();
  return saveArray(path, key, values.data(), shape, outputs, option);
}

}  // namespace

void saveModelWithArrays(const CurveModel& m, const std::filesystem::path& path, OutputSet& outputs,
                         const std::string& option) {
  AtomicFile& file = outputs.add(path, option);
  // toJson's keys from a copy without the arrays, which go to files.
  CurveModel head;
  head.family = m.family;
  head.closed = m.closed;
  head.dimension = m.dimension;
  head.knots = m.knots;
  json doc = toJson(head);
  const uint64_t n = m.points.size(), dim = static_cast<uint64_t>(m.dimension);
  std::vector<double> xy;  // 2-D curves keep (N, 2), as in their JSON form
  xy.reserve(n * dim);
  for (const auto& p : m.points)
    for (uint64_t a = 0; a < dim; ++a) xy.push_back(p[static_cast<int>(a)]);
  doc["points"] = saveArray(path, "points", xy.data(), {n, dim}, outputs, option);
  if (!m.alpha.empty()) doc["alpha"] = saveVertexValues(path, "alpha", m.alpha, {n}, true, outputs, option);
  if (!m.weights.empty()) doc["weights"] = saveVertexValues(path, "weights", m.weights, {n}, false, outputs, option);
  file.write(doc.dump(1) + "\n");
}

void saveModelWithArrays(const SurfaceModel& m, const std::filesystem::path& path, OutputSet& outputs,
                         const std::string& option) {
  AtomicFile& file = outputs.add(path, option);
  SurfaceModel head;
  head.family = m.family;
  head.orderV = m.orderV;
  head.closedU = m.closedU;
  head.closedV = m.closedV;
  head.knotsU = m.knotsU;
  head.knotsV = m.knotsV;
  head.trim = m.trim;
  json doc = toJson(head);
  const uint64_t rows = static_cast<uint64_t>(m.rows), cols = static_cast<uint64_t>(m.cols);
  static_assert(sizeof(glm::dvec3) == 3 * sizeof(double));
  doc["points"] = saveArray(path, "points", &m.points.data()->x, {rows, cols, 3}, outputs, option);
  if (!m.alpha.empty()) doc["alpha"] = saveVertexValues(path, "alpha", m.alpha, {rows, cols}, true, outputs, option);
  if (!m.weights.empty())
    doc["weights"] = saveVertexValues(path, "weights", m.weights, {rows, cols}, false, outputs, option);
  file.write(doc.dump(1) + "\n");
}

}  // namespace shapespline::io
