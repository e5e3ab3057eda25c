#include <shapespline/core/gb_tools.h>

#include <shapespline/core/span_basis.h>
#include <shapespline/core/value_text.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace shapespline {
namespace {

double cross(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

// P_{j-1}, P_j, P_{j+1}, P_{j+2} of span j after validating the model and the span (docs/math.md §11).
struct SpanPoints {
  glm::dvec2 p[4];
};

SpanPoints spanPoints(const CurveModel& model, int span) {
  if (model.family.construction != Construction::GB)
    throw ModelError("construction", std::string(constructionName(model.family.construction)),
                     "the constrained modification needs a gb curve");
  if (model.dimension != 2)
    throw ModelError("points", std::to_string(model.dimension) + "-D", "GB modification needs 2-D data");
  const int n = static_cast<int>(model.points.size());
  const int first = model.closed ? 0 : 1;
  const int last = model.closed ? n - 1 : n - 3;
  if ((model.closed && n < 3) || (!model.closed && n < 4))
    throw ModelError("points", std::to_string(n) + " points", "too few points for a gb curve");
  if (span < first || span > last)
    throw ModelError("span", std::to_string(span),
                     "span must exist: " + std::to_string(first) + ".." + std::to_string(last));
  SpanPoints s;
  for (int r = 0; r < 4; ++r) {
    int i = span - 1 + r;
    if (model.closed) i = ((i % n) + n) % n;
    const glm::dvec3& q = model.points[static_cast<size_t>(i)];
    s.p[r] = glm::dvec2(q.x, q.y);
  }
  return s;
}

glm::dvec2 spanValue(const SpanBasis& basis, const SpanPoints& s, double t) {
  double b[kMaxBasisCount];
  evalSpanBasis(basis, t, b, nullptr, nullptr);
  return b[0] * s.p[0] + b[1] * s.p[1] + b[2] * s.p[2] + b[3] * s.p[3];
}

GbLambdaPath pathAt(const SpanBasis& cubic, const SpanPoints& s, double t) {
  GbLambdaPath path;
  path.c0 = spanValue(cubic, s, t);
  const double h = t * t * (3.0 - 2.0 * t);
  path.e = (1.0 - h) * s.p[1] + h * s.p[2];
  path.cMinus8 = 3.0 * path.c0 - 2.0 * path.e;
  return path;
}

// F(t) evaluated from the points directly (not from the expanded polynomial): this is what the
// bisection's side test means geometrically, and it has no cancellation between monomials.
double pathResidual(const SpanBasis& cubic, const SpanPoints& s, glm::dvec2 x, double t) {
  const GbLambdaPath path = pathAt(cubic, s, t);
  return cross(x - path.e, path.c0 - path.e);
}

double horner(std::span<const double> c, double t) {
  double v = 0.0;
  for (size_t d = c.size(); d-- > 0;) v = v * t + c[d];
  return v;
}

// w of docs/math.md §7.2 by projection onto the path line; NaN where the path degenerates (C_0 = E).
double projectW(const GbLambdaPath& path, glm::dvec2 x, double scale) {
  const glm::dvec2 d = path.c0 - path.e;
  const double len2 = glm::dot(d, d);
  if (!(len2 > 1e-28 * scale * scale)) return std::numeric_limits<double>::quiet_NaN();
  return glm::dot(x - path.e, d) / len2;
}

// 0 < w ≤ 3 ⇔ λ ≥ −8. The upper end admits a few ulps so that a target placed exactly on
// C(−8, t) is not lost to rounding in the projection.
bool admissible(double w) { return w > 0.0 && w <= 3.0 * (1.0 + 1e-13); }

}  // namespace

GbLambdaPath gbLambdaPath(const CurveModel& gbCurve, int span, double t) {
  return pathAt(gbSpanBasis(0.0), spanPoints(gbCurve, span), t);
}

glm::dvec2 gbSpanPoint(const CurveModel& gbCurve, int span, double lambda, double t) {
  return spanValue(gbSpanBasis(lambda), spanPoints(gbCurve, span), t);
}

std::array<double, 7> gbPathPolynomial(const CurveModel& gbCurve, int span, glm::dvec2 target) {
  const SpanPoints s = spanPoints(gbCurve, span);
  const SpanBasis cubic = gbSpanBasis(0.0);
  // C_0(t) = sum_d c0[d] t^d, E(t) = B + (3t² − 2t³)(C − B).
  glm::dvec2 c0[4] = {}, e[4] = {};
  for (int d = 0; d < 4; ++d)
    for (int r = 0; r < 4; ++r) c0[d] += cubic.coef[r][d] * s.p[r];
  const glm::dvec2 leg = s.p[2] - s.p[1];
  e[0] = s.p[1];
  e[2] = 3.0 * leg;
  e[3] = -2.0 * leg;
  glm::dvec2 g[4], dd[4];  // G = X − E, D = C_0 − E
  for (int d = 0; d < 4; ++d) {
    g[d] = -e[d];
    dd[d] = c0[d] - e[d];
  }
  g[0] += target;
  std::array<double, 7> f{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) f[static_cast<size_t>(i + j)] += g[i].x * dd[j].y - g[i].y * dd[j].x;
  return f;
}

std::vector<double> polynomialRootsInUnitInterval(std::span<const double> coef) {
  size_t size = coef.size();
  while (size > 0 && coef[size - 1] == 0.0) --size;
  if (size <= 1) return {};  // a non-zero constant has no root; zero is reported as none
  const std::span<const double> p = coef.first(size);
  std::vector<double> deriv(size - 1);
  for (size_t d = 1; d < size; ++d) deriv[d - 1] = static_cast<double>(d) * p[d];
  const std::vector<double> critical = polynomialRootsInUnitInterval(deriv);

  // Horner's rounding on [0,1] stays below a few ulps of sum |c_d|: values inside that band are
  // indistinguishable from zero.
  double mag = 0.0;
  for (double c : p) mag += std::abs(c);
  const double zeroBand = 16.0 * std::numeric_limits<double>::epsilon() * mag;

  std::vector<double> breaks;
  breaks.push_back(0.0);
  for (double c : critical)
    if (c > 0.0 && c < 1.0) breaks.push_back(c);
  breaks.push_back(1.0);

  std::vector<double> roots;
  for (size_t k = 0; k < breaks.size(); ++k)
    if (std::abs(horner(p, breaks[k])) <= zeroBand) roots.push_back(breaks[k]);
  for (size_t k = 0; k + 1 < breaks.size(); ++k) {
    double lo = breaks[k], hi = breaks[k + 1];
    double flo = horner(p, lo), fhi = horner(p, hi);
    if (std::abs(flo) <= zeroBand || std::abs(fhi) <= zeroBand) continue;  // end already a root
    if ((flo < 0.0) == (fhi < 0.0)) continue;  // monotone between breaks: no sign change, no root
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      const double fm = horner(p, mid);
      if (fm == 0.0) {
        lo = hi = mid;
        break;
      }
      if ((fm < 0.0) == (flo < 0.0)) lo = mid, flo = fm;
      else hi = mid;
    }
    roots.push_back(0.5 * (lo + hi));
  }
  std::sort(roots.begin(), roots.end());
  std::vector<double> unique;
  for (double r : roots)
    if (unique.empty() || r - unique.back() > 1e-12) unique.push_back(r);
  return unique;
}

GbFitResult gbConstrainedModify(const CurveModel& gbCurve, int span, glm::dvec2 target, double tolT) {
  const SpanPoints s = spanPoints(gbCurve, span);
  const SpanBasis cubic = gbSpanBasis(0.0);
  if (!std::isfinite(target.x) || !std::isfinite(target.y))
    throw ModelError("target", preciseText(target.x) + ", " + preciseText(target.y), "target coordinates must be finite");

  double scale = 0.0;
  for (const auto& q : s.p) scale = std::max({scale, std::abs(q.x), std::abs(q.y)});
  scale = std::max({scale, std::abs(target.x), std::abs(target.y), 1e-300});

  // Step 1: the side of the leg line on which the λ = 0 arc lies.
  const double orient = cross(s.p[2] - s.p[1], spanValue(cubic, s, 0.5) - s.p[1]);
  if (orient == 0.0)
    throw ModelError("span", std::to_string(span),
                     "degenerate span: C_0(1/2) lies on the leg line P_j P_{j+1} (sigma = 0)");
  const double sigma = orient > 0.0 ? 1.0 : -1.0;

  GbFitResult result;

  // All admissible solutions: roots of F in [0,1] with 0 < w ≤ 3. Roots from the expanded
  // polynomial are polished on the direct residual where it changes sign nearby.
  const std::array<double, 7> f = gbPathPolynomial(gbCurve, span, target);
  for (double t : polynomialRootsInUnitInterval(f)) {
    const double step = 1e-9;
    double lo = std::max(0.0, t - step), hi = std::min(1.0, t + step);
    double flo = pathResidual(cubic, s, target, lo), fhi = pathResidual(cubic, s, target, hi);
    if (flo != 0.0 && fhi != 0.0 && (flo < 0.0) != (fhi < 0.0)) {
      for (int it = 0; it < 80 && hi - lo > 0.0; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        const double fm = pathResidual(cubic, s, target, mid);
        if (fm == 0.0) {
          lo = hi = mid;
          break;
        }
        if ((fm < 0.0) == (flo < 0.0)) lo = mid, flo = fm;
        else hi = mid;
      }
      t = 0.5 * (lo + hi);
    }
    const double w = projectW(pathAt(cubic, s, t), target, scale);
    if (!admissible(w)) continue;
    result.all.push_back({t, 12.0 * (1.0 - w) / w, w});
  }

  // Step 2: reachability, X between the λ-paths of t = 0 and t = 1.
  const double g0 = sigma * pathResidual(cubic, s, target, 0.0);
  const double g1 = sigma * pathResidual(cubic, s, target, 1.0);
  if (!(g0 >= 0.0 && g1 <= 0.0)) {
    result.reachable = false;
    result.reason = "target not reachable on span " + std::to_string(span) +
                    ": it must lie between the lambda-paths of t = 0 and t = 1 (sigma*F(0) = " + preciseText(g0) +
                    " must be >= 0 and sigma*F(1) = " + preciseText(g1) + " <= 0)";
    return result;
  }

  // Step 3: bisection on the side of the path line of t* (docs/math.md §7.2, R9).
  double first = 0.0, last = 1.0, t0 = -1.0;
  for (int round = 0; round < 64 && last - first > tolT; ++round) {
    const double mid = 0.5 * (first + last);
    const double g = sigma * pathResidual(cubic, s, target, mid);
    if (g == 0.0) {
      t0 = mid;
      break;
    }
    if (g < 0.0) last = mid;
    else first = mid;
  }
  if (t0 < 0.0) t0 = 0.5 * (first + last);

  // Step 4: w by projection, λ0 = 12(1 − w)/w, admissible iff 0 < w ≤ 3.
  const double w = projectW(pathAt(cubic, s, t0), target, scale);
  result.bisection = {t0, 12.0 * (1.0 - w) / w, w};
  if (!admissible(w)) {
    result.reachable = false;
    result.reason = "target not reachable on span " + std::to_string(span) + ": the bisection gives t0 = " +
                    preciseText(t0) + " with w = " + preciseText(w) + " outside (0, 3] (lambda0 = 12(1-w)/w must be >= -8)";
    return result;
  }
  result.reachable = true;
  return result;
}

}  // namespace shapespline
