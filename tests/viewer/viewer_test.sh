#!/usr/bin/env bash
# shapespline view under a virtual X server: a script changes lambda, picks a control point and sets
# its alpha, moves the camera, turns the wireframe and the panel on, and saves a screenshot after
# each step; check_screenshots.py checks them (surface present, each edit changes the image, the
# panel is drawn). --validation makes any Vulkan validation message fail the run. A bad script line
# must fail with exit 2 before any window opens. A NURBS torus session follows, then the panel at
# 1024 x 640 and 1920 x 1080 with every control it can show: it fits its content and the window.
# Then a part (two trimmed faces) and a trimmed face on its own (see the end).
# Usage: viewer_test.sh SHAPESPLINE SOURCE_DIR. Exit 77 (skip) only when Xvfb is missing.
set -euo pipefail
bin=$1
src=$2
if ! command -v Xvfb >/dev/null 2>&1; then
  echo "SKIP: Xvfb is not installed (Debian: xvfb)"
  exit 77
fi
tmp=$(mktemp -d)
xvfb_pid=""
cleanup() {
  if [[ -n "$xvfb_pid" ]]; then kill "$xvfb_pid" 2>/dev/null || true; wait "$xvfb_pid" 2>/dev/null || true; fi
  rm -rf "$tmp"
}
trap cleanup EXIT

# -displayfd: Xvfb takes a free display number itself and writes it (tests may run in parallel).
Xvfb -displayfd 3 -screen 0 1920x1080x24 -nolisten tcp 3>"$tmp/display" >"$tmp/xvfb.log" 2>&1 &
xvfb_pid=$!
for _ in $(seq 100); do
  [[ -s "$tmp/display" ]] && break
  kill -0 "$xvfb_pid" 2>/dev/null || { cat "$tmp/xvfb.log"; echo "FAIL: Xvfb exited"; exit 1; }
  sleep 0.1
done
[[ -s "$tmp/display" ]] || { echo "FAIL: Xvfb gave no display number within 10 s"; exit 1; }
export DISPLAY=":$(head -n1 "$tmp/display")"
unset WAYLAND_DISPLAY
export SHAPESPLINE_CACHE_DIR="$tmp/cache"

model="$src/examples/models/surface_aeb.json"  # alpha_eb degree 5: lambda in [-15, 1]

# expect_exit2 MODEL SCRIPT_TEXT NAMED: view MODEL with a script of SCRIPT_TEXT must exit 2 and say NAMED.
expect_exit2() {
  printf '%b' "$2" >"$tmp/bad.txt"
  set +e
  "$bin" view "$1" --size 320x240 --script "$tmp/bad.txt" >"$tmp/bad.out" 2>&1
  local rc=$?
  set -e
  if [[ $rc -ne 2 ]] || ! grep -q "$3" "$tmp/bad.out"; then
    cat "$tmp/bad.out"; echo "FAIL: the script '$2' on $1 gave exit $rc (want 2, naming '$3')"; exit 1
  fi
}

# A bad line is refused before the window opens: exit 2, naming the line.
expect_exit2 "$model" 'frames 2\nalpha 2 2 1.5x\n' "line 2"
# An alpha outside (0, 1] is the model's rule: exit 2 as well, after the window opened.
expect_exit2 "$model" 'frames 1\nalpha 2 2 1.5\nquit\n' "alpha"

cat >"$tmp/session.txt" <<'SCRIPT'
# the panel is off for the edit screenshots: only the scene changes between them
panel off
frames 2
screenshot base.png
lambda -8
screenshot lambda.png
pick-point 2 2
alpha 0.1
screenshot alpha.png
orbit 50 20
zoom 0.8
screenshot camera.png
tolerance 0.5
wireframe on
screenshot wireframe.png
panel on
frames 2
screenshot panel.png
quit
SCRIPT
"$bin" view "$model" --size 480x360 --script "$tmp/session.txt" --screenshot-dir "$tmp/shots" --validation \
  >"$tmp/session.out" 2>&1 || { cat "$tmp/session.out"; echo "FAIL: the scripted session failed"; exit 1; }
cat "$tmp/session.out"
if grep -qi "validation\|\[vulkan" "$tmp/session.out"; then echo "FAIL: validation output"; exit 1; fi
grep -q "picked control point (2, 2)" "$tmp/session.out" || { echo "FAIL: pick-point 2 2 did not pick (2, 2)"; exit 1; }
/usr/bin/python3 "$src/tests/viewer/check_screenshots.py" "$tmp/shots"

# Knot-vector surfaces: a rational one (the NURBS torus; its double knots leave empty intervals)
# at a fixed rate, a non-rational one (bspline_surface.json) by the adaptive tessellator.
cat >"$tmp/nurbs.txt" <<'SCRIPT'
panel off
frames 2
screenshot nurbs.png
orbit 60 30
wireframe on
screenshot nurbs_orbit.png
quit
SCRIPT
for knot_model in nurbs_torus bspline_surface; do
  "$bin" view "$src/examples/models/$knot_model.json" --size 480x360 --script "$tmp/nurbs.txt" \
    --screenshot-dir "$tmp/$knot_model" --validation >"$tmp/$knot_model.out" 2>&1 ||
    { cat "$tmp/$knot_model.out"; echo "FAIL: the $knot_model session failed"; exit 1; }
  cat "$tmp/$knot_model.out"
  if grep -qi "validation\|\[vulkan" "$tmp/$knot_model.out"; then echo "FAIL: validation output"; exit 1; fi
  /usr/bin/python3 "$src/tests/viewer/check_screenshots.py" "$tmp/$knot_model" nurbs nurbs_orbit
done

# The panel at the window sizes people use: every label and widget inside it, it inside the window.
cat >"$tmp/panel.txt" <<'SCRIPT'
pick-point 2 2
alpha 0.1
frames 3
screenshot panel.png
quit
SCRIPT
for size in 1024x640 1920x1080; do
  "$bin" view "$model" --size "$size" --script "$tmp/panel.txt" --screenshot-dir "$tmp/panel_$size" --validation \
    >"$tmp/panel_$size.out" 2>&1 || { cat "$tmp/panel_$size.out"; echo "FAIL: the $size panel session failed"; exit 1; }
  if grep -qi "validation\|\[vulkan" "$tmp/panel_$size.out"; then cat "$tmp/panel_$size.out"; echo "FAIL: validation output"; exit 1; fi
  /usr/bin/python3 "$src/tests/viewer/check_screenshots.py" --panel "$tmp/panel_$size" panel
done

# A part (make_part.py: two trimmed faces with coedges) meshed on the host: it is drawn, picking a
# face shows it in orange, edges off, a finer tolerance with the wireframe change the picture, and
# the panel fits. A trimmed face alone shows its hole where its untrimmed surface is drawn.
/usr/bin/python3 "$src/tests/viewer/make_part.py" "$tmp/part"
cat >"$tmp/part.txt" <<'SCRIPT'
panel off
zoom 0.6
frames 2
screenshot part.png
pick-face 2
screenshot picked.png
edges off
screenshot no_edges.png
tolerance 0.3
wireframe on
screenshot wire.png
panel on
frames 2
screenshot part_panel.png
quit
SCRIPT
"$bin" view "$tmp/part/part.json" --size 480x360 --script "$tmp/part.txt" --screenshot-dir "$tmp/part_shots" \
  --validation >"$tmp/part.out" 2>&1 || { cat "$tmp/part.out"; echo "FAIL: the part session failed"; exit 1; }
cat "$tmp/part.out"
if grep -qi "validation\|\[vulkan" "$tmp/part.out"; then echo "FAIL: validation output"; exit 1; fi
grep -q "picked face 2 (Geom_BSplineSurface)" "$tmp/part.out" || { echo "FAIL: pick-face 2 did not pick face 2"; exit 1; }
/usr/bin/python3 "$src/tests/viewer/check_screenshots.py" "$tmp/part_shots" part picked no_edges wire
/usr/bin/python3 "$src/tests/viewer/check_screenshots.py" --picked "$tmp/part_shots" part picked
/usr/bin/python3 "$src/tests/viewer/check_screenshots.py" --panel "$tmp/part_shots" part_panel
printf 'panel off\nframes 2\nscreenshot trimmed.png\nquit\n' >"$tmp/trimmed.txt"
printf 'panel off\nnet off\nframes 2\nscreenshot untrimmed.png\nquit\n' >"$tmp/untrimmed.txt"
for face in trimmed untrimmed; do
  model="$tmp/part/face_1.json"
  [[ $face == untrimmed ]] && model="$tmp/part/untrimmed.json"
  "$bin" view "$model" --size 320x240 --script "$tmp/$face.txt" --screenshot-dir "$tmp/face_shots" --validation \
    >"$tmp/$face.out" 2>&1 || { cat "$tmp/$face.out"; echo "FAIL: the $face face session failed"; exit 1; }
done
/usr/bin/python3 "$src/tests/viewer/check_screenshots.py" --hole "$tmp/face_shots" trimmed untrimmed
# A part takes no surface control, and a face it lacks is refused: exit 2 naming the line.
for bad in 'lambda 0.5' 'pick-face 9' 'net off'; do
  expect_exit2 "$tmp/part/part.json" "frames 1\\n$bad\\nquit\\n" "line 2"
done
