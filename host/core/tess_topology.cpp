#include <shapespline/core/tess_topology.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <unordered_set>

namespace shapespline {
namespace {

void checkSize(const std::vector<int>& v, size_t expected, bool allowScalar, const char* field) {
  if (v.size() == expected || (allowScalar && v.size() == 1)) return;
  throw std::invalid_argument(std::string("TessRates.") + field + ": expected " + std::to_string(expected) +
                              (allowScalar ? " values or 1" : " values") + ", got " + std::to_string(v.size()));
}

void checkRates(const std::vector<int>& v, const char* field) {
  for (size_t k = 0; k < v.size(); ++k)
    if (v[k] < 1 || v[k] > 4096)
      throw std::invalid_argument(std::string("TessRates.") + field + "[" + std::to_string(k) + "] = " +
                                  std::to_string(v[k]) + ": a rate must lie in [1, 4096]");
}

struct RingPoint {
  uint32_t index;
  double t;         // parameter along the side
  double u, v;      // local patch coordinates (orientation test)
};

void emit(std::vector<uint32_t>& out, const RingPoint& p, const RingPoint& q, const RingPoint& r) {
  const double area = (q.u - p.u) * (r.v - p.v) - (q.v - p.v) * (r.u - p.u);
  out.push_back(p.index);
  if (area >= 0.0) {
    out.push_back(q.index);
    out.push_back(r.index);
  } else {
    out.push_back(r.index);
    out.push_back(q.index);
  }
}

// Stitches the outer polyline (edge, corners included) to the inner one (outermost interior row):
// advance the side whose next point comes first in parameter, the inner side on ties.
void zipper(const std::vector<RingPoint>& outer, const std::vector<RingPoint>& inner, std::vector<uint32_t>& out) {
  size_t k = 0, i = 0;
  while (k + 1 < outer.size() || i + 1 < inner.size()) {
    const bool advanceOuter =
        i + 1 >= inner.size() || (k + 1 < outer.size() && outer[k + 1].t < inner[i + 1].t);
    if (advanceOuter) {
      emit(out, outer[k], outer[k + 1], inner[i]);
      ++k;
    } else {
      emit(out, outer[k], inner[i + 1], inner[i]);
      ++i;
    }
  }
}

}  // namespace

TessRates TessRates::uniform(int patchesU, int patchesV, bool closedU, bool closedV, int rate) {
  TessRates r;
  r.patchesU = patchesU;
  r.patchesV = patchesV;
  r.closedU = closedU;
  r.closedV = closedV;
  r.rateU = {rate};
  r.rateV = {rate};
  return r;
}

TessTopology buildTessTopology(const TessRates& in) {
  if (in.patchesU < 1 || in.patchesV < 1)
    throw std::invalid_argument("TessRates: patch grid " + std::to_string(in.patchesU) + " x " +
                                std::to_string(in.patchesV) + " must have at least one patch per direction");
  const int PU = in.patchesU, PV = in.patchesV;
  const size_t patches = size_t(PU) * PV;
  checkSize(in.rateU, patches, true, "rateU");
  checkSize(in.rateV, patches, true, "rateV");
  checkRates(in.rateU, "rateU");
  checkRates(in.rateV, "rateV");
  TessTopology t;
  t.rates = in;
  TessRates& r = t.rates;
  const int BU = r.boundariesU(), BV = r.boundariesV();
  // Resolve the edge rates: the max of the neighbours' rates along the edge.
  if (r.edgeU.empty()) {
    r.edgeU.resize(size_t(PU) * BV);
    for (int a = 0; a < PU; ++a)
      for (int b = 0; b < BV; ++b) {
        int e = 0;
        if (b < PV) e = std::max(e, r.patchRateU(a, b));
        if (b > 0 || r.closedV) e = std::max(e, r.patchRateU(a, (b + PV - 1) % PV));
        r.edgeU[size_t(a) * BV + b] = e;
      }
  }
  if (r.edgeV.empty()) {
    r.edgeV.resize(size_t(BU) * PV);
    for (int a = 0; a < BU; ++a)
      for (int b = 0; b < PV; ++b) {
        int e = 0;
        if (a < PU) e = std::max(e, r.patchRateV(a, b));
        if (a > 0 || r.closedU) e = std::max(e, r.patchRateV((a + PU - 1) % PU, b));
        r.edgeV[size_t(a) * PV + b] = e;
      }
  }
  checkSize(r.edgeU, size_t(PU) * BV, false, "edgeU");
  checkSize(r.edgeV, size_t(BU) * PV, false, "edgeV");
  checkRates(r.edgeU, "edgeU");
  checkRates(r.edgeV, "edgeV");

  // ---- Vertices: corners, edge interiors, patch interiors (canonical samples) --------------------
  std::vector<TessSample>& S = t.samples;
  struct Extra {
    uint32_t vertex;
    TessSample s;
  };
  std::vector<Extra> extras;
  auto owner = [](int boundary, int patches, int& patch, double& local) {
    patch = std::min(boundary, patches - 1);
    local = boundary == patch ? 0.0 : 1.0;
  };
  // Corners.
  for (int ca = 0; ca < BU; ++ca)
    for (int cb = 0; cb < BV; ++cb) {
      TessSample s;
      owner(ca, PU, s.a, s.u);
      owner(cb, PV, s.b, s.v);
      const uint32_t k = uint32_t(S.size());
      S.push_back(s);
      // Every other patch with this corner: patches (ca-1|ca) x (cb-1|cb), wrapped.
      for (int da = -1; da <= 0; ++da)
        for (int db = -1; db <= 0; ++db) {
          int a = ca + da, b = cb + db;
          if (r.closedU) a = (a + PU) % PU;
          if (r.closedV) b = (b + PV) % PV;
          if (a < 0 || a >= PU || b < 0 || b >= PV) continue;
          const double u = (a == ca % PU && (ca < PU)) ? 0.0 : 1.0;
          const double v = (b == cb % PV && (cb < PV)) ? 0.0 : 1.0;
          if (a == s.a && b == s.b && u == s.u && v == s.v) continue;
          extras.push_back({k, {a, b, u, v}});
        }
    }
  t.cornerCount = uint32_t(S.size());
  auto cornerIndex = [&](int ca, int cb) { return uint32_t((ca % BU) * BV + (cb % BV)); };
  // Edges along u (at v-boundary b of column a), then along v.
  std::vector<uint32_t> edgeUFirst(r.edgeU.size()), edgeVFirst(r.edgeV.size());
  for (int a = 0; a < PU; ++a)
    for (int b = 0; b < BV; ++b) {
      const int e = r.edgeU[size_t(a) * BV + b];
      edgeUFirst[size_t(a) * BV + b] = uint32_t(S.size());
      int pb;
      double v;
      owner(b, PV, pb, v);
      const bool shared = b > 0 && b < PV ? true : r.closedV;
      for (int k = 1; k < e; ++k) {
        const double u = double(k) / double(e);
        const uint32_t idx = uint32_t(S.size());
        S.push_back({a, pb, u, v});
        if (shared) extras.push_back({idx, {a, (b + PV - 1) % PV, u, 1.0}});
      }
    }
  for (int a = 0; a < BU; ++a)
    for (int b = 0; b < PV; ++b) {
      const int e = r.edgeV[size_t(a) * PV + b];
      edgeVFirst[size_t(a) * PV + b] = uint32_t(S.size());
      int pa;
      double u;
      owner(a, PU, pa, u);
      const bool shared = a > 0 && a < PU ? true : r.closedU;
      for (int k = 1; k < e; ++k) {
        const double v = double(k) / double(e);
        const uint32_t idx = uint32_t(S.size());
        S.push_back({pa, b, u, v});
        if (shared) extras.push_back({idx, {(a + PU - 1) % PU, b, 1.0, v}});
      }
    }
  t.edgeVertexCount = uint32_t(S.size()) - t.cornerCount;
  // Interiors.
  std::vector<uint32_t>& interiorFirst = t.interiorFirst;
  interiorFirst.resize(patches);
  for (int a = 0; a < PU; ++a)
    for (int b = 0; b < PV; ++b) {
      const int n = std::max(r.patchRateU(a, b), 2), m = std::max(r.patchRateV(a, b), 2);
      interiorFirst[size_t(a) * PV + b] = uint32_t(S.size());
      for (int i = 1; i < n; ++i)
        for (int j = 1; j < m; ++j) S.push_back({a, b, double(i) / n, double(j) / m});
    }
  t.vertexCount = uint32_t(S.size());
  if (S.size() + extras.size() >= 0xffffffffu) throw std::length_error("tessellation exceeds 2^32 vertices");
  t.extraFirst.assign(t.vertexCount, 0);
  t.extraCount.assign(t.vertexCount, 0);
  std::stable_sort(extras.begin(), extras.end(), [](const Extra& x, const Extra& y) { return x.vertex < y.vertex; });
  for (const Extra& x : extras) {
    if (t.extraCount[x.vertex] == 0) t.extraFirst[x.vertex] = uint32_t(S.size());
    ++t.extraCount[x.vertex];
    S.push_back(x.s);
  }

  // ---- Triangles per patch ----------------------------------------------------------------------
  t.firstIndex.resize(patches);
  t.indexCount.resize(patches);
  t.sides.resize(patches * 4);
  for (int a = 0; a < PU; ++a)
    for (int b = 0; b < PV; ++b) {
      const size_t p = size_t(a) * PV + b;
      const int n = std::max(r.patchRateU(a, b), 2), m = std::max(r.patchRateV(a, b), 2);
      const uint32_t in0 = interiorFirst[p];
      auto interior = [&](int i, int j) { return in0 + uint32_t((i - 1) * (m - 1) + (j - 1)); };
      t.firstIndex[p] = uint32_t(t.indices.size());
      // Outer polylines, increasing parameter.
      std::vector<RingPoint> outer[4], inner[4];
      for (int s = 0; s < 4; ++s) {
        const bool alongU = s == 0 || s == 2;
        const double fixed = (s == 1 || s == 2) ? 1.0 : 0.0;
        int e;
        uint32_t first, c0, c1;
        if (alongU) {
          const int bb = b + (s == 2 ? 1 : 0);
          e = r.edgeU[size_t(a) * BV + (bb % BV)];
          first = edgeUFirst[size_t(a) * BV + (bb % BV)];
          c0 = cornerIndex(a, bb);
          c1 = cornerIndex(a + 1, bb);
        } else {
          const int aa = a + (s == 1 ? 1 : 0);
          e = r.edgeV[size_t(aa % BU) * PV + b];
          first = edgeVFirst[size_t(aa % BU) * PV + b];
          c0 = cornerIndex(aa, b);
          c1 = cornerIndex(aa, b + 1);
        }
        auto at = [&](uint32_t idx, double tt) {
          return alongU ? RingPoint{idx, tt, tt, fixed} : RingPoint{idx, tt, fixed, tt};
        };
        outer[s].push_back(at(c0, 0.0));
        for (int k = 1; k < e; ++k) outer[s].push_back(at(first + uint32_t(k - 1), double(k) / e));
        outer[s].push_back(at(c1, 1.0));
        std::vector<uint32_t>& sideList = t.sides[p * 4 + s];
        for (const RingPoint& q : outer[s]) sideList.push_back(q.index);
        // Inner polyline: the outermost interior row/column on this side.
        if (alongU) {
          const int j = s == 0 ? 1 : m - 1;
          for (int i = 1; i < n; ++i)
            inner[s].push_back({interior(i, j), double(i) / n, double(i) / n, double(j) / m});
        } else {
          const int i = s == 3 ? 1 : n - 1;
          for (int j = 1; j < m; ++j)
            inner[s].push_back({interior(i, j), double(j) / m, double(i) / n, double(j) / m});
        }
        zipper(outer[s], inner[s], t.indices);
      }
      // Interior quads.
      for (int i = 1; i + 1 < n; ++i)
        for (int j = 1; j + 1 < m; ++j) {
          const uint32_t q00 = interior(i, j), q10 = interior(i + 1, j), q01 = interior(i, j + 1),
                         q11 = interior(i + 1, j + 1);
          t.indices.insert(t.indices.end(), {q00, q10, q11, q00, q11, q01});
        }
      t.indexCount[p] = uint32_t(t.indices.size()) - t.firstIndex[p];
    }
  return t;
}

std::vector<uint32_t> triangleEdges(const std::vector<uint32_t>& triangles) {
  std::unordered_set<uint64_t> seen;
  seen.reserve(triangles.size());
  std::vector<uint32_t> out;
  out.reserve(triangles.size());
  for (size_t t = 0; t + 2 < triangles.size(); t += 3)
    for (int e = 0; e < 3; ++e) {
      uint32_t x = triangles[t + e], y = triangles[t + (e + 1) % 3];
      if (x > y) std::swap(x, y);
      if (seen.insert((uint64_t(x) << 32) | y).second) out.insert(out.end(), {x, y});
    }
  return out;
}

}  // namespace shapespline
