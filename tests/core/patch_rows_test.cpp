// Surface::patchRows (issue 31, part 3): a band of patch rows is a surface of its own whose patch
// (i, j) evaluates to the same bits as patch (first + i, j) of the whole surface, every field and
// the normal rule included (α = 1 corners, closed directions), and whose grid is that slice of the
// whole grid. The GPU path samples nets too large for one device buffer in such bands.
#include "support/tolerances.h"

#include <gtest/gtest.h>

#include <cstring>
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
