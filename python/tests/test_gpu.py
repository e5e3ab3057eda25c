"""GPU (Vulkan) against the CPU fp64 path through Python, within tests/support/tolerances.h, and the
resident GPU model: parameter setters re-evaluate without re-uploading the net. Skipped with the
reason when there is no Vulkan device."""
import numpy as np
import pytest

import shapespline as ss
from conftest import FP32_REL, FP64_REL, model, scale_of

MODELS = ["butterfly_aeb.json", "open_aeb.json", "gb_curve.json", "gubp_curve.json", "clamped_bspline.json",
          "surface_aeb.json", "bspline_surface.json", "torus_aeb.json"]


def tolerance(m, precision):
    rel = FP32_REL if precision == "float" else FP64_REL
    g = 1.0 / float(np.min(m.alpha)) if m.alpha.size else 1.0  # alpha-EB: |V| up to scale / alpha_min
    return rel * scale_of(m.points) * g


def precisions(gpu):
    return ["float", "double"] if gpu["fp64"] else ["float"]


@pytest.mark.parametrize("name", MODELS)
def test_grid_gpu_matches_cpu(gpu, name):
    m = model(name)
    grid = 17 if m.kind == "curve" else (9, 7)
    cpu = m.sample(grid, fields="all", device="cpu")
    for precision in precisions(gpu):
        got, rep = m.sample(grid, fields="all", device="vulkan", precision=precision, require=True, report=True)
        assert rep.gpu and rep.computed_precision == precision
        tol = tolerance(m, precision)
        assert np.abs(got["point"] - cpu["point"]).max() <= tol, precision
        if m.kind == "surface":
            # Unit normals: compared where the surface is regular (both partials clearly non-zero).
            ok = (np.linalg.norm(cpu["du"], axis=-1) > 1e-3) & (np.linalg.norm(cpu["dv"], axis=-1) > 1e-3)
            dn = np.abs(got["normal"] - cpu["normal"]).max(axis=-1)[ok]
            assert dn.max() <= (1e-3 if precision == "float" else 1e-9)


@pytest.mark.parametrize("name", ["butterfly_aeb.json", "surface_aeb.json", "clamped_bspline.json"])
def test_lists_gpu_match_cpu(gpu, name):
    m = model(name)
    rng = np.random.default_rng(7)
    if m.kind == "curve":
        u0, u1 = m.parameter_range
        params = rng.uniform(u0, u1, 200)
    else:
        (u0, u1), (v0, v1) = m.parameter_range
        params = np.column_stack([rng.uniform(u0, u1, 200), rng.uniform(v0, v1, 200)])
    cpu = m.evaluate(params, device="cpu")
    for precision in precisions(gpu):
        got = m.evaluate(params, device="vulkan", precision=precision, require=True)
        assert np.abs(got["point"] - cpu["point"]).max() <= tolerance(m, precision)


def test_tessellation_gpu_matches_cpu(gpu):
    s = model("surface_aeb.json")
    vg, ig = s.tessellate(6, device="vulkan", require=True)
    vc, ic = s.tessellate(6, device="cpu")
    assert np.array_equal(ig, ic)
    tol = FP32_REL * scale_of(s.points) / float(np.min(s.alpha))
    assert np.abs(vg[:, :3] - vc[:, :3]).max() <= tol
    assert np.abs(vg[:, 3:6] - vc[:, 3:6]).max() <= 1e-3
    assert np.array_equal(vg[:, 6:], vc[:, 6:])


def test_setters_reuse_the_resident_net(gpu):
    c = model("butterfly_aeb.json")
    c.sample(32, device="vulkan", precision="float", require=True)
    first = c.upload_stats("float")
    assert first["resident"] and first["mirrors_built"] == 1 and first["net_writes"] == 1
    for change in (lambda: c.set_lambda(-3.0), lambda: c.set_alpha(0.25, index=4), lambda: c.set_alpha(np.linspace(0.3, 1, 20))):
        change()
        got = c.sample(32, device="vulkan", precision="float", require=True)["point"]
        st = c.upload_stats("float")
        assert st["mirrors_built"] == 1 and st["net_bytes"] == first["net_bytes"], "the net was re-uploaded"
        fresh = ss.from_dict(c.to_dict())
        assert np.abs(got - fresh.sample(32, device="cpu")["point"]).max() <= tolerance(c, "float")
    assert st["param_writes"] > first["param_writes"]
    # A control point rewrites only the net entries that change (a few, not the whole net).
    c.set_control_point(3, [5.0, 3.5])
    got = c.sample(32, device="vulkan", precision="float", require=True)["point"]
    st2 = c.upload_stats("float")
    assert st2["mirrors_built"] == 1 and 0 < st2["net_bytes"] - st["net_bytes"] < first["net_bytes"]
    fresh = ss.from_dict(c.to_dict())
    assert np.abs(got - fresh.sample(32, device="cpu")["point"]).max() <= tolerance(c, "float")


def test_surface_setters_and_tessellation_reuse_the_net(gpu):
    s = model("surface_aeb.json")
    s.tessellate(4, device="vulkan", require=True)
    first = s.upload_stats("float")
    s.set_lambda(-2.0)
    s.set_alpha(1.0, index=(1, 1))
    s.set_control_point(2, 2, [0.1, 0.2, 1.5])
    v, i = s.tessellate(4, device="vulkan", require=True)
    e = s.evaluate(np.array([[1.0, 1.0], [2.0, 2.0]]), device="vulkan", precision="float")
    st = s.upload_stats("float")
    assert st["mirrors_built"] == 1 and st["net_bytes"] - first["net_bytes"] < first["net_bytes"]
    vc, _ = ss.from_dict(s.to_dict()).tessellate(4, device="cpu")
    assert np.abs(v[:, :3] - vc[:, :3]).max() <= tolerance(s, "float")
    assert np.abs(e["point"] - s.evaluate(np.array([[1.0, 1.0], [2.0, 2.0]]), device="cpu")["point"]).max() <= tolerance(s, "float")


def test_gpu_chunks_match_gpu_sample(gpu):
    s = model("surface_aeb.json")
    whole = s.sample((33, 17), device="vulkan", precision="float", require=True)["point"].reshape(-1, 3)
    parts = [ch["point"] for ch in s.sample_chunks((33, 17), device="vulkan", precision="float", require=True, chunk_points=300)]
    assert len(parts) > 1
    assert np.array_equal(np.concatenate(parts), whole)


def test_mu_setter_on_gubp(gpu):
    c = model("gubp_curve.json")
    c.sample(16, device="vulkan", precision="float", require=True)
    n0 = c.upload_stats("float")["net_bytes"]
    before = c.sample(16, device="vulkan", precision="float")["point"]
    c.set_mu([0.5, 0.25, 0.25])  # order 5: mu_0 + mu_1 + mu_2 = 1 keeps both parity sums at 1
    assert np.array_equal(c.mu, [0.5, 0.25, 0.25])
    got = c.sample(16, device="vulkan", precision="float")["point"]
    assert c.upload_stats("float")["net_bytes"] == n0
    assert np.abs(got - c.sample(16, device="cpu")["point"]).max() <= tolerance(c, "float")
    assert np.abs(got - before).max() > 1e-3
