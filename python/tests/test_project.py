"""Surface.project, Curve.project and Part.project (docs/python.md "Closest points"): the nearest
points of a cloud, against what is known exactly: a circle's nearest point is along the ray from its
centre, a cube's signed distance is a box's, and a surface's own samples come back at distance ~0 at
their parameters. Bad clouds raise ValueError naming points."""
import numpy as np
import pytest

import shapespline as ss
from test_part import write_cube

CIRCLE = [[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]]
CIRCLE_KNOTS = [0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1]
CIRCLE_W = [1, 2 ** -0.5, 1, 2 ** -0.5, 1, 2 ** -0.5, 1, 2 ** -0.5, 1]


def test_circle_feet_lie_along_the_ray_from_the_centre():
    c = ss.Curve(np.array(CIRCLE, float), construction="bspline", order=3, knots=CIRCLE_KNOTS, weights=CIRCLE_W)
    rng = np.random.default_rng(3)
    q = np.column_stack([rng.uniform(-2, 2, 500), rng.uniform(-2, 2, 500), rng.uniform(-0.5, 0.5, 500)])
    r = c.project(q)
    assert set(r) == {"point", "t", "distance"}
    radial = np.hypot(q[:, 0], q[:, 1])
    exact = np.hypot(radial - 1.0, q[:, 2])
    assert np.max(np.abs(r["distance"] - exact)) <= 1e-12
    assert np.allclose(r["point"][:, :2], q[:, :2] / radial[:, None], atol=1e-9)
    assert np.allclose(c.evaluate(r["t"])["point"], r["point"], rtol=0, atol=1e-14)


def test_surface_samples_come_back_at_their_parameters():
    net = np.array([[[i, j, 0.3 * np.sin(i + 2 * j)] for j in range(6)] for i in range(7)], float)
    s = ss.Surface(net, construction="bspline", order=(4, 4))
    points = s.sample(5)["point"].reshape(-1, 3)
    r = s.project(points)
    assert r["distance"].max() <= 1e-12 * np.linalg.norm(net.max((0, 1)) - net.min((0, 1)))
    back = s.evaluate(r["uv"])["point"]
    assert np.allclose(back, r["point"], atol=1e-12)
    assert np.allclose(np.linalg.norm(r["normal"], axis=1), 1.0)
    assert np.array_equal(np.abs(r["signed_distance"]), r["distance"])


def test_cube_signed_distance_is_the_box_distance(tmp_path):
    part = ss.load_part(str(write_cube(tmp_path)))
    rng = np.random.default_rng(5)
    q = rng.uniform(-1, 3, (2000, 3))
    r = part.project(q, threads=2)
    d = np.abs(q - 1.0) - 1.0
    outside = np.linalg.norm(np.maximum(d, 0), axis=1)
    exact = np.where(outside > 0, outside, d.max(axis=1))
    assert np.max(np.abs(r["signed_distance"] - exact)) <= 1e-12
    assert r["face_ids"].dtype == np.int32 and set(r["face_ids"].tolist()) <= {1, 2, 3, 4, 5, 6}


@pytest.mark.parametrize("points, named", [
    (np.zeros((0, 3)), "no points"),
    (np.zeros((4, 2)), "(n, 3)"),
    (np.array([[0.0, np.nan, 0.0]]), "points[0]"),
    ("abc", "points"),
])
def test_bad_clouds_name_points(tmp_path, points, named):
    part = ss.load_part(str(write_cube(tmp_path)))
    with pytest.raises(ValueError) as e:
        part.project(points)
    assert named in str(e.value)


def test_tolerance_keeps_every_foot_within_it(tmp_path):
    part = ss.load_part(str(write_cube(tmp_path)))
    q = np.random.default_rng(6).uniform(-1, 3, (2000, 3))
    exact = part.project(q)["distance"]
    loose = part.project(q, tolerance=1e-3)["distance"]
    assert np.all(loose <= exact + 1e-3) and np.all(loose >= exact - 1e-12)


@pytest.mark.parametrize("tolerance", [0.0, -1.0, float("nan"), float("inf")])
def test_bad_tolerance_names_it(tmp_path, tolerance):
    part = ss.load_part(str(write_cube(tmp_path)))
    with pytest.raises(ValueError) as e:
        part.project(np.zeros((1, 3)), tolerance=tolerance)
    assert "tolerance" in str(e.value)


def test_vulkan_search_gives_the_cpu_feet(tmp_path, gpu):
    # The search on the device, each foot finished on the CPU: fp64 the CPU's distances to 1e-12 of
    # the part's size, fp32 within 64 ulps of it (docs/math.md "Closest points", on the GPU).
    part = ss.load_part(str(write_cube(tmp_path)))
    rng = np.random.default_rng(9)
    q = rng.uniform(-1.0, 3.0, (2000, 3))
    cpu = part.project(q)
    for precision, bound in [("double", 1e-12), ("float", 64 * 2.0 ** -24)]:
        if precision == "double" and not gpu["fp64"]:
            continue
        dev = part.project(q, device="vulkan", precision=precision, require=True)
        assert np.max(np.abs(dev["distance"] - cpu["distance"])) <= bound * part.diagonal
        assert np.all(np.isfinite(dev["normal"]))


def test_curve_search_stays_on_the_cpu():
    c = ss.Curve(np.array(CIRCLE, float), construction="bspline", order=3, knots=CIRCLE_KNOTS, weights=CIRCLE_W)
    q = np.array([[2.0, 0.0, 0.0]])
    assert c.project(q, device="auto")["distance"][0] == pytest.approx(1.0, abs=1e-12)
    with pytest.raises(RuntimeError, match="curve run on the CPU only"):
        c.project(q, device="vulkan", require=True)
