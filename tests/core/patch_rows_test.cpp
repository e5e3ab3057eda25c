// Surface::patchRows (issue 31, part 3): a band of patch rows is a surface of its own whose patch
// (i, j) evaluates to the same bits as patch (first + i, j) of the whole surface, every field and
// the normal rule included (α = 1 corners, closed directions), and whose grid is that slice of the
// whole grid. The GPU path samples nets too large for one device buffer in such bands; a net read
// from its file is sampled in bands built from the rows it reads alone (Surface::bandOf), which
// must be the same bands.
#include "support/tolerances.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <set>
#include <string>
#include <vector>

#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/surface.h>
#include "support/test_models.h"

namespace shapespline::test {
namespace {


void expectSamePoint(const SurfacePoint& a, const SurfacePoint& b, const std::string& what) {
  EXPECT_TRUE(sameBits(a.point, b.point)) << what << " point";
  EXPECT_TRUE(sameBits(a.du, b.du) && sameBits(a.dv, b.dv)) << what << " first partials";
  EXPECT_TRUE(sameBits(a.duu, b.duu) && sameBits(a.duv, b.duv) && sameBits(a.dvv, b.dvv)) << what << " second partials";
  EXPECT_TRUE(sameBits(a.normal, b.normal)) << what << " normal";
  EXPECT_EQ(a.normalRule, b.normalRule) << what;
}

std::vector<double> grid(const Surface& s, size_t first, size_t count) {
  GridSpec g;
  g.samplesU = 3;
  g.samplesV = 4;
  g.firstItem = first;
  g.itemCount = count;
  std::vector<double> out;
  const FieldMask all = fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dv) | fieldBit(Field::Duu) |
                        fieldBit(Field::Duv) | fieldBit(Field::Dvv) | fieldBit(Field::Normal);
  sampleSurfaceGrid(s, g, all, [&](const GridChunk& c) {
    for (size_t p = 0; p < c.pointCount(); ++p)
      for (Field f : {Field::Point, Field::Du, Field::Dv, Field::Duu, Field::Duv, Field::Dvv, Field::Normal})
        for (int a = 0; a < 3; ++a) out.push_back(c.coord(f, p, a));
  });
  return out;
}

void expectBandsEvaluateAsTheWhole(const Surface& whole, const std::string& name) {
  const PatchRange r = whole.patches();
  const size_t itemsV = static_cast<size_t>(r.v.last - r.v.first + 1);
  const double params[] = {0.0, 0.25, 0.5, 1.0};
  for (int first = r.u.first; first <= r.u.last; ++first) {
    for (int last : {first, std::min(first + 2, r.u.last), r.u.last}) {
      const Surface band = whole.patchRows(first, last);
      const std::string what = name + " rows " + std::to_string(first) + ".." + std::to_string(last);
      ASSERT_EQ(band.patches().u.first, 0) << what;
      ASSERT_EQ(band.patches().u.last, last - first) << what;
      ASSERT_EQ(band.patches().v.first, r.v.first) << what;
      for (int i = 0; i <= last - first; ++i)
        for (int j = r.v.first; j <= r.v.last; ++j)
          for (double u : params)
            for (double v : params)
              expectSamePoint(band.evaluate(i, j, u, v), whole.evaluate(first + i, j, u, v),
                              what + " patch " + std::to_string(i) + "," + std::to_string(j));
      const size_t firstItem = static_cast<size_t>(first - r.u.first) * itemsV;
      const size_t count = static_cast<size_t>(last - first + 1) * itemsV;
      EXPECT_EQ(grid(band, 0, 0), grid(whole, firstItem, count)) << what << ": the grid is the slice";
    }
  }
}

// bandOf from the model's rows (and only those bandPointRows names) against patchRows of the whole:
// the same net, α, layout and therefore the same bits everywhere.
void expectBandsFromRowsAreThePatchRows(const SurfaceModel& model, const std::string& name) {
  const Surface whole = Surface::create(model);
  const PatchRange r = whole.patches();
  const size_t cols = static_cast<size_t>(model.cols);
  for (int first = r.u.first; first <= r.u.last; ++first) {
    for (int last : {first, std::min(first + 2, r.u.last), r.u.last}) {
      const std::string what = name + " rows " + std::to_string(first) + ".." + std::to_string(last);
      const std::vector<int> rows = Surface::bandPointRows(model, first, last);
      ASSERT_TRUE(std::is_sorted(rows.begin(), rows.end())) << what;
      std::vector<int> read;
      const Surface band = Surface::bandOf(
          model, first, last,
          [&](int k) {
            read.push_back(k);
            return &model.points[static_cast<size_t>(k) * cols];
          },
          [&](int k) { return &model.alpha[static_cast<size_t>(k) * cols]; });
      for (int k : read) EXPECT_TRUE(std::binary_search(rows.begin(), rows.end(), k)) << what << ": read row " << k;
      EXPECT_EQ(std::set<int>(read.begin(), read.end()), std::set<int>(rows.begin(), rows.end())) << what;
      const Surface expected = whole.patchRows(first, last);
      ASSERT_EQ(band.patchNet().size(), expected.patchNet().size()) << what;
      EXPECT_EQ(std::memcmp(band.patchNet().data(), expected.patchNet().data(),
                            band.patchNet().size() * sizeof(glm::dvec3)),
                0)
          << what << ": the net's bits";
      EXPECT_EQ(band.alphas(), expected.alphas()) << what;
      EXPECT_EQ(band.netRows(), expected.netRows()) << what;
      EXPECT_EQ(band.netCols(), expected.netCols()) << what;
      EXPECT_EQ(band.netOffsetU(), expected.netOffsetU()) << what;
      EXPECT_EQ(band.netOffsetV(), expected.netOffsetV()) << what;
      EXPECT_EQ(band.model().rows, expected.model().rows) << what;
      EXPECT_EQ(grid(band, 0, 0), grid(expected, 0, 0)) << what << ": the grid";
    }
  }
}

TEST(PatchRows, BandsFromTheirRowsAreThePatchRowsOfTheWhole) {
  SurfaceModel open = wavyNet(FamilySpec{Construction::AlphaEB, 5, 0, -1.5, {}}, 6, true);
  open.alpha[2 * 6 + 3] = open.alpha[4 * 6 + 1] = open.alpha[0] = 1.0;
  expectBandsFromRowsAreThePatchRows(open, "open alpha_eb");
  SurfaceModel closedU = open;
  closedU.closedU = true;
  expectBandsFromRowsAreThePatchRows(closedU, "alpha_eb closed in u");
  expectBandsFromRowsAreThePatchRows(alphaEBTube(5, 6), "alpha_eb tube (closed in v)");
  SurfaceModel xu = wavyNet(FamilySpec{Construction::ExtendedBSpline, 5, 0, 0.5, {}}, 7, false);
  expectBandsFromRowsAreThePatchRows(xu, "open xu-wang");
  xu.closedU = true;
  xu.closedV = true;
  expectBandsFromRowsAreThePatchRows(xu, "closed xu-wang");
  expectBandsFromRowsAreThePatchRows(wavyNet(FamilySpec{Construction::UBP, 0, 5, 0.25, {}}, 8, false),
                                     "open ubp order 5");
}

// A band checks the V rule (§4.2) for the vertices it holds, naming the whole net's vertex as
// create() does; a band without the bad vertex is built.
TEST(PatchRows, BandFromRowsRefusesAVertexBeyondFp64AsCreateDoes) {
  SurfaceModel m = wavyNet(FamilySpec{Construction::AlphaEB, 5, 0, 0.0, {}}, 7, true);
  m.alpha.assign(m.alpha.size(), 0.5);
  m.alpha[4 * 7 + 3] = 1e-310;  // (1-α)/α overflows: only this vertex's V leaves fp64
  std::string expected;
  try {
    (void)Surface::create(m);
  } catch (const ModelError& e) {
    expected = e.field();
  }
  ASSERT_EQ(expected, "alpha[4][3]");
  auto band = [&](int first, int last) {
    return Surface::bandOf(
        m, first, last, [&](int k) { return &m.points[static_cast<size_t>(k) * 7]; },
        [&](int k) { return &m.alpha[static_cast<size_t>(k) * 7]; });
  };
  EXPECT_NO_THROW((void)band(0, 2));  // vertex rows 0..3
  for (int first : {3, 4}) {
    try {
      (void)band(first, 4);
      ADD_FAILURE() << "band " << first << "..4 accepted a V beyond fp64";
    } catch (const ModelError& e) {
      EXPECT_EQ(e.field(), expected);
    }
  }
  EXPECT_THROW((void)band(0, 6), std::invalid_argument);  // patch rows are 0..5
}

TEST(PatchRows, AlphaEBBandsEvaluateAsTheWhole) {
  SurfaceModel open = wavyNet(FamilySpec{Construction::AlphaEB, 5, 0, -1.5, {}}, 6, true);
  open.alpha[2 * 6 + 3] = open.alpha[4 * 6 + 1] = open.alpha[0] = 1.0;  // corner-limit normals
  expectBandsEvaluateAsTheWhole(Surface::create(open), "open alpha_eb");
  SurfaceModel closedU = open;
  closedU.closedU = true;
  expectBandsEvaluateAsTheWhole(Surface::create(closedU), "alpha_eb closed in u");
  expectBandsEvaluateAsTheWhole(Surface::create(alphaEBTube(5, 6)), "alpha_eb tube (closed in v)");
}

TEST(PatchRows, UniformSpanFamiliesBandsEvaluateAsTheWhole) {
  SurfaceModel xu = wavyNet(FamilySpec{Construction::ExtendedBSpline, 5, 0, 0.5, {}}, 7, false);
  expectBandsEvaluateAsTheWhole(Surface::create(xu), "open xu-wang");
  xu.closedU = true;
  xu.closedV = true;
  expectBandsEvaluateAsTheWhole(Surface::create(xu), "closed xu-wang");
  SurfaceModel ubp = wavyNet(FamilySpec{Construction::UBP, 0, 5, 0.25, {}}, 8, false);
  expectBandsEvaluateAsTheWhole(Surface::create(ubp), "open ubp order 5");
}

TEST(PatchRows, RefusesRowsOutsideAndKnotVectors) {
  const Surface s = Surface::create(wavyNet(FamilySpec{Construction::ExtendedBSpline, 4, 0, 0.0, {}}, 6, false));
  EXPECT_THROW((void)s.patchRows(s.patches().u.first - 1, s.patches().u.first), std::invalid_argument);
  EXPECT_THROW((void)s.patchRows(s.patches().u.first, s.patches().u.last + 1), std::invalid_argument);
  EXPECT_THROW((void)s.patchRows(s.patches().u.last, s.patches().u.first), std::invalid_argument);
  const Surface torus = Surface::create(nurbsTorus(3.0, 1.0));
  EXPECT_THROW((void)torus.patchRows(torus.patches().u.first, torus.patches().u.first), std::invalid_argument);
}

}  // namespace
}  // namespace shapespline::test
