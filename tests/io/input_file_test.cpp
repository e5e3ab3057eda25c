// io/input_file.h (issue 12): the bounded reader, the JSON limits and the bounded value text.
#include <shapespline/io/input_file.h>

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include <shapespline/core/model.h>
#include <shapespline/io/model_json.h>

namespace shapespline {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path scratchFile(const std::string& name) {
  return fs::temp_directory_path() / ("shapespline_input_file_test_" + std::to_string(::getpid()) + "_" + name);
}

// Runs `f`, expecting a ModelError; returns it for inspection.
template <class F>
ModelError modelError(F&& f) {
  try {
    f();
  } catch (const ModelError& e) {
    return e;
  }
  ADD_FAILURE() << "no ModelError";
  return ModelError("", "", "");
}

std::string nested(size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); }

// ---- readInputFile -----------------------------------------------------------------------------

TEST(ReadInputFile, ReadsARegularFileWhole) {
  const fs::path p = scratchFile("regular.json");
  std::string bytes(100'000, 'x');
  bytes[5] = '\0';  // binary content is kept as is
  std::ofstream(p, std::ios::binary) << bytes;
  EXPECT_EQ(io::readInputFile(p, "F"), bytes);
  fs::remove(p);
}

TEST(ReadInputFile, RefusesSpecialFiles) {
  EXPECT_EQ(modelError([] { io::readInputFile("/dev/zero", "MODEL"); }).rule(),
            "is not a regular file (it is a character device)");
  EXPECT_EQ(modelError([] { io::readInputFile(fs::temp_directory_path(), "MODEL"); }).rule(),
            "is not a regular file (it is a directory)");
  const fs::path fifo = scratchFile("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const ModelError e = modelError([&] { io::readInputFile(fifo, "--at"); });  // must not block
  EXPECT_EQ(e.field(), "--at");
  EXPECT_EQ(e.rule(), "is not a regular file (it is a FIFO)");
  fs::remove(fifo);
}

TEST(ReadInputFile, SizeIsCheckedBeforeReading) {
  const fs::path p = scratchFile("big.json");
  std::ofstream(p) << "0123456789";
  const ModelError e = modelError([&] { io::readInputFile(p, "MODEL", 9); });
  EXPECT_EQ(e.field(), "MODEL");
  EXPECT_EQ(e.value(), "10 bytes");
  EXPECT_EQ(e.rule(), "input files are limited to 0 MiB (9 bytes); a model's big point arrays go in .npy files beside it "
                      "(\"points\": {\"npy\": \"points.npy\"}, docs/format.md)");
  EXPECT_EQ(io::readInputFile(p, "MODEL", 10), "0123456789");
  fs::remove(p);
}

// /proc files report size 0 and have content: the limit must hold while reading, too (a file that
// grows after fstat takes the same path).
TEST(ReadInputFile, SizeIsCheckedWhileReading) {
  struct stat st {};
  ASSERT_EQ(::stat("/proc/self/status", &st), 0);
  ASSERT_EQ(st.st_size, 0);
  const std::string whole = io::readInputFile("/proc/self/status", "F");
  EXPECT_NE(whole.find("Name:"), std::string::npos);
  const ModelError e = modelError([] { io::readInputFile("/proc/self/status", "F", 64); });
  EXPECT_EQ(e.value(), "more than 64 bytes");
}

TEST(ReadInputFile, MissingFileIsARuntimeError) {
  EXPECT_THROW(io::readInputFile(scratchFile("missing.json"), "F"), std::runtime_error);
}

// ---- parseJsonText -----------------------------------------------------------------------------

TEST(ParseJsonText, DepthLimit) {
  EXPECT_EQ(io::parseJsonText(nested(io::kMaxJsonDepth), "D").dump(), nested(io::kMaxJsonDepth));
  const ModelError e = modelError([] { io::parseJsonText(nested(100'000), "D"); });
  EXPECT_EQ(e.rule(), "JSON nesting is limited to 64 levels");
  EXPECT_EQ(e.field().rfind("[0][0][0]", 0), 0u) << e.field();
  EXPECT_LE(e.field().size(), 80u);
  EXPECT_EQ(
      modelError([] { io::parseJsonText("{\"a\": " + nested(io::kMaxJsonDepth) + "}", "D"); }).field().substr(0, 5),
      "a[0][");
}

TEST(ParseJsonText, KeyLimitAndDuplicates) {
  auto object = [](size_t keys, const std::string& extra) {
    std::string s = "{\"o\": {";
    for (size_t i = 0; i < keys; ++i) s += (i ? ", \"k" : "\"k") + std::to_string(i) + "\": " + std::to_string(i);
    return s + extra + "}}";
  };
  EXPECT_EQ(io::parseJsonText(object(io::kMaxJsonObjectKeys, ""), "D")["o"].size(), io::kMaxJsonObjectKeys);
  ModelError e = modelError([&] { io::parseJsonText(object(io::kMaxJsonObjectKeys + 1, ""), "D"); });
  EXPECT_EQ(e.field(), "o.k1024");
  EXPECT_EQ(e.rule(), "JSON objects are limited to 1024 keys");
  e = modelError([&] { io::parseJsonText(object(1000, ", \"k999\": 0"), "D"); });
  EXPECT_EQ(e.field(), "o.k999");
  EXPECT_EQ(e.rule(), "duplicate key in a JSON object");
  // The same key in two objects is no duplicate.
  EXPECT_NO_THROW(io::parseJsonText(R"([{"a": 1}, {"a": 2}, {"b": {"a": 3}}])", "D"));
}

TEST(ParseJsonText, ArrayLimitNamesTheElement) {
  std::string s = "{\"points\": [[0";
  s.reserve(2 * io::kMaxJsonArrayLength + 32);
  for (size_t i = 0; i < io::kMaxJsonArrayLength; ++i) s += ",0";
  const ModelError e = modelError([&] { io::parseJsonText(s + "]]}", "D", "F"); });
  EXPECT_EQ(e.field(), "F.points[0][4194304]");
  EXPECT_EQ(e.value(), "more than 4194304 elements");
}

TEST(ParseJsonText, MalformedTextShowsWhereAndStaysShort) {
  const ModelError e = modelError([] { io::parseJsonText("{\"kind\": \"curve\",\n", "(document)"); });
  EXPECT_EQ(e.field(), "(document)");
  EXPECT_EQ(e.value().rfind("near \"{\"kind\"", 0), 0u) << e.value();
  EXPECT_NE(e.rule().find("malformed JSON: [json.exception.parse_error.101]"), std::string::npos) << e.rule();
  // nlohmann quotes the last token: a 1 MB string with a bad escape at its end is not echoed.
  const ModelError big = modelError([] { io::parseJsonText("[\"" + std::string(1 << 20, 'x') + "\\q\"]", "D"); });
  EXPECT_LE(big.rule().size(), 220u);
  EXPECT_LE(big.value().size(), io::kMaxValueChars);
}

// A file that does not begin as a JSON object is not one of ours (a path that named /etc/hostname):
// its bytes appear neither as the value nor in nlohmann's "last read".
TEST(ParseJsonText, TextThatIsNoJsonObjectIsNotEchoed) {
  for (const char* text : {"vm-7f3a secret\n", "  root:x:0:0:root\n", "[\"secret\", tru]", "\xEF\xBB\xBFsecret"}) {
    SCOPED_TRACE(text);
    const ModelError e = modelError([&] { io::parseJsonText(text, "(document)"); });
    EXPECT_EQ(e.field(), "(document)");
    EXPECT_EQ(e.value(), "");
    EXPECT_NE(e.rule().find("not a JSON object"), std::string::npos) << e.what();
    for (const char* word : {"secret", "root", "vm-7f3a"})
      EXPECT_EQ(std::string(e.what()).find(word), std::string::npos) << e.what();
  }
  // A UTF-8 byte-order mark before the object is still an object's text: shown as before.
  const ModelError bom = modelError([] { io::parseJsonText("\xEF\xBB\xBF{\"kind\": tru}", "(document)"); });
  EXPECT_EQ(bom.value().rfind("near \"", 0), 0u) << bom.value();
}

// An array of many objects: nlohmann's callback parser rescans the enclosing array after every
// object (100k objects took 14 s); the SAX limits must stay linear.
// Measured as the growth from n to 8n objects in one run (linear: about 8x; quadratic: 64x), so a
// slow machine or a sanitizer build passes as well.
TEST(ParseJsonText, ManyObjectsAreLinear) {
  const auto seconds = [](size_t n) {
    std::string s = "[{}";
    for (size_t i = 0; i < n; ++i) s += ",{\"a\":1}";
    s += "]";
    double best = 1e9;
    for (int rep = 0; rep < 3; ++rep) {
      const auto start = std::chrono::steady_clock::now();
      EXPECT_EQ(io::parseJsonText(s, "D").size(), n + 1);
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    return best;
  };
  const double small = seconds(37'500), large = seconds(300'000);
  EXPECT_LT(large, 24 * small) << small << " s -> " << large << " s for 8x the objects";
}

// ---- shortText / shortValue ----------------------------------------------------------------------

TEST(ShortValue, SmallValuesAreDumpedAsIs) {
  for (const char* text :
       {"1", "-2.5", "true", "null", "\"abc\"", "[1,2,[3]]", "{\"a\":[1,{\"b\":null}]}", "[]", "{}"}) {
    const json v = json::parse(text);
    EXPECT_EQ(io::shortValue(v), v.dump()) << text;
  }
}

TEST(ShortValue, LargeAndDeepValuesAreCut) {
  json big = json::array();
  for (int i = 0; i < 1'000'000; ++i) big.push_back(i);
  const std::string s = io::shortValue(big);
  EXPECT_EQ(s.size(), io::kMaxValueChars);
  EXPECT_EQ(s.substr(0, 10), "[0,1,2,3,4");
  EXPECT_EQ(s.substr(s.size() - 3), "...");
  // Built in code, past any parse limit: shown without recursing through it.
  json deep = json::array();
  json* inner = &deep;
  for (int i = 0; i < 200'000; ++i) {
    inner->push_back(json::array());
    inner = &inner->back();
  }
  EXPECT_EQ(io::shortValue(deep), "[[[[[...]]]]]");
  EXPECT_EQ(io::shortValue(json(std::string(1 << 20, 'y'))).size(), io::kMaxValueChars);
}

TEST(ShortText, NeverCutsInsideAUtf8Sequence) {
  const std::string e = "\xC3\xA9";  // é, two bytes
  std::string s;
  for (int i = 0; i < 40; ++i) s += e;
  const std::string cut = io::shortText(s);
  EXPECT_LE(cut.size(), io::kMaxValueChars);
  EXPECT_EQ(cut.substr(cut.size() - 3), "...");
  const std::string body = cut.substr(0, cut.size() - 3);
  EXPECT_EQ(body.size() % 2, 0u);
  EXPECT_EQ(io::shortText("short"), "short");
}

// The model reader goes through both (a regression net for model_json.cpp).
TEST(ModelLimits, ModelTextUsesTheLimits) {
  EXPECT_EQ(modelError([] { io::parseModelText("{\"points\": " + nested(100'000) + "}"); }).rule(),
            "JSON nesting is limited to 64 levels");
  EXPECT_EQ(modelError([] { io::parseModelText(R"({"kind": "curve", "kind": "surface"})"); }).field(), "kind");
  const fs::path fifo = scratchFile("model_fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(modelError([&] { io::loadModelFile(fifo); }).field(), "(file)");
  fs::remove(fifo);
}

}  // namespace
}  // namespace shapespline
