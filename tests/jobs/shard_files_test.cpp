// jobs/shard_pattern and jobs/shard_record (issue 16): every expanded name reads back to its (K, N);
// names that expand() does not write do not match; the shard record reads back what it wrote and
// refuses anything else naming the key.
#include <shapespline/jobs/shard_pattern.h>
#include <shapespline/jobs/shard_record.h>

#include <gtest/gtest.h>

#include <string>

namespace shapespline::jobs {
namespace {

TEST(ShardPattern, ExpandsAndReadsBack) {
  const ShardPattern p = ShardPattern::parse("dir/sub/out-{shard:05d}-of-{count:05d}.f32");
  EXPECT_EQ(p.folder(), "dir/sub/");
  EXPECT_TRUE(p.hasShard() && p.hasCount());
  EXPECT_EQ(p.expand(3, 12), "dir/sub/out-00003-of-00012.f32");
  EXPECT_EQ(p.expand(123456, 1000000), "dir/sub/out-123456-of-1000000.f32");  // wider than 5: in full
  for (uint64_t n : {uint64_t{1}, uint64_t{9}, uint64_t{10}, uint64_t{99999}, uint64_t{100000}, uint64_t{1000000000}}) {
    for (uint64_t k : {uint64_t{1}, n / 2 + 1, n}) {
      const std::string name = p.expand(k, n).substr(p.folder().size());
      const auto m = p.match(name);
      ASSERT_TRUE(m) << name;
      EXPECT_EQ(m->first, k);
      EXPECT_EQ(m->second, n);
    }
  }
  // Not as expand() writes them: unpadded, over-padded, other text, a sign, empty digits.
  for (const char* bad : {"out-3-of-00012.f32", "out-000003-of-00012.f32", "out-00003-of-00012.f64",
                          "out-00003-of-00012.f32.json", "out--0003-of-00012.f32", "out--of-00012.f32",
                          "xout-00003-of-00012.f32"}) {
    EXPECT_FALSE(p.match(bad)) << bad;
  }
  const ShardPattern plain = ShardPattern::parse("p{shard}.csv");
  EXPECT_EQ(plain.match("p7.csv")->first, 7u);
  EXPECT_EQ(plain.match("p7.csv")->second, 0u);  // no {count}
  EXPECT_FALSE(plain.match("p07.csv"));           // a leading zero is not how {shard} writes 7
  EXPECT_FALSE(plain.match("p12345678901.csv"));  // more than 10 digits
  // The same placeholder twice must agree; other braces are text.
  const ShardPattern twice = ShardPattern::parse("a{x}{shard:02d}_{shard:02d}");
  EXPECT_EQ(twice.expand(4, 9), "a{x}04_04");
  EXPECT_TRUE(twice.match("a{x}04_04"));
  EXPECT_FALSE(twice.match("a{x}04_05"));
}

TEST(ShardPattern, RefusesMalformedPlaceholders) {
  for (const char* bad : {"p{shard:5d}", "p{shard:00d}", "p{shard:011d}", "p{shard:0d}", "p{shard:05x}", "p{shard",
                          "p{countx}", "p{shard}{count}", "p{shard}7", "d{count}/p{shard}", "p{shard:-5d}",
                          "p{shard: 5d}", "no-placeholder"}) {
    EXPECT_THROW(ShardPattern::parse(bad), ShardPatternError) << bad;
  }
  EXPECT_TRUE(ShardPattern::looksLikePattern("a{shard:5d}"));
  EXPECT_FALSE(ShardPattern::looksLikePattern("a{b}.f32"));
}

ShardRecord sample() {
  ShardRecord r;
  r.job = "0123456789abcdef";
  r.surface = true;
  r.format = "ply";
  r.shardIndex = 2;
  r.shardCount = 3;
  r.firstItem = 5;
  r.itemCount = 5;
  r.totalItems = 16;
  r.points = 45;
  r.vertices = 51;
  r.files = {{"p2.ply", "data", 1234, std::string(64, 'a')}};
  r.metadata.toolVersion = "0.1.0";
  r.metadata.toolCommit = "abc";
  r.metadata.modelFile = "m.json";
  r.metadata.surface = true;
  r.metadata.construction = Construction::ExtendedBSpline;
  r.metadata.samplesU = r.metadata.samplesV = 3;
  return r;
}

TEST(ShardRecord, ReadsBackWhatItWrites) {
  const ShardRecord r = sample();
  const ShardRecord back = parseShardRecord(shardRecordJson(r));
  EXPECT_EQ(back.job, r.job);
  EXPECT_EQ(back.format, r.format);
  EXPECT_EQ(back.shardIndex, 2);
  EXPECT_EQ(back.shardCount, 3);
  EXPECT_EQ(back.firstItem, 5u);
  EXPECT_EQ(back.vertices, 51u);
  EXPECT_EQ(back.files, r.files);
  EXPECT_EQ(back.metadata, r.metadata);
  EXPECT_EQ(shardRecordPath("a/b.f32").string(), "a/b.f32.shard.json");
}

TEST(ShardRecord, RefusesAnythingElseNamingTheKey) {
  const nlohmann::json good = nlohmann::json::parse(shardRecordJson(sample()));
  struct Case {
    const char* key;
    nlohmann::json value;
  };
  auto refusedAt = [&](const nlohmann::json& j, const std::string& key) {
    try {
      parseShardRecord(j.dump());
      ADD_FAILURE() << "accepted: " << j.dump().substr(0, 200);
    } catch (const ShardRecordError& e) {
      EXPECT_EQ(e.key(), key) << e.what();
    }
  };
  for (const char* key : {"format", "format_version", "job", "kind", "output_format", "shard", "items", "points",
                          "vertices", "files", "metadata"}) {
    nlohmann::json j = good;
    j.erase(key);
    refusedAt(j, key);
  }
  auto with = [&](const nlohmann::json::json_pointer& at, const nlohmann::json& v) {
    nlohmann::json j = good;
    j[at] = v;
    return j;
  };
  using P = nlohmann::json::json_pointer;
  refusedAt(with(P("/format"), "shapespline-raw"), "format");
  refusedAt(with(P("/format_version"), 2), "format_version");
  refusedAt(with(P("/job"), "0123"), "job");
  refusedAt(with(P("/kind"), "volume"), "kind");
  refusedAt(with(P("/output_format"), "exe"), "output_format");
  refusedAt(with(P("/shard/index"), 4), "shard.index");
  refusedAt(with(P("/shard/count"), 0), "shard.count");
  refusedAt(with(P("/shard/count"), -1), "shard.count");
  refusedAt(with(P("/items/first"), 17), "items.first");
  refusedAt(with(P("/items/count"), 12), "items.count");
  refusedAt(with(P("/items/total"), "16"), "items.total");
  refusedAt(with(P("/points"), 1.5), "points");
  refusedAt(with(P("/files"), nlohmann::json::array()), "files");
  refusedAt(with(P("/files/0/name"), "../etc/passwd"), "files[0].name");
  refusedAt(with(P("/files/0/name"), ".."), "files[0].name");
  refusedAt(with(P("/files/0/role"), "sidecar"), "files[0].role");
  refusedAt(with(P("/files/0/sha256"), std::string(64, 'A')), "files[0].sha256");
  refusedAt(with(P("/files/0/bytes"), -5), "files[0].bytes");
  refusedAt(with(P("/extra"), 1), "extra");
  nlohmann::json dup = good;
  dup["files"].push_back(dup["files"][0]);
  dup["files"][1]["role"] = "sidecar";
  refusedAt(dup, "files[1].name");
  nlohmann::json meta = good;
  meta["metadata"]["kind"] = "volume";
  EXPECT_THROW(parseShardRecord(meta.dump()), ShardRecordError);
  for (const std::string& text : {std::string("not json"), std::string("[]"), std::string(100000, '['), std::string()}) {
    EXPECT_THROW(parseShardRecord(text), ShardRecordError);
  }
}

// A projection's shard (`project --shard`): kind "projection", its target, no metadata.
TEST(ShardRecord, AProjectionsShardReadsBackWithItsTarget) {
  ShardRecord r = sample();
  r.projection = "part";
  r.format = "npy";
  r.metadata = {};
  const nlohmann::json j = nlohmann::json::parse(shardRecordJson(r));
  EXPECT_EQ(j["kind"], "projection");
  EXPECT_EQ(j["target"], "part");
  EXPECT_FALSE(j.contains("metadata"));
  const ShardRecord back = parseShardRecord(j.dump());
  EXPECT_EQ(back.projection, "part");
  EXPECT_TRUE(back.surface);
  EXPECT_EQ(back.files, r.files);
  auto refusedAt = [](const nlohmann::json& bad, const std::string& key) {
    try {
      parseShardRecord(bad.dump());
      ADD_FAILURE() << "accepted: " << bad.dump().substr(0, 200);
    } catch (const ShardRecordError& e) {
      EXPECT_EQ(e.key(), key) << e.what();
    }
  };
  nlohmann::json noTarget = j, badTarget = j, withMetadata = j;
  noTarget.erase("target");
  refusedAt(noTarget, "target");
  badTarget["target"] = "volume";
  refusedAt(badTarget, "target");
  withMetadata["metadata"] = nlohmann::json::parse(shardRecordJson(sample()))["metadata"];
  refusedAt(withMetadata, "metadata");
  nlohmann::json sampled = nlohmann::json::parse(shardRecordJson(sample()));
  sampled["target"] = "part";
  refusedAt(sampled, "target");
}

}  // namespace
}  // namespace shapespline::jobs
