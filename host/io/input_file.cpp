#include <shapespline/io/input_file.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <unordered_set>
#include <vector>

#include <shapespline/core/model.h>

namespace shapespline::io {

namespace {

using nlohmann::json;

constexpr std::size_t kMaxFieldChars = 80;    // a JSON path shown as a field
constexpr std::size_t kMaxKeyChars = 32;      // one key inside such a path
constexpr std::size_t kMaxReasonChars = 200;  // nlohmann's parse error text (it quotes the last token)
constexpr int kMaxShownDepth = 4;             // shortValue prints deeper containers as "..."

const char* fileKind(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a plain file";
}

// The way out for a JSON file (a model's big arrays need not be written out in it).
std::string tooLarge(std::uint64_t maxBytes) {
  return "input files are limited to " + std::to_string(maxBytes >> 20) + " MiB (" + std::to_string(maxBytes) +
         " bytes); a model's big point arrays go in .npy files beside it (\"points\": {\"npy\": \"points.npy\"}, "
         "docs/format.md)";
}

// Control characters of the input shown as '?', so a message stays one printable line.
std::string printable(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return out;
}

// SAX handler: checks the limits while nlohmann's own DOM builder (to which every event is
// forwarded) builds the value. Not json::parse with a parser callback: that parser rescans the
// enclosing array after every object (O(n^2) for a list of n objects). Tracks the open containers
// (for the path shown in errors), their element and key counts and the keys seen per object (a
// hash set, so n keys cost O(n)).
class LimitSax {
 public:
  using Dom = nlohmann::detail::json_sax_dom_parser<json>;

  LimitSax(json& result, const std::string& documentField, const std::string& pathPrefix)
      : dom_(result, true), documentField_(documentField), pathPrefix_(pathPrefix) {}

  bool null() { return addElement(), dom_.null(); }
  bool boolean(bool v) { return addElement(), dom_.boolean(v); }
  bool number_integer(json::number_integer_t v) { return addElement(), dom_.number_integer(v); }
  bool number_unsigned(json::number_unsigned_t v) { return addElement(), dom_.number_unsigned(v); }
  bool number_float(json::number_float_t v, const json::string_t& s) { return addElement(), dom_.number_float(v, s); }
  bool string(json::string_t& v) { return addElement(), dom_.string(v); }
  bool binary(json::binary_t& v) { return addElement(), dom_.binary(v); }
  bool start_object(std::size_t n) { return open(true), dom_.start_object(n); }
  bool start_array(std::size_t n) { return open(false), dom_.start_array(n); }
  bool end_object() { return close(), dom_.end_object(); }
  bool end_array() { return close(), dom_.end_array(); }
  bool key(json::string_t& k) {
    Frame& f = frames_.back();
    f.key = k;
    if (++f.count > kMaxJsonObjectKeys)
      throw ModelError(path(), "more than " + std::to_string(kMaxJsonObjectKeys) + " keys",
           "JSON objects are limited to " + std::to_string(kMaxJsonObjectKeys) + " keys");
    if (!f.keys.insert(k).second) throw ModelError(path(), "(repeated)", "duplicate key in a JSON object");
    return dom_.key(k);
  }
  // A template, as in nlohmann's parser: it throws `e` by its static type (json::parse_error).
  template <class Exception>
  bool parse_error(std::size_t position, const std::string& token, const Exception& e) {
    return dom_.parse_error(position, token, e);
  }

 private:
  struct Frame {
    bool object = false;
    std::size_t count = 0;  // elements (arrays) or keys (objects) so far
    std::string key;        // objects: the current key
    std::unordered_set<std::string> keys;
  };

  void open(bool object) {
    addElement();
    if (frames_.size() >= static_cast<std::size_t>(kMaxJsonDepth))
      throw ModelError(path(), "more than " + std::to_string(kMaxJsonDepth) + " levels",
           "JSON nesting is limited to " + std::to_string(kMaxJsonDepth) + " levels");
    frames_.push_back({object, 0, {}, {}});
  }
  void close() {
    if (!frames_.empty()) frames_.pop_back();
  }

  // A value or container begins inside the innermost array: count it (objects count keys instead).
  void addElement() {
    if (frames_.empty() || frames_.back().object) return;
    if (++frames_.back().count > kMaxJsonArrayLength)
      throw ModelError(path(), "more than " + std::to_string(kMaxJsonArrayLength) + " elements",
           "JSON arrays are limited to " + std::to_string(kMaxJsonArrayLength) + " elements");
  }

  // Path of the value being read: "points[2][1]", "samples[0].uv".
  std::string path() const {
    std::string p;
    for (const Frame& f : frames_) {
      if (f.object) {
        if (f.count == 0) break;
        p += (p.empty() ? "" : ".") + printable(shortText(f.key, kMaxKeyChars));
      } else {
        if (f.count == 0) break;
        p += "[" + std::to_string(f.count - 1) + "]";
      }
      if (p.size() > kMaxFieldChars) break;
    }
    if (p.empty()) return documentField_;
    if (!pathPrefix_.empty() && p[0] != '[') p = "." + p;
    return shortText(pathPrefix_ + p, kMaxFieldChars);
  }

  Dom dom_;
  const std::string& documentField_;
  const std::string& pathPrefix_;
  std::vector<Frame> frames_;
};

void appendString(std::string& out, const std::string& s, std::size_t budget) {
  // A prefix is enough; the replace handler keeps a UTF-8 sequence cut here from throwing.
  const json prefix = s.size() > budget ? s.substr(0, budget) : s;
  out += prefix.dump(-1, ' ', false, json::error_handler_t::replace);
}

void appendShort(std::string& out, const json& v, std::size_t budget, int depth) {
  if (v.is_object() || v.is_array()) {
    const bool object = v.is_object();
    out += object ? '{' : '[';
    if (!v.empty() && depth >= kMaxShownDepth) {
      out += "...";
    } else {
      bool first = true;
      for (auto it = v.begin(); it != v.end(); ++it) {
        if (out.size() > budget) {
          out += ",...";
          break;
        }
        if (!first) out += ',';
        first = false;
        if (object) {
          appendString(out, it.key(), budget);
          out += ':';
        }
        appendShort(out, it.value(), budget, depth + 1);
      }
    }
    out += object ? '}' : ']';
  } else if (v.is_string()) {
    appendString(out, v.get_ref<const std::string&>(), budget);
  } else {
    out += v.dump();  // a scalar: a few characters
  }
}

}  // namespace

InputFd::InputFd(const std::filesystem::path& path, const std::string& field) {
  do {
    fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  } while (fd_ < 0 && errno == EINTR);
  if (fd_ < 0) throw std::runtime_error("cannot open '" + path.string() + "': " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd_, &st) != 0) {
    const int err = errno;
    ::close(fd_);
    throw std::runtime_error("cannot stat '" + path.string() + "': " + std::strerror(err));
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd_);
    throw ModelError(field, shortText(path.string()), std::string("is not a regular file (it is ") + fileKind(st.st_mode) + ")");
  }
  size_ = st.st_size < 0 ? 0 : static_cast<std::uint64_t>(st.st_size);
}

InputFd::~InputFd() { ::close(fd_); }

std::string readInputFile(const std::filesystem::path& path, const std::string& field, std::uint64_t maxBytes) {
  const InputFd f(path, field);
  if (f.size() > maxBytes) throw ModelError(field, std::to_string(f.size()) + " bytes", tooLarge(maxBytes));

  // One byte more than fstat reports, so that the read meeting end of file needs no reallocation.
  std::string bytes(static_cast<std::size_t>(f.size()) + 1, '\0');
  std::size_t used = 0;
  for (;;) {
    if (used == bytes.size()) {
      // The file grew since fstat (or reports size 0, as some special files do): read on, bounded.
      if (used > maxBytes) throw ModelError(field, "more than " + std::to_string(maxBytes) + " bytes", tooLarge(maxBytes));
      bytes.resize(static_cast<std::size_t>(std::min<std::uint64_t>(maxBytes + 1, used + (std::size_t{1} << 16))));
      if (used == bytes.size()) throw ModelError(field, "more than " + std::to_string(maxBytes) + " bytes", tooLarge(maxBytes));
    }
    const ssize_t n = ::read(f.get(), bytes.data() + used, bytes.size() - used);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error("cannot read '" + path.string() + "': " + std::strerror(errno));
    }
    if (n == 0) break;
    used += static_cast<std::size_t>(n);
  }
  if (used > maxBytes) throw ModelError(field, "more than " + std::to_string(maxBytes) + " bytes", tooLarge(maxBytes));
  bytes.resize(used);
  return bytes;
}

json parseJsonText(std::string_view text, const std::string& documentField, const std::string& pathPrefix) {
  try {
    json result;
    LimitSax sax(result, documentField, pathPrefix);
    json::sax_parse(text.begin(), text.end(), &sax);
    return result;
  } catch (const json::exception& e) {
    // Text that does not even begin as a JSON object is no file of ours (a model, a sample list, a
    // sidecar): none of its bytes are echoed, not even in nlohmann's "last read" (a path that named
    // /etc/shadow must not print its first line).
    const std::size_t first = text.find_first_not_of(" \t\r\n");
    const bool utf8Bom = text.substr(0, 3) == "\xEF\xBB\xBF";
    if (first == std::string_view::npos || (text[first] != '{' && !(utf8Bom && text.substr(3, 1) == "{")))
      throw ModelError(documentField, "", "malformed JSON: the text is not a JSON object (it does not begin with '{'); "
                                          "its bytes are not shown");
    // parse_error carries the byte position; show the text around it as the value.
    std::string near;
    if (const auto* pe = dynamic_cast<const json::parse_error*>(&e)) {
      const std::size_t at = pe->byte > 0 ? pe->byte - 1 : 0;
      const std::size_t from = at > 20 ? at - 20 : 0;
      if (from < text.size()) near = "near \"" + printable(text.substr(from, 40)) + "\"";
    }
    throw ModelError(documentField, shortText(near), "malformed JSON: " + printable(shortText(e.what(), kMaxReasonChars)));
  }
}

std::string shortText(std::string_view s, std::size_t maxChars) {
  if (s.size() <= maxChars) return std::string(s);
  std::size_t cut = maxChars > 3 ? maxChars - 3 : 0;
  // Never end inside a UTF-8 sequence: back up over continuation bytes (10xxxxxx).
  while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;
  return std::string(s.substr(0, cut)) + "...";
}

std::string shortValue(const json& value, std::size_t maxChars) {
  std::string out;
  appendShort(out, value, maxChars, 0);
  return shortText(out, maxChars);
}

}  // namespace shapespline::io
