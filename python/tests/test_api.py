"""Models from files, dicts and NumPy keywords; sample() shapes and dtypes; lists; tools."""
import numpy as np
import pytest

import shapespline as ss
from conftest import MODELS, model


def test_file_dict_and_keywords_give_the_same_model():
    f = model("butterfly_aeb.json")
    d = ss.from_dict(f.to_dict())
    k = ss.Curve(np.asarray(f.points), construction="alpha_eb", degree=f.degree, lambda_=f.lambda_,
                 alpha=np.asarray(f.alpha), closed=True)
    a = f.sample(16, fields="all", device="cpu")
    for other in (d, k):
        b = other.sample(16, fields="all", device="cpu")
        for key in a:
            assert np.array_equal(a[key], b[key])
    assert isinstance(f, ss.Curve) and f.kind == "curve" and f.closed


def test_scalar_alpha_expands_and_surface_keywords():
    pts = np.random.default_rng(1).normal(size=(5, 6, 3))
    s1 = ss.Surface(pts, construction="alpha_eb", degree=5, alpha=0.5, closed=(False, True), lambda_=-1)
    s2 = ss.Surface(pts, construction="alpha_eb", degree=5, alpha=np.full((5, 6), 0.5), closed=[False, True], lambda_=-1)
    assert s1.shape == (5, 6) and s1.closed == (False, True)
    assert np.array_equal(s1.alpha, np.full(30, 0.5))
    assert np.array_equal(s1.sample(4, device="cpu")["point"], s2.sample(4, device="cpu")["point"])
    assert np.array_equal(s1.points, pts)


def test_sample_shapes_and_dtypes():
    c = model("butterfly_aeb.json")
    r = c.sample(33, fields=("point", "d1"), device="cpu")
    assert set(r) == {"point", "d1"}
    assert r["point"].shape == (c.item_count, 33, 3) and r["point"].dtype == np.float64
    assert r["point"].flags.c_contiguous and r["point"].flags.writeable
    s = model("surface_aeb.json")
    r, rep = s.sample((5, 7), fields="all", device="cpu", precision="float", report=True)
    assert set(r) == {"point", "du", "dv", "duu", "duv", "dvv", "normal"}
    assert r["normal"].shape == (s.item_count, 5, 7, 3) and r["normal"].dtype == np.float32
    assert rep.device == "cpu" and not rep.gpu and rep.computed_precision == "double" and rep.output_precision == "float"
    # A flat view needs no copy.
    flat = r["point"].reshape(-1, 3)
    assert np.shares_memory(flat, r["point"])


def test_sample_item_range_and_grid_placement():
    s = model("surface_aeb.json")
    whole = s.sample((6, 4), device="cpu")["point"]
    part = s.sample((6, 4), device="cpu", first_item=2, item_count=3)["point"]
    assert np.array_equal(part, whole[2:5])
    # Grid samples sit at u_a = a/(Su-1), v_b = b/(Sv-1) of each patch (u outer, row-major patches).
    (pu0, pu1), (pv0, pv1) = s.patches
    i, j = pu0 + 1, pv0 + 2
    item = (i - pu0) * (pv1 - pv0 + 1) + (j - pv0)
    e = s.evaluate(patch=[[i, j]], uv=[[3 / 5, 1 / 3]], device="cpu")
    assert np.allclose(whole[item, 3, 1], e["point"][0], rtol=0, atol=1e-13)


def test_chunks_equal_sample_bitwise():
    s = model("surface_aeb.json")
    whole = s.sample((40, 30), fields=("point", "normal"), device="cpu")
    got = {k: np.empty_like(v).reshape(-1, 3) for k, v in whole.items()}
    seen = 0
    with s.sample_chunks((40, 30), fields=("point", "normal"), device="cpu", chunk_points=500) as it:
        for ch in it:
            n = ch["point"].shape[0]
            assert ch["first_point"] == seen
            for k in got:
                got[k][seen : seen + n] = ch[k]
            seen += n
        assert it.report is not None and it.report.device == "cpu"
    assert seen == whole["point"].size // 3
    for k in whole:
        assert np.array_equal(got[k], whole[k].reshape(-1, 3))


def test_evaluate_global_and_local_agree():
    c = model("butterfly_aeb.json")
    u0, u1 = c.parameter_range
    u = np.linspace(u0, u1, 101)
    g = c.evaluate(u, device="cpu")
    assert g["point"].shape == (101, 3)
    span = np.minimum(np.floor(u).astype(int), c.spans[1])
    loc = c.evaluate(span=span, t=u - span, device="cpu")
    assert np.allclose(g["point"], loc["point"], atol=1e-12)
    s = model("surface_aeb.json")
    e = s.evaluate(np.array([[0.25, 0.5], [1.5, 1.5]]), device="cpu")
    assert np.allclose(np.linalg.norm(e["normal"], axis=1), 1.0)


def test_evaluate_fields_are_the_full_evaluations_own():
    s = model("nurbs_torus.json")
    uv = np.random.default_rng(5).random((200, 2))
    full = s.evaluate(uv, device="cpu")
    lean = s.evaluate(uv, device="cpu", fields=["du", "dv"])  # the lean list kernel
    assert sorted(lean) == ["du", "dv", "point"]
    for k in lean:
        assert np.array_equal(lean[k], full[k]), k
    assert sorted(s.evaluate(uv, device="cpu", fields="point")) == ["point"]
    assert sorted(s.evaluate(uv, device="cpu", fields=["normal"])) == ["normal", "point"]
    c = model("clamped_bspline.json")
    u = np.linspace(0.0, 1.0, 33)
    cf, cl = c.evaluate(u, device="cpu"), c.evaluate(u, device="cpu", fields="d1")
    assert sorted(cl) == ["d1", "point"] and np.array_equal(cl["d1"], cf["d1"])
    with pytest.raises(ValueError, match="fields"):
        s.evaluate(uv, device="cpu", fields=["d1"])


def test_basis_tables_partition_of_unity():
    t = np.linspace(0, 1, 21)
    for fam, kw in [("xuwang", {"degree": 5, "lambda_": -3}), ("gb", {"lambda_": 2}), ("ubp", {"order": 6, "lambda_": -3}),
                    ("gubp", {"order": 5, "mu": [0.25, 0.5, 0.25]}), ("bspline", {"order": 4})]:
        b = ss.basis(fam, t, **kw)
        assert np.allclose(b["values"].sum(axis=1), 1.0, atol=1e-13), fam
        assert np.allclose(b["d1"].sum(axis=1), 0.0, atol=1e-11), fam
    s = ss.basis("singular_blend", t)
    assert s["values"].shape == (21, 1) and s["values"][0, 0] == 0 and s["values"][-1, 0] == 1


def test_gb_paths_are_straight_and_modification_hits_the_target():
    c = model("gb_curve.json")
    t = np.array([0.25, 0.5, 0.75])
    p = c.gb_lambda_path(2, t)
    for lam in (-6.0, -2.0, 3.0, 20.0):
        w = 12 / (12 + lam)
        assert np.allclose(c.gb_span_points(2, lam, t), w * p["c0"] + (1 - w) * p["e"], atol=1e-12)
    target = c.gb_span_points(1, 4.0, [0.4])[0]
    r = c.gb_constrained_modify(1, target)
    assert r["reachable"] and abs(r["lambda0"] - 4.0) < 1e-6
    hit = r["curve"].evaluate(span=1, t=r["t0"], device="cpu")["point"][0, :2]
    assert np.allclose(hit, target, atol=1e-9)
    far = c.gb_constrained_modify(1, [100.0, -100.0])
    assert not far["reachable"] and far["reason"] and far["curve"] is None


def test_extension_passes_through_the_targets():
    c = model("clamped_bspline.json")
    for targets in ([[10, 5]], [[10, 5], [12, 3]]):
        r = c.extend(targets)
        ext = r["curve"]
        assert ext.points.shape == (c.points.shape[0] + len(targets), 2)
        got = ext.evaluate(r["u"], device="cpu")["point"][:, :2]
        assert np.allclose(got, targets, atol=1e-9)
        # Unchanged on the original range.
        u = np.linspace(*c.parameter_range, 11)
        assert np.allclose(ext.evaluate(u * 0.999, device="cpu")["point"], c.evaluate(u * 0.999, device="cpu")["point"], atol=1e-9)


def test_tessellation_cpu_mesh():
    s = model("surface_aeb.json")
    v, i = s.tessellate(4, device="cpu")
    assert v.dtype == np.float32 and v.shape[1] == 8 and i.dtype == np.uint32 and i.shape[1] == 3
    assert i.max() < v.shape[0] and np.allclose(np.linalg.norm(v[:, 3:6], axis=1), 1, atol=1e-5)
    # Watertight: every interior edge is shared by exactly two triangles.
    edges = np.sort(np.concatenate([i[:, [0, 1]], i[:, [1, 2]], i[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert counts.max() == 2


def test_to_dict_save_and_devices(tmp_path):
    c = model("open_aeb.json")
    p = tmp_path / "m.json"
    c.save(str(p))
    assert np.array_equal(ss.load(str(p)).sample(8, device="cpu")["point"], c.sample(8, device="cpu")["point"])
    assert isinstance(ss.devices(), str)
    assert ss.__version__.count(".") == 2
