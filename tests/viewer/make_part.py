"""Writes a part for tests/viewer/viewer_test.sh into DIR: two trimmed bicubic B-spline faces side by
side (face 1 at x in [0, 1], face 2 at x in [1.2, 2.2]), each a square with a square hole, with
each loop one coedge on an edge of its own (as part::faceAsPart makes them), and part.json naming
them; and DIR/untrimmed.json, face 1 without its trim loops. Usage: make_part.py DIR."""
import json
import sys
from pathlib import Path

OUTER = [[0.05, 0.05], [0.95, 0.05], [0.95, 0.95], [0.05, 0.95]]
HOLE = [[0.3, 0.3], [0.7, 0.3], [0.7, 0.7], [0.3, 0.7]]


def face(x0, trimmed=True):
    n = 5  # control points per direction: 2 knot intervals
    points = [[[x0 + i / (n - 1), j / (n - 1), 0.05 * ((i * 7 + j * 3) % 3)] for j in range(n)] for i in range(n)]
    model = {"kind": "surface", "construction": "bspline", "order": [4, 4],
             "knots": [[0, 0, 0, 0, 0.5, 1, 1, 1, 1]] * 2, "closed": [False, False], "points": points}
    if trimmed:
        model["trim"] = {"loops": [OUTER, HOLE], "tolerance": 1e-9}
    return model


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    faces, edges = [], []
    for k, x0 in enumerate([0.0, 1.2]):
        name = f"face_{k + 1}.json"
        (out / name).write_text(json.dumps(face(x0)))
        loops = []
        for l, loop in enumerate([OUTER, HOLE]):
            edge = 2 * k + l + 1
            edges.append({"id": edge})
            loops.append([{"edge": edge, "start": 0, "t": list(range(len(loop) + 1))}])
        faces.append({"id": k + 1, "model": name, "surface": "Geom_BSplineSurface", "coedges": loops})
    (out / "part.json").write_text(json.dumps({"format": "shapespline-part", "faces": faces, "edges": edges}))
    (out / "untrimmed.json").write_text(json.dumps(face(0.0, trimmed=False)))


if __name__ == "__main__":
    main()
