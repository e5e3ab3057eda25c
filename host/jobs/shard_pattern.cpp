#include <shapespline/jobs/shard_pattern.h>

namespace shapespline::jobs {

namespace {

constexpr std::string_view kExpected =
    "expected {shard}, {count}, {shard:0Wd} or {count:0Wd} with a width W of 1 to 10";

bool isDigit(char c) { return c >= '0' && c <= '9'; }

std::string padded(uint64_t v, int width) {
  std::string s = std::to_string(v);
  if (static_cast<int>(s.size()) < width) s.insert(0, static_cast<size_t>(width) - s.size(), '0');
  return s;
}

}  // namespace

bool ShardPattern::looksLikePattern(std::string_view path) {
  return path.find("{shard") != std::string_view::npos || path.find("{count") != std::string_view::npos;
}

ShardPattern ShardPattern::parse(std::string_view path) {
  ShardPattern p;
  const size_t slash = path.rfind('/');
  const size_t nameStart = slash == std::string_view::npos ? 0 : slash + 1;
  p.folder_ = std::string(path.substr(0, nameStart));
  if (looksLikePattern(p.folder_)) {
    throw ShardPatternError("shard placeholders may appear in the file name only, not in a folder");
  }
  const std::string_view name = path.substr(nameStart);
  size_t i = 0;
  auto addText = [&](std::string_view t) {
    if (t.empty()) return;
    if (!p.parts_.empty() && p.parts_.back().kind == Part::Kind::Text) {
      p.parts_.back().text += t;
    } else {
      p.parts_.push_back({Part::Kind::Text, std::string(t), 0});
    }
  };
  while (i < name.size()) {
    const bool shard = name.substr(i).starts_with("{shard"), count = name.substr(i).starts_with("{count");
    if (!shard && !count) {
      addText(name.substr(i, 1));
      ++i;
      continue;
    }
    const size_t start = i;
    const size_t close = name.find('}', i);
    const std::string where = " at character " + std::to_string(nameStart + start + 1);
    if (close == std::string_view::npos) {
      throw ShardPatternError("unclosed placeholder '" + std::string(name.substr(start, 16)) + "'" + where + ": " +
                              std::string(kExpected));
    }
    const std::string_view body = name.substr(start + 6, close - start - 6);  // after "{shard" / "{count"
    int width = 0;
    if (!body.empty()) {
      // ":0Wd"
      bool ok = body.size() >= 4 && body[0] == ':' && body[1] == '0' && body.back() == 'd';
      if (ok) {
        const std::string_view digits = body.substr(2, body.size() - 3);
        ok = !digits.empty() && digits.size() <= 2;
        for (char c : digits) ok = ok && isDigit(c);
        if (ok) width = std::stoi(std::string(digits));
        ok = ok && width >= 1 && width <= kMaxPatternWidth;
      }
      if (!ok) {
        throw ShardPatternError("malformed placeholder '" + std::string(name.substr(start, close - start + 1)) +
                                "'" + where + ": " + std::string(kExpected));
      }
    }
    if (!p.parts_.empty() && p.parts_.back().kind != Part::Kind::Text) {
      throw ShardPatternError("placeholder '" + std::string(name.substr(start, close - start + 1)) + "'" + where +
                              " follows another placeholder directly; put text between them, so that the numbers "
                              "can be read back from the file names");
    }
    p.parts_.push_back({shard ? Part::Kind::Shard : Part::Kind::Count, {}, width});
    (shard ? p.hasShard_ : p.hasCount_) = true;
    i = close + 1;
    if (i < name.size() && isDigit(name[i])) {
      throw ShardPatternError("placeholder '" + std::string(name.substr(start, close - start + 1)) + "'" + where +
                              " is followed by a digit; put other text between them, so that the numbers can be "
                              "read back from the file names");
    }
  }
  if (!p.hasShard_ && !p.hasCount_) throw ShardPatternError("not a shard pattern: no {shard} or {count}");
  return p;
}

std::string ShardPattern::expand(uint64_t k, uint64_t n) const {
  std::string s = folder_;
  for (const Part& part : parts_) {
    switch (part.kind) {
      case Part::Kind::Text: s += part.text; break;
      case Part::Kind::Shard: s += padded(k, part.width); break;
      case Part::Kind::Count: s += padded(n, part.width); break;
    }
  }
  return s;
}

std::optional<std::pair<uint64_t, uint64_t>> ShardPattern::match(std::string_view fileName) const {
  std::optional<uint64_t> k, n;
  size_t at = 0;
  for (const Part& part : parts_) {
    if (part.kind == Part::Kind::Text) {
      if (!fileName.substr(at).starts_with(part.text)) return std::nullopt;
      at += part.text.size();
      continue;
    }
    size_t end = at;
    while (end < fileName.size() && isDigit(fileName[end])) ++end;
    const size_t len = end - at;
    if (len == 0 || len > static_cast<size_t>(kMaxPatternWidth)) return std::nullopt;
    const uint64_t v = std::stoull(std::string(fileName.substr(at, len)));
    if (padded(v, part.width) != fileName.substr(at, len)) return std::nullopt;  // not as expand() writes it
    std::optional<uint64_t>& slot = part.kind == Part::Kind::Shard ? k : n;
    if (slot && *slot != v) return std::nullopt;  // the same placeholder twice with two values
    slot = v;
    at = end;
  }
  if (at != fileName.size()) return std::nullopt;
  return std::pair{k.value_or(0), n.value_or(0)};
}

}  // namespace shapespline::jobs
