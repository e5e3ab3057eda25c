// io/shard_info.h: the job line round-trips and rejects anything else, the fingerprint separates
// jobs that differ in any input, the escaping keeps a path on one line, span windows.
#include <shapespline/io/shard_info.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace shapespline::io {
namespace {

ShardInfo sampleInfo() {
  ShardInfo s;
  s.job = "0123456789abcdef";
  s.surface = true;
  s.shardIndex = 2;
  s.shardCount = 3;
  s.firstItem = 5;
  s.itemCount = 6;
  s.totalItems = 16;
  s.samplesU = 3;
  s.samplesV = 4;
  return s;
}

TEST(ShardInfo, LineRoundTrips) {
  const ShardInfo s = sampleInfo();
  const std::string line = shardInfoLine(s);
  EXPECT_EQ(line, "shapespline job 0123456789abcdef surface shard 2/3 items 5..11 of 16 grid 3x4");
  const auto back = parseShardInfoLine(line);
  ASSERT_TRUE(back);
  EXPECT_EQ(shardInfoLine(*back), line);
  EXPECT_EQ(back->firstItem, 5u);
  EXPECT_EQ(back->itemCount, 6u);
}

TEST(ShardInfo, MalformedLinesAreRejected) {
  const std::string good = shardInfoLine(sampleInfo());
  for (const std::string& bad : std::initializer_list<std::string>{
           std::string(""), good + " ", " " + good, good.substr(0, good.size() - 1) + "x",
           "shapespline job 0123456789ABCDEF surface shard 2/3 items 5..11 of 16 grid 3x4",   // upper-case hex
           "shapespline job 0123456789abcde surface shard 2/3 items 5..11 of 16 grid 3x4",    // 15 digits
           "shapespline job 0123456789abcdef surface shard 4/3 items 5..11 of 16 grid 3x4",   // K > N
           "shapespline job 0123456789abcdef surface shard 0/3 items 5..11 of 16 grid 3x4",   // K = 0
           "shapespline job 0123456789abcdef surface shard 2/3 items 11..5 of 16 grid 3x4",   // F > E
           "shapespline job 0123456789abcdef surface shard 2/3 items 5..17 of 16 grid 3x4",   // E > T
           "shapespline job 0123456789abcdef surface shard 2/3 items 5..11 of 16 grid 1x4",   // U < 2
           "shapespline job 0123456789abcdef curve shard 2/3 items 5..11 of 16 grid 3x4",     // curve V != 1
           "shapespline job 0123456789abcdef surface shard 2/3 items 05..11 of 16 grid 3x4",  // leading zero
           "shapespline job 0123456789abcdef surface shard 2/3 items -5..11 of 16 grid 3x4",
           "shapespline job 0123456789abcdef surface shard 2/3 items 5..11 of 18446744073709551616 grid 3x4",
           "shapespline job 0123456789abcdef surface shard 2/3 items 5..11 of 4611686018427387904 grid 3x4",  // 2^62
       }) {
    EXPECT_FALSE(parseShardInfoLine(bad)) << bad;
  }
}

TEST(ShardInfo, EscapeKeepsOneLineAndValidUtf8) {
  EXPECT_EQ(escapeText("a\nb\rc\td\"e\\f"), "a\\nb\\rc\\td\\\"e\\\\f");
  EXPECT_EQ(escapeText(std::string("x\0y", 3)), "x\\u0000y");
  EXPECT_EQ(escapeText("\x7f"), "\\u007f");
  EXPECT_EQ(escapeText("caf\xc3\xa9"), "caf\xc3\xa9");           // valid UTF-8 kept
  EXPECT_EQ(escapeText("a\xff" "b"), "a\\ufffdb");              // invalid byte replaced
  EXPECT_EQ(escapeText("\xc0\xaf"), "\\ufffd\\ufffd");          // overlong form
  EXPECT_EQ(escapeText("\xed\xa0\x80"), "\\ufffd\\ufffd\\ufffd");  // surrogate
  EXPECT_EQ(escapeText("\xe2\x82"), "\\ufffd\\ufffd");          // cut sequence
}

TEST(ShardInfo, FingerprintSeparatesJobs) {
  CurveModel m;
  m.family.construction = Construction::ExtendedBSpline;
  m.family.degree = 4;
  m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 2, 0}};
  SampleLayout l;
  l.samplesU = 8;
  l.totalItems = 3;
  l.fields = fieldBit(Field::Point);
  const std::string base = jobFingerprint(m, l, OutputFormat::Ply);
  EXPECT_EQ(base.size(), 16u);
  EXPECT_EQ(jobFingerprint(m, l, OutputFormat::Ply), base);
  // The shard does not enter the fingerprint: every shard of a job shares it.
  SampleLayout shard = l;
  shard.shardIndex = 2;
  shard.shardCount = 3;
  shard.firstItem = 1;
  shard.itemCount = 1;
  shard.source = "elsewhere.json";
  EXPECT_EQ(jobFingerprint(m, shard, OutputFormat::Ply), base);
  EXPECT_NE(jobFingerprint(m, l, OutputFormat::Obj), base);
  SampleLayout other = l;
  other.samplesU = 9;
  EXPECT_NE(jobFingerprint(m, other, OutputFormat::Ply), base);
  other = l;
  other.precision = Precision::Float;
  EXPECT_NE(jobFingerprint(m, other, OutputFormat::Ply), base);
  other = l;
  other.fields |= fieldBit(Field::D1);
  EXPECT_NE(jobFingerprint(m, other, OutputFormat::Ply), base);
  CurveModel n = m;
  n.points[2].y = std::nextafter(1.0, 2.0);
  EXPECT_NE(jobFingerprint(n, l, OutputFormat::Ply), base);
  n = m;
  n.family.lambda = -0.0;  // another bit pattern
  EXPECT_NE(jobFingerprint(n, l, OutputFormat::Ply), base);
  n = m;
  n.closed = true;
  EXPECT_NE(jobFingerprint(n, l, OutputFormat::Ply), base);
}

TEST(ShardInfo, SpanWindowCoversTheRowsAndColumnsOfTheItems) {
  // 4 x 5 patches.
  auto w = spanWindow(0, 20, 5);
  EXPECT_EQ(w.row0, 0u);
  EXPECT_EQ(w.row1, 4u);
  EXPECT_EQ(w.col0, 0u);
  EXPECT_EQ(w.col1, 5u);
  w = spanWindow(6, 3, 5);  // row 1, columns 1..3
  EXPECT_EQ(w.row0, 1u);
  EXPECT_EQ(w.row1, 2u);
  EXPECT_EQ(w.col0, 1u);
  EXPECT_EQ(w.col1, 4u);
  w = spanWindow(4, 2, 5);  // crosses a row: all columns
  EXPECT_EQ(w.row0, 0u);
  EXPECT_EQ(w.row1, 2u);
  EXPECT_EQ(w.col0, 0u);
  EXPECT_EQ(w.col1, 5u);
  w = spanWindow(7, 0, 5);  // empty
  EXPECT_EQ(w.row1 - w.row0, 0u);
  EXPECT_EQ(w.col1 - w.col0, 0u);
}

}  // namespace
}  // namespace shapespline::io
