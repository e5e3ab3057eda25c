// Issue 15 (requirement 5) for `eval`: every number it prints is the shortest text that reads back
// to the value as --precision gives it, checked against Python's own shortest forms (repr of a
// float; numpy's str of a float32): at most 17 significant digits in fp64, 9 in fp32.
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace shapespline::test {
namespace {

constexpr const char* kCheck = R"PY(
import json, re, sys
import numpy as np
text, precision = open(sys.argv[1]).read(), sys.argv[2]
samples = json.loads(text, parse_float=str, parse_int=str)['samples']  # numbers kept as printed
digits = lambda s: len(re.sub(r'^0+', '', re.sub(r'e.*$', '', s.lstrip('-')).replace('.', '')))
results = params = 0
for sample in samples:
    for key, value in sample.items():
        if value is None:
            continue
        for s in value if isinstance(value, list) else [value]:
            x = float(s)
            if key in ('point', 'du', 'dv', 'duu', 'duv', 'dvv', 'normal', 'render_normal', 'd1', 'd2') and precision == 'float':
                f = np.float32(s)
                assert digits(s) <= 9 and str(f) in (s, s + '.0'), (key, s, str(f))
                results += 1
            else:  # fp64: results after --precision double, and every parameter
                assert repr(x) in (s, s + '.0') and digits(s) <= 17, (key, s, repr(x))
                params += 1
assert results + params > 40, (results, params)
print('OK', results, params)
)PY";

TEST(EvalText, NumbersAreShortestRoundTrip) {
  ScratchDir dir("eval_text");
  writeText(dir / "at.json", R"({"samples":[{"patch":[1,2],"uv":[0.3,0.7]},{"patch":[0,0],"uv":[0.1,0.9]},)"
                             R"({"patch":[3,3],"uv":[1,1]}]})");
  writeText(dir / "check.py", kCheck);
  for (const char* precision : {"float", "double"}) {
    SCOPED_TRACE(precision);
    const CliResult r = runCli("eval " + quote(examplesDir() + "/surface_aeb.json") + " --at " +
                                   quote((dir / "at.json").string()) + " --device cpu -q --precision " + precision,
                               dir.path());
    ASSERT_EQ(r.rc, 0) << r.err;
    writeText(dir / "out.json", r.out);
    const CliResult py = runCaptured("/usr/bin/python3 " + quote((dir / "check.py").string()) + " " +
                                         quote((dir / "out.json").string()) + " " + precision + " >" +
                                         quote((dir / "_o").string()) + " 2>" + quote((dir / "_e").string()),
                                     dir / "_o", dir / "_e");
    EXPECT_EQ(py.rc, 0) << py.out << py.err;
    EXPECT_TRUE(contains(py.out, "OK")) << py.out << py.err;
  }
}

}  // namespace
}  // namespace shapespline::test
