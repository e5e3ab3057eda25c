#pragma once
// The --script file of `shapespline view` (docs/viewer.md): one command per line, '#' starts a
// comment. Parsed completely before the window opens, so a bad line fails fast (ScriptError).
#include <string>
#include <string_view>
#include <vector>

namespace shapespline::viewer {

struct ScriptCommand {
  enum class Kind {
    Lambda,      // lambda V
    Mu,          // mu V0,V1,...            (the model's half vector)
    Alpha,       // alpha V                 (the picked point) | alpha I J V
    Pick,        // pick X Y                (a click at pixel X, Y)
    PickPoint,   // pick-point I J          (a click where control point (I, J) projects now)
    PickFace,    // pick-face ID            (a part: a click where face ID is drawn now)
    Orbit,       // orbit DAZ DEL           (degrees)
    Pan,         // pan DX DY               (pixels)
    Zoom,        // zoom F                  (distance x F)
    Tolerance,   // tolerance PX
    Wireframe,   // wireframe on|off
    Net,         // net on|off
    Edges,       // edges on|off            (a part's edges)
    Panel,       // panel on|off            (the ImGui panel; off for clean screenshots)
    Frames,      // frames N
    Screenshot,  // screenshot NAME.png     (a file name, written under --screenshot-dir)
    Quit,        // quit
  };
  Kind kind;
  std::vector<double> numbers;  // the numeric arguments in order
  bool on = false;              // wireframe / net / edges / panel
  std::string name;             // screenshot
  int line = 0;
  std::string text;             // the line as written (error messages)
};

// Throws ScriptError naming the line and the rule.
std::vector<ScriptCommand> parseScript(std::string_view text);
// Reads and parses a file; an unreadable file is a ScriptError on line 0.
std::vector<ScriptCommand> loadScript(const std::string& path);

}  // namespace shapespline::viewer
