"""NumPy arrays go to the core as arrays (issue 31, part 2): Surface(points=array), Curve(...) and
from_dict with arrays give bit for bit the model the same numbers give as lists (the JSON path),
and bad arrays get the file parser's messages: the field, with the index of a non-finite value."""
import math

import numpy as np
import pytest

import shapespline as ss


def net(n=6, m=7):
    i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
    return np.stack([i, j, np.sin(0.7 * i) * np.cos(0.4 * j)], axis=-1).astype(float)


def same_samples(a, b, grid):
    sa, sb = a.sample(grid, fields="all", device="cpu"), b.sample(grid, fields="all", device="cpu")
    assert sa.keys() == sb.keys()
    for k in sa:
        assert np.array_equal(sa[k], sb[k]), k


def test_arrays_and_lists_give_the_same_model():
    P = net()
    al = np.random.default_rng(5).uniform(0.1, 1.0, P.shape[:2])
    a = ss.Surface(P, construction="alpha_eb", degree=5, alpha=al)
    b = ss.Surface(P.tolist(), construction="alpha_eb", degree=5, alpha=al.tolist())
    assert np.array_equal(a.points, P)
    same_samples(a, b, (5, 4))
    # Other dtypes and layouts are converted: int, float32, a Fortran-order or strided view.
    for Q in (P.astype(np.int64), P.astype(np.float32), np.asfortranarray(P), P[:, ::1, :].copy()[::1]):
        c = ss.Surface(Q, construction="extended_bspline", degree=4)
        d = ss.Surface(np.asarray(Q, float).tolist(), construction="extended_bspline", degree=4)
        same_samples(c, d, (4, 4))
    # A rational curve with array weights, and from_dict with arrays.
    C = np.array([(math.cos(t), math.sin(2 * t)) for t in np.linspace(0, 3, 8)])
    W = np.linspace(0.5, 2.0, 8)
    knots = [0, 0, 0, 0, 0.2, 0.3, 0.5, 0.8, 1, 1, 1, 1]
    e = ss.Curve(C, construction="bspline", order=4, knots=knots, weights=W)
    f = ss.from_dict({"kind": "curve", "construction": "bspline", "order": 4, "knots": knots,
                      "points": C.tolist(), "weights": W.tolist()})
    g = ss.Curve.from_dict({"kind": "curve", "construction": "bspline", "order": 4, "knots": knots,
                            "points": C, "weights": W})
    same_samples(e, f, 9)
    same_samples(g, f, 9)


@pytest.mark.parametrize(
    "points, alpha, field, rule",
    [
        (net()[:, :, :2], 0.5, "points", "(rows, cols, 3)"),
        (net().reshape(-1, 3), 0.5, "points", "(rows, cols, 3)"),
        (np.where(np.arange(126).reshape(6, 7, 3) == 40, np.nan, net()), 0.5, "points[1][6][1]", "finite"),
        (np.where(np.arange(126).reshape(6, 7, 3) == 3, np.inf, net()), 0.5, "points[0][1][0]", "finite"),
        (net(), np.full((6, 5), 0.5), "alpha", "shape (6, 7)"),
        (net(), np.where(np.arange(42).reshape(6, 7) == 8, 1.5, 0.5), "alpha[1][1]", "(0,1]"),
    ],
)
def test_bad_arrays_name_the_field(points, alpha, field, rule):
    with pytest.raises(ss.ModelError) as info:
        ss.Surface(points, construction="alpha_eb", degree=5, alpha=alpha)
    assert info.value.field == field, str(info.value)
    assert rule in str(info.value)


def test_weights_array_is_checked_like_the_file():
    P = net(5, 5)
    knots = [[0, 0, 0, 0, 0.5, 1, 1, 1, 1]] * 2
    W = np.ones((5, 5))
    W[2, 3] = 0.0
    with pytest.raises(ss.ModelError) as info:
        ss.Surface(P, construction="bspline", order=[4, 4], knots=knots, weights=W)
    assert info.value.field == "weights[2][3]"
    with pytest.raises(ss.ModelError) as info:
        ss.Surface(P, construction="bspline", order=[4, 4], knots=knots, weights=np.ones(25))
    assert info.value.field == "weights" and "shape (5, 5)" in str(info.value)
