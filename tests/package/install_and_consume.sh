#!/usr/bin/env bash
# package/install_and_consume: cmake --install into a scratch prefix; every installed header
# compiles on its own against that prefix (so no public header needs a private one); pkg-config
# resolves; the licence files and fields are there; tests/consumer builds and runs against it.
source "$(dirname "$0")/common.sh"

cmake --install "$BUILD" --prefix "$T/usr" >"$T/install.log" || { cat "$T/install.log"; fail "cmake --install"; }
[ -x "$T/usr/bin/shapespline" ] || fail "no bin/shapespline"
"$T/usr/bin/shapespline" --version | grep -q "^shapespline $VERSION (commit $COMMIT)$" || fail "shapespline --version"
for f in shapespline-config.cmake shapespline-config-version.cmake shapespline-targets.cmake; do
  [ -n "$(find "$T/usr" -path "*/cmake/shapespline/$f")" ] || fail "no cmake/shapespline/$f"
done
for lib in core io vk shaders gpu render; do
  [ -n "$(find "$T/usr" -name "libshapespline_$lib.a")" ] || fail "no libshapespline_$lib.a"
done

# Each public header alone, with nothing but the prefix and the dependencies' own flags.
cflags=$(PKG_CONFIG_PATH=$(dirname "$(find "$T/usr" -name shapespline.pc)") pkg-config --cflags shapespline)
CXX=${CXX:-c++}
(cd "$T/usr/include" && find shapespline -name '*.h' | sort) >"$T/headers"
[ -s "$T/headers" ] || fail "no headers installed"
echo "$(wc -l <"$T/headers") public headers"
# docs/api.md names every installed header (the statement of the public API stays true).
while read -r h; do
  rel=${h#shapespline/}
  [ "$rel" = version.h ] && continue
  dir=${rel%/*} name=${rel##*/}
  grep -E "^\| \`$dir/\` \|" "$SRC/docs/api.md" | grep -qF "\`$name\`" || fail "docs/api.md does not list $rel"
done <"$T/headers"
export CXX cflags T
xargs -P 2 -I{} sh -c 'printf "#include <%s>\n" "$1" | $CXX -std=c++20 -fsyntax-only -Wall -Wextra $cflags -x c++ - \
    >"$T/hdr.$$.log" 2>&1 || { echo "FAIL: <$1> does not compile on its own:"; cat "$T/hdr.$$.log"; exit 255; }' \
    _ {} <"$T/headers" || fail "a public header does not compile alone"

licence "$T/usr"
cli_import "$T/usr"
pkgconfig "$T/usr"
python_import "$T/usr"
consume "$T/usr"
echo "PASS"
