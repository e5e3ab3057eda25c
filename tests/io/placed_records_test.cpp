// The raw and .npy writers take their records from the sampler's workers (SampleWriter::writeSlice,
// through makeSampleWriter's checking wrapper, which once dropped the call so that every record was
// converted on the consumer's thread), convert them bit for bit as a cast does (the AVX2 fp64 ->
// fp32 path four points a step and its scalar tail), and tell whether each value is within the
// file precision's finite range (the check `sample` then skips).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "support/temp_files.h"

#include <shapespline/io/atomic_file.h>
#include <shapespline/io/sample_writer.h>

namespace shapespline::io {
namespace {

namespace fs = std::filesystem;

fs::path tempFile(const std::string& name) { return test::processTempFile("placed", name); }

// One 5 x 7 patch (35 points: eight 4-point steps and a tail) with the point, du and dv planes.
struct PlacedJob {
  SampleLayout layout;
  std::vector<double> planes[3];
  std::vector<float> planesF[3];
  GridChunk chunk(Precision p) const {
    GridChunk c;
    c.itemCount = 1;
    c.pointsPerItem = 35;
    c.pointsPerRow = 7;
    c.precision = p;
    const Field f[3] = {Field::Point, Field::Du, Field::Dv};
    for (int k = 0; k < 3; ++k)
      c.planes[static_cast<size_t>(f[k])] = p == Precision::Double ? static_cast<const void*>(planes[k].data())
                                                                    : static_cast<const void*>(planesF[k].data());
    return c;
  }
};

PlacedJob makeJob() {
  PlacedJob j;
  SampleLayout& l = j.layout;
  l.surface = true;
  l.dimension = 3;
  l.samplesU = 5;
  l.samplesV = 7;
  l.itemCount = l.totalItems = 1;
  l.itemsV = 1;
  l.spanU = {0};
  l.spanV = {0};
  l.paramU = {{0.0, 1.0}};
  l.paramV = {{0.0, 1.0}};
  l.fields = fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dv);
  l.source = "test";
  for (int k = 0; k < 3; ++k)
    for (int v = 0; v < 105; ++v) {
      // Values that round differently in fp32 (thirds, large and tiny magnitudes, signs).
      const double x = (v % 2 ? -1.0 : 1.0) * (v + 1) / 3.0 * std::pow(10.0, (v * 7 + k) % 13 - 6);
      j.planes[k].push_back(x);
      j.planesF[k].push_back(static_cast<float>(x));
    }
  return j;
}

// Writes the job as two slices, the later one first, then consume() and finish(); returns what
// each writeSlice answered.
std::vector<bool> writeSliced(OutputFormat format, const PlacedJob& job, const GridChunk& chunk, const fs::path& file) {
  AtomicFile out(file, "-o");
  AtomicFile sidecar(fs::path(file.string() + ".json"), "-o");
  const auto writer = makeSampleWriter(format, out, &sidecar);
  writer->begin(job.layout);
  std::vector<bool> answers;
  answers.push_back(writer->writeSlice(chunk, 13, 22));
  answers.push_back(writer->writeSlice(chunk, 0, 13));
  writer->consume(chunk);
  writer->finish();
  out.commit();
  sidecar.commit();
  return answers;
}

template <class T>
void expectRecords(const std::vector<char>& bytes, size_t offset, const PlacedJob& job) {
  ASSERT_EQ(bytes.size(), offset + 35 * 9 * sizeof(T));
  for (size_t p = 0; p < 35; ++p)
    for (int f = 0; f < 3; ++f)
      for (int c = 0; c < 3; ++c) {
        T got;
        std::memcpy(&got, bytes.data() + offset + ((p * 3 + f) * 3 + c) * sizeof(T), sizeof(T));
        const T want = static_cast<T>(job.planes[f][p * 3 + c]);
        EXPECT_EQ(std::memcmp(&got, &want, sizeof(T)), 0) << "point " << p << " field " << f << " axis " << c;
      }
}

TEST(PlacedRecords, RawAndNpyWritersTakeSlicesAndConvertAsACastDoes) {
  const PlacedJob job = makeJob();
  const fs::path f32 = tempFile("a.f32"), f64 = tempFile("a.f64"), npy = tempFile("a.npy");
  EXPECT_EQ(writeSliced(OutputFormat::RawF32, job, job.chunk(Precision::Double), f32), std::vector<bool>({true, true}));
  expectRecords<float>(test::readBytes(f32), 0, job);
  // fp32 planes (GPU chunks) into fp32 records.
  EXPECT_EQ(writeSliced(OutputFormat::RawF32, job, job.chunk(Precision::Float), f32), std::vector<bool>({true, true}));
  expectRecords<float>(test::readBytes(f32), 0, job);
  EXPECT_EQ(writeSliced(OutputFormat::RawF64, job, job.chunk(Precision::Double), f64), std::vector<bool>({true, true}));
  expectRecords<double>(test::readBytes(f64), 0, job);
  PlacedJob floatJob = job;
  floatJob.layout.precision = Precision::Float;
  EXPECT_EQ(writeSliced(OutputFormat::Npy, floatJob, job.chunk(Precision::Double), npy), std::vector<bool>({true, true}));
  const std::vector<char> bytes = test::readBytes(npy);
  ASSERT_GT(bytes.size(), 128u);
  const size_t header = bytes.size() - 35 * 9 * 4;
  EXPECT_EQ(header % 64, 0u);
  expectRecords<float>(bytes, header, job);
  for (const auto& p : {f32, f64, npy}) {
    fs::remove(p);
    fs::remove(p.string() + ".json");
  }
}

TEST(PlacedRecords, ASliceTellsWhetherEveryValueFitsTheFilePrecision) {
  const double fltMax = std::numeric_limits<float>::max();
  struct Case {
    OutputFormat format;
    Precision planes;
    size_t point;  // in the first slice [0, 13) (vector steps), or the tail of the second
    double value;
    bool fits;
  };
  const Case cases[] = {
      {OutputFormat::RawF32, Precision::Double, 2, fltMax, true},
      {OutputFormat::RawF32, Precision::Double, 2, 1e39, false},
      {OutputFormat::RawF32, Precision::Double, 34, -1e39, false},  // the scalar tail
      {OutputFormat::RawF32, Precision::Double, 5, std::nan(""), false},
      {OutputFormat::RawF64, Precision::Double, 2, 1e300, true},
      {OutputFormat::RawF64, Precision::Double, 9, std::numeric_limits<double>::infinity(), false},
      {OutputFormat::RawF32, Precision::Float, 3, fltMax, true},
      {OutputFormat::RawF32, Precision::Float, 2, std::numeric_limits<double>::infinity(), false},
      {OutputFormat::RawF32, Precision::Float, 34, std::nan(""), false},
      {OutputFormat::RawF64, Precision::Float, 2, fltMax, true},
      {OutputFormat::RawF64, Precision::Float, 30, std::numeric_limits<double>::infinity(), false},
  };
  for (const Case& c : cases) {
    PlacedJob job = makeJob();
    job.planes[1][c.point * 3 + 2] = c.value;
    job.planesF[1][c.point * 3 + 2] = static_cast<float>(c.value);
    const fs::path file = tempFile("b.raw");
    const std::vector<bool> answers = writeSliced(c.format, job, job.chunk(c.planes), file);
    const bool inFirst = c.point < 13;
    EXPECT_EQ(answers[1], inFirst ? c.fits : true) << c.value << " at " << c.point;
    EXPECT_EQ(answers[0], inFirst ? true : c.fits) << c.value << " at " << c.point;
    fs::remove(file);
    fs::remove(file.string() + ".json");
  }
}

TEST(PlacedRecords, WritersThatPlaceNoRecordsLeaveTheCheckToTheCaller) {
  const PlacedJob job = makeJob();
  const fs::path file = tempFile("c.ply");
  AtomicFile out(file, "-o");
  const auto writer = makeSampleWriter(OutputFormat::Ply, out, nullptr);
  writer->begin(job.layout);
  EXPECT_FALSE(writer->writeSlice(job.chunk(Precision::Double), 0, 35));
}

}  // namespace
}  // namespace shapespline::io
