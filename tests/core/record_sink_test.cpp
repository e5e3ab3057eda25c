// Records straight from the CPU sampler (SamplerOptions::records, core/point_records.h): the
// workers' row encoder gives, bit for bit, what encoding the planes of a plain run gives, for every
// path (plain tensor rows, α-EB with normals, knot-vector B-splines, curves), for fp32 and fp64
// records, for 1 to 7 fields, with items cut into row ranges and several blocks per slice; a row
// larger than a block falls back to slices; a block with a value beyond the records' range is
// handed to the slice consumer with its planes, so the caller can report the value.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <random>
#include <string>
#include <vector>

#include <shapespline/core/grid_sampler.h>

#include "support/test_models.h"
#include <shapespline/core/point_records.h>

namespace shapespline {
namespace {

std::vector<Field> fieldsOf(FieldMask mask) {
  std::vector<Field> fields;
  for (int f = 0; f < kFieldCount; ++f)
    if (mask & fieldBit(static_cast<Field>(f))) fields.push_back(static_cast<Field>(f));
  return fields;
}

// A job's records in memory, placed by point index as the raw writer places them in its file.
struct RecordFile {
  std::vector<Field> fields;
  bool float64;
  size_t firstItem, pointsPerItem, bytesPerRecord;
  std::vector<char> bytes;
  std::mutex mutex;
  std::vector<std::vector<char>> blocks;
  std::vector<size_t> freeBlocks;
  size_t slices = 0, sinkBlocks = 0, chunksWithPlanes = 0;

  RecordFile(FieldMask mask, bool f64, size_t first, size_t items, size_t ppi)
      : fields(fieldsOf(mask)), float64(f64), firstItem(first), pointsPerItem(ppi),
        bytesPerRecord(recordBytes(fields.size(), f64)), bytes(items * ppi * bytesPerRecord, char(0x5a)) {}

  char* at(const GridChunk& c, size_t first) {
    return bytes.data() + ((c.firstItem - firstItem) * pointsPerItem + c.firstItemPoint() + first) * bytesPerRecord;
  }
  SliceConsumer slice() {
    return [this](const GridChunk& c, size_t first, size_t count) {
      {
        std::lock_guard lock(mutex);
        ++slices;
      }
      encodeRecords(at(c, first), c, fields, float64, first, count);
    };
  }
  ChunkConsumer consumer() {
    return [this](const GridChunk& c) {
      for (const void* p : c.planes)
        if (p) {
          ++chunksWithPlanes;
          break;
        }
    };
  }
  RecordSink sink(size_t maxPoints) {
    RecordSink s;
    s.fields = fields;
    s.float64 = float64;
    s.maxPoints = maxPoints;
    s.acquire = [this, maxPoints] {
      std::lock_guard lock(mutex);
      ++sinkBlocks;
      if (freeBlocks.empty()) {
        blocks.emplace_back(maxPoints * bytesPerRecord + 64);
        freeBlocks.push_back(blocks.size() - 1);
      }
      const size_t k = freeBlocks.back();
      freeBlocks.pop_back();
      return RecordBlock{blocks[k].data(), k};
    };
    s.submit = [this](RecordBlock b, const GridChunk& c, size_t first, size_t count) {
      std::memcpy(at(c, first), b.data, count * bytesPerRecord);
      std::lock_guard lock(mutex);
      freeBlocks.push_back(b.token);
    };
    return s;
  }
};

struct Options {
  int threads;
  size_t chunkPoints, blockPoints;
};

// The records of a planes run (encoded per slice) and of a sink run must be the same bytes.
template <class Sample>
void expectSameRecords(Sample sample, FieldMask fields, size_t firstItem, size_t items, size_t ppi, Options o,
                       bool sinkUsed, const std::string& what) {
  for (bool f64 : {false, true}) {
    RecordFile planes(fields, f64, firstItem, items, ppi), sunk(fields, f64, firstItem, items, ppi);
    SamplerOptions a{o.threads, o.chunkPoints};
    a.slice = planes.slice();
    sample(a, planes.consumer());
    SamplerOptions b{o.threads, o.chunkPoints};
    b.slice = sunk.slice();
    b.records = sunk.sink(o.blockPoints);
    sample(b, sunk.consumer());
    const std::string label = what + (f64 ? " fp64" : " fp32");
    ASSERT_EQ(planes.bytes.size(), sunk.bytes.size()) << label;
    EXPECT_EQ(0, std::memcmp(planes.bytes.data(), sunk.bytes.data(), planes.bytes.size())) << label;
    if (sinkUsed) {
      EXPECT_GT(sunk.sinkBlocks, 0u) << label;
      EXPECT_EQ(sunk.slices, 0u) << label << ": every value is in range, no slice is due";
      EXPECT_EQ(sunk.chunksWithPlanes, 0u) << label << ": chunks of sunk points carry no planes";
    } else {
      EXPECT_EQ(sunk.sinkBlocks, 0u) << label << ": a row larger than a block goes through slices";
      EXPECT_GT(sunk.slices, 0u) << label;
    }
  }
}

void checkSurface(const Surface& s, const GridSpec& grid, FieldMask fields, Options o, bool sinkUsed,
                  const std::string& what) {
  const size_t items = grid.itemCount ? grid.itemCount : surfaceGridItems(s).size() - grid.firstItem;
  expectSameRecords([&](const SamplerOptions& opt, const ChunkConsumer& c) { sampleSurfaceGrid(s, grid, fields, c, opt); },
                    fields, grid.firstItem, items, grid.pointsPerItem(), o, sinkUsed, what);
}

TEST(RecordSink, PlainSurfaceRowsEveryFieldCount) {
  const Surface s = Surface::create(test::wavyNet({Construction::ExtendedBSpline, 4, 0, 0.0, {}}, 7, false));
  const FieldMask masks[] = {fieldBit(Field::Point), fieldBit(Field::Point) | fieldBit(Field::Dv),
                             fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dv),
                             fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dv) | fieldBit(Field::Duu) |
                                 fieldBit(Field::Duv) | fieldBit(Field::Dvv)};
  for (FieldMask m : masks) {
    const std::string what = "plain, fields " + std::to_string(m);
    // Rows of 4k+1..4k+3 points exercise the vector steps and the scalar tail.
    checkSurface(s, {9, 13, 0, 0}, m, {2, 1000, 1000}, true, what + ", 9x13");
    checkSurface(s, {6, 6, 0, 0}, m, {1, 64, 64}, true, what + ", 6x6");
    checkSurface(s, {5, 2, 0, 0}, m, {2, 64, 64}, true, what + ", 5x2");
    // Patches cut into row ranges, several blocks per slice, a shard's item range.
    checkSurface(s, {40, 23, 3, 5}, m, {3, 333, 50}, true, what + ", 40x23 in row ranges");
  }
}

TEST(RecordSink, AlphaEBSurfaceWithNormalsAndKnotVectorSurface) {
  const Surface a = Surface::create(test::wavyNet({Construction::AlphaEB, 5, 0, -2.0, {}}, 7, true));
  checkSurface(a, {11, 9, 0, 0}, kSurfaceFields, {2, 200, 40}, true, "alpha-EB all fields");
  checkSurface(a, {11, 9, 0, 0}, fieldBit(Field::Point) | fieldBit(Field::Normal), {2, 200, 40}, true,
               "alpha-EB point+normal");
  SurfaceModel m = test::wavyNet({Construction::BSpline, 0, 4, 0.0, {}}, 5, false);
  m.knotsU = m.knotsV = {0, 0, 0, 0, 0.4, 1, 1, 1, 1};
  const Surface k = Surface::create(std::move(m));
  checkSurface(k, {7, 6, 0, 0}, kSurfaceFields, {2, 100, 30}, true, "knot-vector");
}

TEST(RecordSink, Curves) {
  struct Case {
    FamilySpec family;
    bool knots;
  };
  for (const Case& c : {Case{{Construction::ExtendedBSpline, 5, 0, -3.0, {}}, false},
                        Case{{Construction::AlphaEB, 5, 0, 0.5, {}}, false}, Case{{Construction::GB, 0, 0, 7.0, {}}, true}}) {
    CurveModel m;
    m.family = c.family;
    m.dimension = 3;
    for (int i = 0; i < 9; ++i) m.points.push_back({double(i), std::sin(1.3 * i), 0.2 * i});
    if (c.family.construction == Construction::AlphaEB) m.alpha.assign(9, 0.6);
    if (c.knots) m.knots = {0, 0.5, 2, 2.25, 4, 4.5, 7};
    const Curve curve = Curve::create(std::move(m));
    const size_t items = curveGridItems(curve).size();
    const std::string what(constructionName(c.family.construction));
    for (FieldMask mask : {fieldBit(Field::Point), kCurveFields}) {
      expectSameRecords(
          [&](const SamplerOptions& o, const ChunkConsumer& k) { sampleCurveGrid(curve, {301, 1, 0, 0}, mask, k, o); },
          mask, 0, items, 301, {2, 100, 37}, true, what);
    }
  }
}

TEST(RecordSink, ARowLargerThanABlockGoesThroughSlices) {
  const Surface s = Surface::create(test::wavyNet({Construction::ExtendedBSpline, 4, 0, 0.0, {}}, 5, false));
  checkSurface(s, {5, 40, 0, 0}, fieldBit(Field::Point) | fieldBit(Field::Du), {2, 100, 39}, false, "row of 40, block of 39");
}

TEST(RecordSink, ABlockWithAValueBeyondFp32GoesToTheSliceWithItsPlanes) {
  // A net of coordinates up to 4e39: beyond fp32, well within fp64.
  const Surface s = Surface::create(test::wavyNet({Construction::ExtendedBSpline, 4, 0, 0.0, {}}, 5, false, 1e39));
  const FieldMask fields = fieldBit(Field::Point) | fieldBit(Field::Duu);
  const size_t items = surfaceGridItems(s).size();
  RecordFile file(fields, false, 0, items, 36);
  size_t slices = 0;
  bool sawBeyond = false;
  SamplerOptions o{2, 100};
  o.records = file.sink(20);
  o.slice = [&](const GridChunk& c, size_t first, size_t count) {
    ++slices;  // one worker: no race
    ASSERT_TRUE(c.has(Field::Point) && c.has(Field::Duu));
    for (Field f : {Field::Point, Field::Duu})
      for (size_t p = first; p < first + count; ++p)
        for (int a = 0; a < 3; ++a) sawBeyond |= std::abs(c.coord(f, p, a)) > std::numeric_limits<float>::max();
  };
  o.threads = 1;
  sampleSurfaceGrid(s, {6, 6, 0, 0}, fields, file.consumer(), o);
  EXPECT_GT(slices, 0u);
  EXPECT_TRUE(sawBeyond) << "the slice's planes hold the value the records could not";
  // In fp64 records every value fits: no slice.
  RecordFile f64(fields, true, 0, items, 36);
  SamplerOptions d{2, 100};
  d.records = f64.sink(20);
  d.slice = f64.slice();
  sampleSurfaceGrid(s, {6, 6, 0, 0}, fields, f64.consumer(), d);
  EXPECT_EQ(f64.slices, 0u);
}

TEST(RecordSink, RefusesFieldsOtherThanTheSampledOnesAndAMissingSlice) {
  const Surface s = Surface::create(test::wavyNet({Construction::ExtendedBSpline, 4, 0, 0.0, {}}, 5, false));
  RecordFile file(fieldBit(Field::Point), false, 0, 4, 9);
  SamplerOptions o;
  o.records = file.sink(10);
  o.slice = file.slice();
  const FieldMask two = fieldBit(Field::Point) | fieldBit(Field::Du);
  EXPECT_THROW(sampleSurfaceGrid(s, {3, 3, 0, 0}, two, file.consumer(), o), std::invalid_argument);
  o.slice = {};
  EXPECT_THROW(sampleSurfaceGrid(s, {3, 3, 0, 0}, fieldBit(Field::Point), file.consumer(), o), std::invalid_argument);
}

// The row encoder against the value encoding, value by value, with values beyond each range at
// every position of a row (vector steps and tail).
TEST(RecordSink, RowEncoderIsTheValueEncodingAndChecksEveryValue) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-1e3, 1e3);
  const double fltMax = std::numeric_limits<float>::max();
  for (size_t nf = 1; nf <= 7; ++nf)
    for (size_t n = 1; n <= 13; ++n)
      for (bool f64 : {false, true}) {
        std::vector<std::vector<double>> rows(3 * nf, std::vector<double>(n));
        for (auto& r : rows)
          for (double& v : r) v = d(rng) / 3.0;
        std::vector<const double*> ptrs;
        for (const auto& r : rows) ptrs.push_back(r.data());
        auto encode = [&](bool& ok) {
          std::vector<char> out(n * recordBytes(nf, f64) + 16, 0);
          ok = encodeRowRecords(out.data(), ptrs.data(), nf, f64, n);
          return out;
        };
        auto expected = [&] {
          std::vector<char> out(n * recordBytes(nf, f64) + 16, 0);
          char* e = out.data();
          for (size_t b = 0; b < n; ++b)
            for (size_t k = 0; k < 3 * nf; ++k) e = putBinaryValue(e, rows[k][b], f64);
          return out;
        };
        bool ok = false;
        EXPECT_EQ(encode(ok), expected()) << nf << " fields, " << n << " points";
        EXPECT_TRUE(ok);
        rows[0][0] = fltMax;
        EXPECT_EQ(encode(ok), expected());
        EXPECT_TRUE(ok);
        for (size_t b = 0; b < n; ++b) {
          const size_t k = (b * 5) % (3 * nf);
          const double keep = rows[k][b];
          for (double bad : {1e39, -1e39, std::nan(""), std::numeric_limits<double>::infinity()}) {
            rows[k][b] = bad;
            encode(ok);
            EXPECT_EQ(ok, f64 && std::abs(bad) < 1e300) << nf << " fields, point " << b << " of " << n << ", " << bad;
          }
          rows[k][b] = keep;
        }
      }
}

}  // namespace
}  // namespace shapespline
