#!/usr/bin/env bash
# package/deb: cpack -G DEB builds the .deb; its Depends names the runtime libraries; it carries
# usr/share/doc/shapespline/copyright (DEP-5) with the licence and THIRD_PARTY.md; unpacked with
# dpkg-deb -x into a scratch root, its shapespline --version prints version and commit, and
# tests/consumer builds and runs against <root>/usr.
source "$(dirname "$0")/common.sh"
command -v dpkg-deb >/dev/null || { echo "dpkg-deb not found: skipped"; exit 0; }

(cd "$T" && cpack -G DEB --config "$BUILD/CPackConfig.cmake" -B "$T/pkg") >"$T/cpack.log" 2>&1 \
  || { cat "$T/cpack.log"; fail "cpack -G DEB"; }
deb=$(find "$T/pkg" -maxdepth 1 -name 'shapespline_*.deb' | head -1)
[ -n "$deb" ] || { cat "$T/cpack.log"; fail "no .deb written"; }
echo "$(basename "$deb"):"
dpkg-deb -f "$deb" Package Version Architecture Depends Recommends Suggests | sed 's/^/  /'
[ "$(dpkg-deb -f "$deb" Version)" = "$VERSION" ] || fail "package version is not $VERSION"
depends=$(dpkg-deb -f "$deb" Depends)
for p in libc6 libstdc++6 libvulkan1 libpng16-16; do
  tr ',|' '\n\n' <<<"$depends" | sed 's/^ *//; s/ .*//' | grep -qxF "$p" || fail "Depends lacks $p: $depends"
done

# Debian's place for the copyright file, which dpkg-deb lists as ./usr/share/doc/PACKAGE/copyright.
dpkg-deb -c "$deb" | awk '{print $NF}' | grep -qx "./usr/share/doc/shapespline/copyright" \
  || fail "the .deb has no ./usr/share/doc/shapespline/copyright"

dpkg-deb -x "$deb" "$T"
licence "$T/usr"
[ -f "$T/usr/include/shapespline/gpu/evaluator.h" ] || fail "no usr/include/shapespline/gpu/evaluator.h"
[ ! -e "$T/usr/include/shapespline/gpu/kernels.h" ] || fail "a private header was packed"
out=$("$T/usr/bin/shapespline" --version) || fail "shapespline --version exited $?"
echo "$out"
[ "$out" = "shapespline $VERSION (commit $COMMIT)" ] || fail "--version printed '$out'"
[ "$COMMIT" != unknown ] || echo "note: the build was configured without git, commit 'unknown'"

cli_import "$T/usr"
pkgconfig "$T/usr"
python_import "$T/usr"
consume "$T/usr"
echo "PASS"
