# Shared by the package tests: arguments, a scratch folder, the consumer build.
#   $1 build dir  $2 source dir  $3 project version  $4 git commit  $5 C++ compiler launcher (may be empty)
#   $6 the licence's SPDX id
set -euo pipefail
BUILD=$(cd "$1" && pwd)
SRC=$(cd "$2" && pwd)
VERSION=$3
COMMIT=$4
LAUNCHER=${5:-}
LICENSE_ID=$6
# Both tests lay out $T/usr (the prefix) and $T/build (the consumer) the same way, so that with
# CCACHE_BASEDIR=$T the second consumer build is a ccache hit (same relative -I paths).
T=$(mktemp -d "${TMPDIR:-/tmp}/shapespline-package.XXXXXX")
trap 'rm -rf "$T"' EXIT
export CCACHE_BASEDIR=$T

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# consume PREFIX: configure, build and run tests/consumer against the package under PREFIX.
consume() {
  local prefix=$1
  cmake -S "$SRC/tests/consumer" -B "$T/build" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" \
    -DSHAPESPLINE_REQUIRED_VERSION="$VERSION" ${LAUNCHER:+-DCMAKE_CXX_COMPILER_LAUNCHER=$LAUNCHER} >"$T/configure.log" \
    || { cat "$T/configure.log"; fail "consumer configure against $prefix"; }
  grep -q "shapespline $VERSION from $prefix/" "$T/configure.log" \
    || { cat "$T/configure.log"; fail "consumer did not find shapespline $VERSION under $prefix"; }
  grep -q "shapespline licence: $LICENSE_ID$" "$T/configure.log" \
    || { cat "$T/configure.log"; fail "the CMake package does not set shapespline_LICENSE to $LICENSE_ID"; }
  cmake --build "$T/build" >"$T/build.log" 2>&1 || { cat "$T/build.log"; fail "consumer build against $prefix"; }
  # The consumer must not reach into the build or source tree for headers or libraries.
  if grep -F -e "$BUILD/" -e "-I$SRC" "$T/build/build.ninja" >/dev/null; then
    fail "consumer build uses the shapespline build or source tree"
  fi
  (cd "$SRC" && "$T/build/shapespline_consumer" examples/models/surface_aeb.json) | tee "$T/run.log" \
    || fail "consumer run against $prefix"
  grep -q "^shapespline $VERSION (commit $COMMIT)" "$T/run.log" || fail "consumer reports another version"
  grep -qE "^(ok:|gpu: skipped:)" "$T/run.log" || fail "consumer printed no result"
}

# cli_import PREFIX: where the build has `import` (Open CASCADE found), the installed CLI finds the
# plugin it loads for it: a part that is not STEP is refused as such (exit 2), not as a missing plugin.
cli_import() {
  local prefix=$1 rc=0
  [ -f "$BUILD/host/cli/libshapespline-occt.so" ] || { echo "import: built without Open CASCADE"; return 0; }
  echo "not a step file" >"$T/bad.step"
  "$prefix/bin/shapespline" import "$T/bad.step" -o "$T/imported" 2>"$T/import.err" || rc=$?
  [ "$rc" = 2 ] && grep -q "not a readable STEP file" "$T/import.err" \
    || { cat "$T/import.err"; fail "installed shapespline import exited $rc"; }
  echo "import: the plugin loads from $(find "$prefix" -name libshapespline-occt.so)"
}

# pkgconfig PREFIX: the relocatable shapespline.pc resolves to PREFIX.
pkgconfig() {
  local prefix=$1 pc
  pc=$(dirname "$(find "$prefix" -name shapespline.pc | head -1)")
  [ -n "$pc" ] || fail "no shapespline.pc under $prefix"
  [ "$(PKG_CONFIG_PATH=$pc pkg-config --modversion shapespline)" = "$VERSION" ] || fail "pkg-config version"
  local inc
  inc=$(PKG_CONFIG_PATH=$pc pkg-config --cflags-only-I shapespline | tr ' ' '\n' | grep -m1 '^-I' | cut -c3-)
  [ "$(realpath "$inc")" = "$(realpath "$prefix/include")" ] || fail "pkg-config include dir $inc is not in $prefix"
  echo "pkg-config: $(PKG_CONFIG_PATH=$pc pkg-config --libs shapespline)"
  PKG_CONFIG_PATH=$pc pkg-config --validate shapespline || fail "pkg-config --validate shapespline"
  grep -qx "License: $LICENSE_ID" "$pc/shapespline.pc" || fail "shapespline.pc has no 'License: $LICENSE_ID'"
  [ "$(PKG_CONFIG_PATH=$pc pkg-config --variable=license shapespline)" = "$LICENSE_ID" ] \
    || fail "pkg-config --variable=license shapespline is not $LICENSE_ID"
}

# licence PREFIX: share/doc/shapespline holds the licence as in the source tree, THIRD_PARTY.md and
# the Debian machine-readable copyright file (DEP-5) that gives the project's files that licence.
licence() {
  local doc=$1/share/doc/shapespline
  cmp -s "$doc/LICENSE" "$SRC/LICENSE" || fail "$doc/LICENSE is not the source tree's LICENSE"
  cmp -s "$doc/THIRD_PARTY.md" "$SRC/THIRD_PARTY.md" || fail "$doc/THIRD_PARTY.md is not the source tree's"
  [ -f "$doc/copyright" ] || fail "no $doc/copyright"
  head -1 "$doc/copyright" | grep -qx "Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/" \
    || fail "$doc/copyright is not a DEP-5 file (its first line: $(head -1 "$doc/copyright"))"
  # The paragraph of all files ("Files: *"): its Copyright and License fields.
  local files
  files=$(awk '/^Files: \*$/ {p = 1} p && /^$/ {exit} p' "$doc/copyright")
  local ours
  ours=$(sed -n 's/^SPDX-FileCopyrightText = "\(.*\)"$/\1/p' "$SRC/REUSE.toml" | head -1)
  grep -qxF "Copyright: $ours" <<<"$files" || fail "copyright: the 'Files: *' paragraph lacks REUSE.toml's 'Copyright: $ours'"
  grep -qx "License: $LICENSE_ID" <<<"$files" || fail "copyright: the 'Files: *' paragraph is not 'License: $LICENSE_ID'"
  if grep -q "@[A-Z_]*@" "$doc/copyright"; then fail "copyright: an unsubstituted @VARIABLE@"; fi
  echo "licence: $LICENSE_ID ($(ls "$doc" | tr '\n' ' '))"
}

# python_import PREFIX: the installed Python module imports from PREFIX's dist-packages with
# Debian's python3 (and nothing from the build tree), loads a model and samples it on the CPU.
python_import() {
  local prefix=$1 dir
  dir=$(find "$prefix" -name 'shapespline.cpython-*.so' -printf '%h\n' | head -1)
  if [ -z "$dir" ]; then
    [ -f "$BUILD/python/CTestTestfile.cmake" ] && fail "no Python module installed under $prefix"
    echo "python: module not built: skipped"
    return 0
  fi
  [ "$dir" = "$prefix/lib/python3/dist-packages" ] || fail "Python module installed in $dir"
  [ -f "$dir/shapespline.pyi" ] || fail "no shapespline.pyi beside the module"
  (cd "$T" && PYTHONPATH="$dir" /usr/bin/python3 -c "
import shapespline as ss, sys
assert ss.__file__.startswith('$dir/'), ss.__file__
assert ss.__version__ == '$VERSION', ss.__version__
assert ss.__license__ == '$LICENSE_ID', ss.__license__
c = ss.load('$SRC/examples/models/butterfly_aeb.json')
p = c.sample(8, device='cpu')['point']
print('python: shapespline', ss.__version__, 'from', ss.__file__, 'sampled', p.shape)
") || fail "the installed Python module does not import from $dir"
}
