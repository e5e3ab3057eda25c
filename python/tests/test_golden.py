"""Every golden case (tests/data/golden) through the Python module equals the C++ CPU result bit for
bit (the reference: shapespline_py_golden_reference, the same core calls as tests/core), and the
curve/surface samples are within the case's fp64 tolerance of the exact values."""
import json
import os
import pathlib
import struct
import subprocess

import numpy as np
import pytest

import shapespline as ss
from conftest import GOLDEN, REPO


def _reference():
    exe = os.environ.get("SHAPESPLINE_PY_GOLDEN_REFERENCE")
    if not exe:
        exe = str(REPO / "build" / "python" / "shapespline_py_golden_reference")
    out = subprocess.run([exe, str(GOLDEN)], check=True, capture_output=True, text=True, cwd=REPO).stdout
    return json.loads(out)


REFERENCE = _reference()
CASES = []
for f in sorted(GOLDEN.glob("*.json")):
    for c in json.loads(f.read_text())["cases"]:
        CASES.append(pytest.param(c, id=c["id"]))


def bits(values):
    a = np.ascontiguousarray(np.asarray(values, dtype=np.float64).ravel())
    return a.view(np.uint64)


def same(name, python_values, reference_hex):
    ref = np.array([float.fromhex(h) for h in reference_hex], dtype=np.float64)
    got = np.asarray(python_values, dtype=np.float64).ravel()
    assert got.shape == ref.shape, f"{name}: {got.shape} values, C++ has {ref.shape}"
    diff = np.nonzero(bits(got) != bits(ref))[0]
    assert diff.size == 0, f"{name}[{diff[0]}]: Python {got[diff[0]]!r} != C++ {ref[diff[0]]!r} ({diff.size} differ)"


def pad3(points):
    p = np.asarray(points, dtype=np.float64)
    out = np.zeros((p.shape[0], 3))
    out[:, : p.shape[1]] = p
    return out


def num(x):
    return float(x)


def check_curve(c, ref):
    m = ss.from_dict(c["model"])
    samples = c["inputs"]["samples"]
    rows = []
    for s in samples:
        r = m.evaluate(num(s["u"]), device="cpu") if "u" in s else m.evaluate(span=s["span"], t=num(s["t"]), device="cpu")
        rows.append(np.concatenate([r["point"][0], r["d1"][0], r["d2"][0]]))
    same("samples", rows, ref["samples"])
    # Batched evaluation gives the same bits as one call per sample.
    if all("u" in s for s in samples):
        r = m.evaluate([num(s["u"]) for s in samples], device="cpu")
    else:
        r = m.evaluate(span=[s["span"] for s in samples], t=[num(s["t"]) for s in samples], device="cpu")
    same("samples (batched)", np.hstack([r["point"], r["d1"], r["d2"]]), ref["samples"])
    same("u_range", m.parameter_range, ref["u_range"])
    assert list(m.spans) == ref["span_range"]
    same("alpha_nodes", m.alpha_nodes, ref["alpha_nodes"])
    same("alpha_v", m.alpha_v, ref["alpha_v"])
    tol = float(c["tolerance"]["fp64"])
    for s, e, got in zip(samples, c["expected"]["samples"], r["point"]):
        exp = np.array([float(v) for v in e["point"]])
        assert np.abs(got[: exp.size] - exp).max() <= tol, f"point at {s}"


def check_surface(c, ref):
    m = ss.from_dict(c["model"])
    samples = c["inputs"]["samples"]
    r = m.evaluate(patch=[s["patch"] for s in samples], uv=[[num(x) for x in s["uv"]] for s in samples], device="cpu")
    fields = ["point", "du", "dv", "duu", "duv", "dvv", "normal"]
    same("samples", np.hstack([r[f] for f in fields]), ref["samples"])
    (u0, u1), (v0, v1) = m.patches
    assert [u0, u1, v0, v1] == ref["patch_range"]
    same("alpha_nodes", m.alpha_nodes, ref["alpha_nodes"])
    same("alpha_v", m.alpha_v, ref["alpha_v"])
    tol = float(c["tolerance"]["fp64"])
    for e, got in zip(c["expected"]["samples"], r["point"]):
        exp = np.array([float(v) for v in e["point"]])
        assert np.abs(got - exp).max() <= tol


def check_basis(c, ref):
    fam = c["family"].split(".")[1]
    p = c.get("params", {})
    inputs = c["inputs"]
    kw = {}
    if "degree" in p:
        kw["degree"] = p["degree"]
    if "order" in p:
        kw["order"] = p["order"]
    if "lambda" in p:
        kw["lambda_"] = num(p["lambda"])
    if "mu" in p:
        kw["mu"] = p["mu"]
    if fam in ("xuwang", "gb", "singular_blend"):
        t = ss.basis(fam, [num(x) for x in inputs["t"]], **kw)
        for k in ("values", "d1", "d2"):
            same(k, t[k], ref[k])
        return
    b = ss.bell(fam, [num(x) for x in inputs["x"]], **kw)
    same("N", b["N"], ref["N"])
    same("dN", b["dN"], ref["dN"])
    t = ss.basis(fam, [num(x) for x in inputs["t"]], **kw)
    same("local_values", t["values"], ref["local_values"])
    same("local_d1", t["d1"], ref["local_d1"])
    if fam == "ubp":
        same("doubled_knot_coefficients", ss.ubp_doubled_knot_coefficients(p["order"], num(p["lambda"])),
             ref["doubled_knot_coefficients"])


def check_gb_modify(c, ref):
    m = ss.from_dict(c["model"])
    r = m.gb_constrained_modify(c["inputs"]["span"], c["inputs"]["target"])
    assert r["reachable"] == ref["reachable"]
    same("bisection", [r["t0"], r["lambda0"], r["w"]], ref["bisection"])
    same("all_solutions", [[s["t0"], s["lambda0"], s["w"]] for s in r["all_solutions"]], ref["all_solutions"])
    assert r["curve"].lambda_ == r["lambda0"]


def given_u(inputs):
    p = inputs["parametrization"]
    return None if isinstance(p, str) else [num(x) for x in p["u"]]


def check_unclamp(c, ref):
    m = ss.from_dict(c["model"])
    r = m.unclamp_right([num(x) for x in c["inputs"]["new_right_knots"]])
    same("points", pad3(r["points"]), ref["points"])
    same("knots", r["knots"], ref["knots"])


def check_extend_curve(c, ref):
    m = ss.from_dict(c["model"])
    r = m.extend(c["inputs"]["targets"], u=given_u(c["inputs"]))
    ext = r["curve"]
    same("u", r["u"], ref["u"])
    same("unclamp_knots", r["unclamp_knots"], ref["unclamp_knots"])
    same("unclamped_points", pad3(r["unclamped_points"]), ref["unclamped_points"])
    same("points", pad3(ext.points), ref["points"])
    same("knots", ext.knots, ref["knots"])
    same("knots_normalized", r["knots_normalized"], ref["knots_normalized"])
    e = ext.evaluate([float(s["t"]) for s in c["expected"]["samples"]], device="cpu")
    same("samples", np.hstack([e["point"], e["d1"]]), ref["samples"])


def check_extend_surface(c, ref):
    m = ss.from_dict(c["model"])
    r = m.extend_u(c["inputs"]["target_curves"], u=given_u(c["inputs"]))
    ext = r["surface"]
    same("u", r["u"], ref["u"])
    same("points", ext.points.reshape(-1, 3), ref["points"])
    same("knots_u", ext.knots[0], ref["knots_u"])
    same("knots_v", ext.knots[1], ref["knots_v"])
    same("knots_normalized_u", r["knots_normalized_u"], ref["knots_normalized_u"])
    st = [[float(s["t"]), float(s["s"])] for s in c["expected"]["samples"]]
    e = ext.evaluate(st, device="cpu")
    same("samples", np.hstack([e["point"], e["du"], e["dv"]]), ref["samples"])


def check_validation(c, ref):
    if ref["valid"]:
        ss.from_dict(c["model"])
        return
    with pytest.raises(ValueError) as info:
        ss.from_dict(c["model"])
    assert isinstance(info.value, ss.ModelError)
    assert info.value.field == ref["field"]
    assert ref["field"] in str(info.value)


CHECKERS = {
    "curve": check_curve,
    "surface": check_surface,
    "basis.xuwang": check_basis,
    "basis.gb": check_basis,
    "basis.singular_blend": check_basis,
    "basis.ubp": check_basis,
    "basis.gubp": check_basis,
    "gb_modify": check_gb_modify,
    "bspline_unclamp": check_unclamp,
    "bspline_extend_curve": check_extend_curve,
    "bspline_extend_surface": check_extend_surface,
    "validation": check_validation,
}


def test_every_case_has_a_reference():
    ids = {p.values[0]["id"] for p in CASES}
    assert ids == set(REFERENCE), "the C++ reference and the golden files list other cases"
    assert len(ids) >= 50


@pytest.mark.parametrize("case", CASES)
def test_golden_case_equals_cpp(case):
    CHECKERS[case["family"]](case, REFERENCE[case["id"]])
