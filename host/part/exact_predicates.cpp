// Written here rather than taken from a package: Debian has no permissively licensed robust 2-D
// predicate or CDT library (CGAL's triangulations are GPL, Triangle is non-free, poly2tri is not
// packaged and not robust).
//
// Why the fallback is exact: under round-to-nearest, twoSum(a, b) returns s = fl(a + b) and the
// rounding error e = (a + b) - s, itself a double, so a + b == s + e exactly; twoProduct returns
// p = fl(a * b) and e = fma(a, b, -p), which an FMA computes with a single rounding of the exact
// a * b - p, a double, so a * b == p + e exactly. An expansion is a sum of such doubles, ordered by
// increasing magnitude and non-overlapping; sums and products of expansions built from these two
// steps lose nothing, and the sign of a non-overlapping expansion is the sign of its largest
// component. The determinants below are therefore evaluated without any rounding.
#include <shapespline/part/exact_predicates.h>

#include <cmath>

namespace shapespline::part {
namespace {

constexpr double kEpsilon = 0x1p-53;  // half an ulp of 1: the relative rounding error of one step
// Bounds on the rounding error of the filters' determinants relative to their permanents
// (Shewchuk's ccwerrboundA and iccerrboundA).
constexpr double kOrientBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;
constexpr double kIncircleBound = (10.0 + 96.0 * kEpsilon) * kEpsilon;

inline void twoSum(double a, double b, double& s, double& e) {
  s = a + b;
  const double bv = s - a;
  const double av = s - bv;
  e = (a - av) + (b - bv);
}

inline void twoDiff(double a, double b, double& s, double& e) {
  s = a - b;
  const double bv = a - s;
  const double av = s + bv;
  e = (a - av) + (bv - b);
}

inline void twoProduct(double a, double b, double& p, double& e) {
  p = a * b;
  e = std::fma(a, b, -p);
}

// h = e + f (both non-overlapping, increasing magnitude), zeros dropped; returns h's length.
// Shewchuk's FAST-EXPANSION-SUM with zero elimination; h has room for elen + flen components.
int sumExpansions(int elen, const double* e, int flen, const double* f, double* h) {
  int ei = 0, fi = 0, hi = 0;
  double q;
  double enow = e[0], fnow = f[0];
  if ((fnow > enow) == (fnow > -enow)) {
    q = enow;
    enow = ++ei < elen ? e[ei] : 0.0;
  } else {
    q = fnow;
    fnow = ++fi < flen ? f[fi] : 0.0;
  }
  double qnew, hh;
  if (ei < elen && fi < flen) {
    // Fast two-sum is exact here: the component added is no larger than q's magnitude order.
    if ((fnow > enow) == (fnow > -enow)) {
      qnew = enow + q;
      hh = q - (qnew - enow);
      enow = ++ei < elen ? e[ei] : 0.0;
    } else {
      qnew = fnow + q;
      hh = q - (qnew - fnow);
      fnow = ++fi < flen ? f[fi] : 0.0;
    }
    q = qnew;
    if (hh != 0.0) h[hi++] = hh;
    while (ei < elen && fi < flen) {
      if ((fnow > enow) == (fnow > -enow)) {
        twoSum(q, enow, qnew, hh);
        enow = ++ei < elen ? e[ei] : 0.0;
      } else {
        twoSum(q, fnow, qnew, hh);
        fnow = ++fi < flen ? f[fi] : 0.0;
      }
      q = qnew;
      if (hh != 0.0) h[hi++] = hh;
    }
  }
  while (ei < elen) {
    twoSum(q, enow, qnew, hh);
    enow = ++ei < elen ? e[ei] : 0.0;
    q = qnew;
    if (hh != 0.0) h[hi++] = hh;
  }
  while (fi < flen) {
    twoSum(q, fnow, qnew, hh);
    fnow = ++fi < flen ? f[fi] : 0.0;
    q = qnew;
    if (hh != 0.0) h[hi++] = hh;
  }
  if (q != 0.0 || hi == 0) h[hi++] = q;
  return hi;
}

// h = b * e, zeros dropped (Shewchuk's SCALE-EXPANSION); h has room for 2 * elen components.
int scaleExpansion(int elen, const double* e, double b, double* h) {
  double q, hh, product1, product0, sum;
  int hi = 0;
  twoProduct(e[0], b, q, hh);
  if (hh != 0.0) h[hi++] = hh;
  for (int i = 1; i < elen; ++i) {
    twoProduct(e[i], b, product1, product0);
    twoSum(q, product0, sum, hh);
    if (hh != 0.0) h[hi++] = hh;
    // product1 + sum cannot round: product1 is a multiple of a larger power of two than sum's size.
    q = product1 + sum;
    hh = sum - (q - product1);
    if (hh != 0.0) h[hi++] = hh;
  }
  if (q != 0.0 || hi == 0) h[hi++] = q;
  return hi;
}

// An exact value with room for kCap components.
template <int kCap>
struct Expansion {
  double c[kCap];
  int n = 0;
  double sign() const { return c[n - 1]; }
};

// out = e * f; out has room for 2 * e.n * f.n components.
template <int kOut, int kE, int kF>
void multiply(const Expansion<kE>& e, const Expansion<kF>& f, Expansion<kOut>& out) {
  static_assert(kOut >= 2 * kE * kF);
  double scaled[2 * kE];
  double tmp[kOut];
  out.n = scaleExpansion(e.n, e.c, f.c[0], out.c);
  for (int i = 1; i < f.n; ++i) {
    const int m = scaleExpansion(e.n, e.c, f.c[i], scaled);
    const int len = sumExpansions(out.n, out.c, m, scaled, tmp);
    for (int k = 0; k < len; ++k) out.c[k] = tmp[k];
    out.n = len;
  }
}

template <int kOut, int kE, int kF>
void add(const Expansion<kE>& e, const Expansion<kF>& f, Expansion<kOut>& out) {
  static_assert(kOut >= kE + kF);
  out.n = sumExpansions(e.n, e.c, f.n, f.c, out.c);
}

template <int kCap>
Expansion<kCap> negated(const Expansion<kCap>& e) {
  Expansion<kCap> r = e;
  for (int i = 0; i < r.n; ++i) r.c[i] = -r.c[i];
  return r;
}

Expansion<2> difference(double a, double b) {
  Expansion<2> r;
  double s, e;
  twoDiff(a, b, s, e);
  r.n = 0;
  if (e != 0.0) r.c[r.n++] = e;
  r.c[r.n++] = s;
  return r;
}

// x1 * y2 - y1 * x2 exactly, from two-component differences.
Expansion<16> cross(const Expansion<2>& x1, const Expansion<2>& y1, const Expansion<2>& x2, const Expansion<2>& y2) {
  Expansion<8> p, q;
  multiply(x1, y2, p);
  multiply(y1, x2, q);
  Expansion<16> r;
  add(p, negated(q), r);
  return r;
}

int signOf(double v) { return (v > 0.0) - (v < 0.0); }

int orientExact(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  const Expansion<16> det =
      cross(difference(a.x, c.x), difference(a.y, c.y), difference(b.x, c.x), difference(b.y, c.y));
  return signOf(det.sign());
}

int incircleExact(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d) {
  const Expansion<2> adx = difference(a.x, d.x), ady = difference(a.y, d.y);
  const Expansion<2> bdx = difference(b.x, d.x), bdy = difference(b.y, d.y);
  const Expansion<2> cdx = difference(c.x, d.x), cdy = difference(c.y, d.y);
  auto lift = [](const Expansion<2>& x, const Expansion<2>& y) {
    Expansion<8> xx, yy;
    multiply(x, x, xx);
    multiply(y, y, yy);
    Expansion<16> r;
    add(xx, yy, r);
    return r;
  };
  // det = |a-d|^2 (b-d)x(c-d) + |b-d|^2 (c-d)x(a-d) + |c-d|^2 (a-d)x(b-d)
  Expansion<512> ta, tb, tc;
  multiply(lift(adx, ady), cross(bdx, bdy, cdx, cdy), ta);
  multiply(lift(bdx, bdy), cross(cdx, cdy, adx, ady), tb);
  multiply(lift(cdx, cdy), cross(adx, ady, bdx, bdy), tc);
  Expansion<1024> tab;
  add(ta, tb, tab);
  Expansion<1536> det;
  add(tab, tc, det);
  return signOf(det.sign());
}

}  // namespace

int orient2d(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  const double left = (a.x - c.x) * (b.y - c.y);
  const double right = (a.y - c.y) * (b.x - c.x);
  const double det = left - right;
  // Terms of opposite signs cannot cancel: the rounded difference has the exact sign.
  if ((left > 0.0 && right <= 0.0) || (left < 0.0 && right >= 0.0) || (left == 0.0 && right == 0.0))
    return signOf(det);
  if (std::fabs(det) >= kOrientBound * (std::fabs(left) + std::fabs(right))) return signOf(det);
  return orientExact(a, b, c);
}

int incircle(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d) {
  const double adx = a.x - d.x, ady = a.y - d.y;
  const double bdx = b.x - d.x, bdy = b.y - d.y;
  const double cdx = c.x - d.x, cdy = c.y - d.y;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double alift = adx * adx + ady * ady;
  const double blift = bdx * bdx + bdy * bdy;
  const double clift = cdx * cdx + cdy * cdy;
  const double det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * alift +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * blift +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * clift;
  if (std::fabs(det) > kIncircleBound * permanent) return signOf(det);
  return incircleExact(a, b, c, d);
}

}  // namespace shapespline::part
