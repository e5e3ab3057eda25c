#include <shapespline/viewer/script.h>

#include <shapespline/viewer/errors.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace shapespline::viewer {
namespace {

using Kind = ScriptCommand::Kind;

constexpr int kMaxFrames = 100000;

struct Syntax {
  Kind kind;
  const char* usage;
};

const std::map<std::string, Syntax, std::less<>>& commands() {
  static const std::map<std::string, Syntax, std::less<>> table{
      {"lambda", {Kind::Lambda, "lambda V"}},
      {"mu", {Kind::Mu, "mu V0,V1,..."}},
      {"alpha", {Kind::Alpha, "alpha V (the picked point) or alpha I J V"}},
      {"pick", {Kind::Pick, "pick X Y (pixels)"}},
      {"pick-point", {Kind::PickPoint, "pick-point I J (point indices)"}},
      {"pick-face", {Kind::PickFace, "pick-face ID (a part's face id)"}},
      {"orbit", {Kind::Orbit, "orbit DAZ DEL (degrees)"}},
      {"pan", {Kind::Pan, "pan DX DY (pixels)"}},
      {"zoom", {Kind::Zoom, "zoom F (F > 0)"}},
      {"tolerance", {Kind::Tolerance, "tolerance PX (PX > 0)"}},
      {"wireframe", {Kind::Wireframe, "wireframe on|off"}},
      {"net", {Kind::Net, "net on|off"}},
      {"edges", {Kind::Edges, "edges on|off"}},
      {"panel", {Kind::Panel, "panel on|off"}},
      {"frames", {Kind::Frames, "frames N (1..100000)"}},
      {"screenshot", {Kind::Screenshot, "screenshot NAME.png"}},
      {"quit", {Kind::Quit, "quit"}},
  };
  return table;
}

bool parseNumber(const std::string& word, double& out) {
  const char* end = word.data() + word.size();
  const auto [ptr, ec] = std::from_chars(word.data(), end, out);
  return ec == std::errc() && ptr == end && std::isfinite(out);
}

ScriptCommand parseLine(const std::string& line, int number) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  const auto it = commands().find(words[0]);
  if (it == commands().end()) {
    std::string known;
    for (const auto& [name, syntax] : commands()) known += (known.empty() ? "" : ", ") + name;
    throw ScriptError(number, line, "unknown command '" + words[0] + "'; commands: " + known);
  }
  ScriptCommand c{it->second.kind, {}, false, {}, number, line};
  const std::string usage = std::string("expected ") + it->second.usage;
  const std::vector<std::string> args(words.begin() + 1, words.end());
  auto numbers = [&](std::initializer_list<size_t> counts) {
    bool countOk = false;
    for (size_t n : counts) countOk |= args.size() == n;
    if (!countOk) throw ScriptError(number, line, usage);
    for (const std::string& a : args) {
      double v;
      if (!parseNumber(a, v)) throw ScriptError(number, line, usage + "; '" + a + "' is not a finite number");
      c.numbers.push_back(v);
    }
  };
  switch (c.kind) {
    case Kind::Lambda:
    case Kind::Zoom:
    case Kind::Tolerance:
    case Kind::PickFace:
    case Kind::Frames: numbers({1}); break;
    case Kind::Alpha: numbers({1, 3}); break;
    case Kind::Pick:
    case Kind::PickPoint:
    case Kind::Orbit:
    case Kind::Pan: numbers({2}); break;
    case Kind::Mu: {
      if (args.size() != 1) throw ScriptError(number, line, usage);
      std::string item;
      for (std::istringstream list(args[0]); std::getline(list, item, ',');) {
        double v;
        if (!parseNumber(item, v)) throw ScriptError(number, line, usage + "; '" + item + "' is not a finite number");
        c.numbers.push_back(v);
      }
      break;
    }
    case Kind::Wireframe:
    case Kind::Net:
    case Kind::Edges:
    case Kind::Panel:
      if (args.size() != 1 || (args[0] != "on" && args[0] != "off")) throw ScriptError(number, line, usage);
      c.on = args[0] == "on";
      break;
    case Kind::Screenshot: {
      const std::string& n = args.size() == 1 ? args[0] : std::string();
      const bool png = n.size() > 4 && n.compare(n.size() - 4, 4, ".png") == 0;
      if (!png || n.find('/') != std::string::npos || n[0] == '.')
        throw ScriptError(number, line, usage + ": a file name ending in .png, without '/', not starting with '.'");
      c.name = n;
      break;
    }
    case Kind::Quit:
      if (!args.empty()) throw ScriptError(number, line, usage);
      break;
  }
  if (c.kind == Kind::Zoom && c.numbers[0] <= 0.0) throw ScriptError(number, line, usage);
  if (c.kind == Kind::Tolerance && c.numbers[0] <= 0.0) throw ScriptError(number, line, usage);
  if (c.kind == Kind::Frames && (c.numbers[0] < 1 || c.numbers[0] > kMaxFrames || c.numbers[0] != std::floor(c.numbers[0])))
    throw ScriptError(number, line, usage);
  if ((c.kind == Kind::Alpha && c.numbers.size() == 3) || c.kind == Kind::PickPoint)
    for (int k = 0; k < 2; ++k)
      if (c.numbers[k] < 0 || c.numbers[k] != std::floor(c.numbers[k]))
        throw ScriptError(number, line, usage + "; I and J are point indices (integers >= 0)");
  if (c.kind == Kind::PickFace && (c.numbers[0] < 0 || c.numbers[0] > 2147483647.0 || c.numbers[0] != std::floor(c.numbers[0])))
    throw ScriptError(number, line, usage + "; ID is a face id of part.json (an integer >= 0)");
  return c;
}

}  // namespace

std::vector<ScriptCommand> parseScript(std::string_view text) {
  std::vector<ScriptCommand> out;
  std::istringstream in{std::string(text)};
  int number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
    out.push_back(parseLine(line, number));
  }
  return out;
}

std::vector<ScriptCommand> loadScript(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ScriptError(0, path, "cannot read the script file");
  std::ostringstream text;
  text << in.rdbuf();
  return parseScript(text.str());
}

}  // namespace shapespline::viewer
