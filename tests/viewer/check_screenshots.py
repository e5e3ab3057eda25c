"""Checks the screenshots of tests/viewer/viewer_test.sh: the surface covers a good part of the
first one, each edit (lambda, alpha of a picked point, camera, wireframe) changes the scene, and the
panel draws where it stands. Usage: check_screenshots.py DIR.
check_screenshots.py DIR NAME...: the views of one model only (check_views).
check_screenshots.py --panel DIR NAME...: the panel of NAME.png fits its content and the window
(check_panel, from NAME.panel.json, which the viewer writes beside a screenshot with the panel).
check_screenshots.py --picked DIR BEFORE AFTER: AFTER shows a picked face in its orange, BEFORE none.
check_screenshots.py --hole DIR TRIMMED UNTRIMMED: the centre of the picture (a trimmed face's hole)
is background in TRIMMED and drawn in UNTRIMMED (the same surface without its trim loops)."""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import numpy as np  # noqa: E402

MIN_SURFACE = 0.10   # of the pixels are not the white background in the first screenshot
MIN_CHANGED = 0.002  # of the pixels change visibly after each edit
VISIBLE = 8 / 255    # a channel difference seen as a change
PANEL = (slice(8, 100), slice(8, 200))  # rows, columns inside the panel's first-use place


def load(folder, name):
    img = mpimg.imread(folder / name)  # float RGB in [0, 1]
    return np.asarray(img[..., :3], dtype=np.float64)


def changed(a, b):
    return float((np.abs(a - b).max(axis=2) > VISIBLE).mean())


def check_views(folder, names):
    """Screenshots of one model from several cameras: the surface is drawn in each, and each view
    differs from the one before."""
    shots = [load(folder, n + ".png") for n in names]
    failures = []
    for name, img in zip(names, shots):
        covered = float((img.min(axis=2) < 1 - VISIBLE).mean())
        print(f"{name}: {covered:.3f} of the pixels are not background")
        if covered < MIN_SURFACE:
            failures.append(f"{name}: the surface covers {covered:.3f} of the image, want >= {MIN_SURFACE}")
    for (a, ia), (b, ib) in zip(zip(names, shots), list(zip(names, shots))[1:]):
        c = changed(ia, ib)
        print(f"{a} -> {b}: {c:.4f} of the pixels changed")
        if c < MIN_CHANGED:
            failures.append(f"{b}: only {c:.4f} of the pixels changed, want >= {MIN_CHANGED}")
    return failures


PANEL_DARK = 0.6  # of the panel's pixels are ImGui's dark window background or text on it


def check_panel(folder, names):
    """The panel's window lies inside the framebuffer, everything it draws (labels included) lies
    inside the window's padding, and the screenshot shows the panel where the viewer says it is."""
    failures = []
    for name in names:
        bounds = json.loads((folder / (name + ".panel.json")).read_text())
        img = load(folder, name + ".png")
        width, height = bounds["framebuffer"]
        x0, y0, x1, y1 = bounds["window"]
        cx, cy = bounds["content_max"]
        px, py = bounds["padding"]
        print(f"{name}: {width}x{height}, panel [{x0:.0f}, {x1:.0f}] x [{y0:.0f}, {y1:.0f}], "
              f"content to ({cx:.0f}, {cy:.0f}), padding ({px:.0f}, {py:.0f})")
        if img.shape[:2] != (height, width):
            failures.append(f"{name}: the screenshot is {img.shape[1]}x{img.shape[0]}, the framebuffer {width}x{height}")
            continue
        if x0 < 0 or y0 < 0 or x1 > width or y1 > height:
            failures.append(f"{name}: the panel [{x0}, {x1}] x [{y0}, {y1}] leaves the {width}x{height} window")
        if cx > x1 - px + 0.5 or cy > y1 - py + 0.5:
            failures.append(f"{name}: the content reaches ({cx}, {cy}), past the panel's inner edge "
                            f"({x1 - px}, {y1 - py}): a label or widget is clipped")
        inside = img[int(y0) + 1:int(y1) - 1, int(x0) + 1:int(x1) - 1]
        dark = float((inside.max(axis=2) < 0.3).mean()) if inside.size else 0.0
        print(f"{name}: {dark:.3f} of the panel's pixels are dark")
        if dark < PANEL_DARK:
            failures.append(f"{name}: only {dark:.3f} of the pixels where the panel stands are the panel's")
    return failures


MIN_PICKED = 50  # pixels of the picked face's orange


def picked_pixels(img):
    """Pixels of render::kPickedFaceColour (0.95, 0.55, 0.15) under any shading: red well above
    green, green well above blue. Nothing else the viewer draws for a part is orange."""
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    return int(((r > g + 0.15) & (g > b + 0.15) & (r > 0.3)).sum())


def check_picked(folder, before, after):
    counts = [picked_pixels(load(folder, n + ".png")) for n in (before, after)]
    print(f"picked-face pixels: {before} {counts[0]}, {after} {counts[1]}")
    if counts[0] != 0 or counts[1] < MIN_PICKED:
        return [f"want no picked-face pixels in {before} and >= {MIN_PICKED} in {after}, got {counts}"]
    return []


def check_hole(folder, trimmed, untrimmed):
    failures = []
    for name, want_background in ((trimmed, True), (untrimmed, False)):
        img = load(folder, name + ".png")
        h, w = img.shape[:2]
        centre = img[h // 2 - 2:h // 2 + 3, w // 2 - 2:w // 2 + 3]
        background = bool((centre.min(axis=2) > 1 - VISIBLE).all())
        print(f"{name}: the centre is {'background' if background else 'drawn'}")
        if background != want_background:
            failures.append(f"{name}: the centre should be {'background' if want_background else 'drawn'}")
    return failures


def main():
    if sys.argv[1] in ("--picked", "--hole"):
        check = check_picked if sys.argv[1] == "--picked" else check_hole
        failures = check(Path(sys.argv[2]), sys.argv[3], sys.argv[4])
        for f in failures:
            print("FAIL:", f)
        return 1 if failures else 0
    if sys.argv[1] == "--panel":  # check_screenshots.py --panel FOLDER NAME...
        failures = check_panel(Path(sys.argv[2]), sys.argv[3:])
        for f in failures:
            print("FAIL:", f)
        return 1 if failures else 0
    folder = Path(sys.argv[1])
    if len(sys.argv) > 2:  # check_screenshots.py FOLDER NAME...: check_views only
        failures = check_views(folder, sys.argv[2:])
        for f in failures:
            print("FAIL:", f)
        return 1 if failures else 0
    names = ["base", "lambda", "alpha", "camera", "wireframe", "panel"]
    shots = {n: load(folder, n + ".png") for n in names}
    failures = []
    covered = float((shots["base"].min(axis=2) < 1 - VISIBLE).mean())
    print(f"base: {covered:.3f} of the pixels are not background")
    if covered < MIN_SURFACE:
        failures.append(f"base: the surface covers {covered:.3f} of the image, want >= {MIN_SURFACE}")
    for before, after in zip(names[:4], names[1:5]):
        c = changed(shots[before], shots[after])
        print(f"{before} -> {after}: {c:.4f} of the pixels changed")
        if c < MIN_CHANGED:
            failures.append(f"{after}: only {c:.4f} of the pixels changed after the edit, want >= {MIN_CHANGED}")
    dark = lambda img: float((img[PANEL].max(axis=2) < 0.3).mean())  # noqa: E731 (ImGui's dark theme)
    print(f"panel region: {dark(shots['wireframe']):.3f} dark without the panel, {dark(shots['panel']):.3f} with it")
    if dark(shots["panel"]) < 0.5 or dark(shots["panel"]) < dark(shots["wireframe"]) + 0.3:
        failures.append("panel: the ImGui panel is not drawn in the top-left corner")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
