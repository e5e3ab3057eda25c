"""Rational B-splines (docs/math.md §10.8) against an exact rational reference: the NURBS basis, the
homogeneous sums and the quotient rule computed in Python fractions from the very floats the model
holds, so the only error left is shapespline's rounding. The quadratic NURBS circle lies on the
circle; a rational surface's point and its first and second derivatives match at random
parameters, on the CPU and, where a Vulkan device exists, on the GPU."""
import math
import random
from fractions import Fraction as F

import numpy as np
import pytest

import shapespline as ss
from conftest import FP32_REL, FP64_REL

H = math.sqrt(0.5)
CIRCLE = [(1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1), (1, 0)]
CIRCLE_W = [1, H, 1, H, 1, H, 1, H, 1]
CIRCLE_KNOTS = [0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1]


def basis(knots, order, t):
    """[(N_i, N_i', N_i'')] of every basis function at t by Cox-de Boor in exact arithmetic; the span
    is the one findKnotSpan picks (the last non-empty one at the right end)."""
    k = [F(x) for x in knots]
    n = len(k) - order
    t = F(t)
    span = n - 1
    if t < k[n]:
        span = max(j for j in range(order - 1, n) if k[j] <= t)
    else:
        while k[span] == k[span + 1]:
            span -= 1

    def N(i, p, d):
        # d-th derivative of N_{i,p} (degree p), the recursion of The NURBS Book eq. 2.5 / 2.9.
        if d > p:
            return F(0)
        if p == 0:
            return F(1) if i == span else F(0)
        a = k[i + p] - k[i]
        b = k[i + p + 1] - k[i + 1]
        if d == 0:
            left = (t - k[i]) / a * N(i, p - 1, 0) if a else F(0)
            right = (k[i + p + 1] - t) / b * N(i + 1, p - 1, 0) if b else F(0)
            return left + right
        left = p / a * N(i, p - 1, d - 1) if a else F(0)
        right = p / b * N(i + 1, p - 1, d - 1) if b else F(0)
        return left - right

    return [[N(i, order - 1, d) for d in range(3)] for i in range(n)]


def rational_curve(points, weights, knots, order, t):
    """Point, d1, d2 of the rational curve at t, exactly."""
    B = basis(knots, order, t)
    dim = len(points[0])
    A = [[sum(B[i][d] * F(weights[i]) * F(points[i][c]) for i in range(len(points))) for c in range(dim)] for d in range(3)]
    W = [sum(B[i][d] * F(weights[i]) for i in range(len(points))) for d in range(3)]
    C0 = [a / W[0] for a in A[0]]
    C1 = [(A[1][c] - W[1] * C0[c]) / W[0] for c in range(dim)]
    C2 = [(A[2][c] - 2 * W[1] * C1[c] - W[2] * C0[c]) / W[0] for c in range(dim)]
    return C0, C1, C2


def rational_surface(P, Wt, ku, kv, order, u, v):
    """Point and the five partials (du, dv, duu, duv, dvv) of a rational surface at (u, v), exactly."""
    Bu, Bv = basis(ku, order, u), basis(kv, order, v)
    rows, cols = len(P), len(P[0])
    orders = [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)]
    A, W = [], []
    for du, dv in orders:
        A.append([sum(Bu[i][du] * Bv[j][dv] * F(Wt[i][j]) * F(P[i][j][c]) for i in range(rows) for j in range(cols))
                  for c in range(3)])
        W.append(sum(Bu[i][du] * Bv[j][dv] * F(Wt[i][j]) for i in range(rows) for j in range(cols)))
    S = [a / W[0] for a in A[0]]
    Su = [(A[1][c] - W[1] * S[c]) / W[0] for c in range(3)]
    Sv = [(A[2][c] - W[2] * S[c]) / W[0] for c in range(3)]
    Suu = [(A[3][c] - 2 * W[1] * Su[c] - W[3] * S[c]) / W[0] for c in range(3)]
    Suv = [(A[4][c] - W[1] * Sv[c] - W[2] * Su[c] - W[4] * S[c]) / W[0] for c in range(3)]
    Svv = [(A[5][c] - 2 * W[2] * Sv[c] - W[5] * S[c]) / W[0] for c in range(3)]
    return {"point": S, "du": Su, "dv": Sv, "duu": Suu, "duv": Suv, "dvv": Svv}


def devices(gpu):
    out = [("cpu", "double", 8 * FP64_REL)]
    if gpu is not None:
        out.append(("vulkan", "float", 64 * FP32_REL))
        if gpu["fp64"]:
            out.append(("vulkan", "double", 64 * FP64_REL))
    return out


@pytest.fixture
def maybe_gpu(request):
    try:
        return request.getfixturevalue("gpu")
    except pytest.skip.Exception:
        return None


def test_circle_is_exact_and_matches_the_rational_reference(maybe_gpu):
    c = ss.Curve(np.array(CIRCLE, float), construction="bspline", order=3, knots=CIRCLE_KNOTS, weights=CIRCLE_W)
    assert np.array_equal(c.weights, CIRCLE_W)
    rng = random.Random(11)
    us = [0.0, 0.25, 0.5, 1.0] + [rng.random() for _ in range(12)]
    ref = [rational_curve(CIRCLE, CIRCLE_W, CIRCLE_KNOTS, 3, u) for u in us]
    for device, precision, rel in devices(maybe_gpu):
        got = c.evaluate(np.array(us), device=device, precision=precision, require=device != "cpu")
        radius = np.linalg.norm(got["point"], axis=1)
        assert np.max(np.abs(radius - 1.0)) <= (1e-15 if precision == "double" else 1e-6), (device, precision)
        for k, (C0, C1, C2) in enumerate(ref):
            for field, exact in (("point", C0), ("d1", C1), ("d2", C2)):
                want = np.array([float(x) for x in exact] + [0.0] * (3 - len(exact)))
                err = np.max(np.abs(got[field][k] - want))
                assert err <= rel * (1.0 + np.linalg.norm(want)), (device, precision, field, us[k], err)


def test_rational_surface_derivatives_match_the_rational_reference(maybe_gpu):
    R, r = 3.0, 1.25
    P = [[((R + r * d[0]) * c[0], (R + r * d[0]) * c[1], r * d[1]) for d in CIRCLE] for c in CIRCLE]
    Wt = [[wi * wj for wj in CIRCLE_W] for wi in CIRCLE_W]
    Wt[4][4] = 2.5  # a general rational surface, no longer a torus
    s = ss.Surface(np.array(P), construction="bspline", order=[3, 3], knots=[CIRCLE_KNOTS, CIRCLE_KNOTS],
                   weights=np.array(Wt))
    rng = random.Random(5)
    uv = [(rng.random(), rng.random()) for _ in range(6)] + [(0.25, 0.5), (1.0, 0.0)]
    ref = [rational_surface(P, Wt, CIRCLE_KNOTS, CIRCLE_KNOTS, 3, u, v) for u, v in uv]
    for device, precision, rel in devices(maybe_gpu):
        got = s.evaluate(np.array(uv), device=device, precision=precision, require=device != "cpu")
        for k, exact in enumerate(ref):
            for field, value in exact.items():
                want = np.array([float(x) for x in value])
                err = np.max(np.abs(got[field][k] - want))
                assert err <= rel * (R + r + np.linalg.norm(want)), (device, precision, field, uv[k], err)


def test_torus_tessellates_onto_the_torus(maybe_gpu):
    """A rational surface with double knots (empty intervals, which get no patch) tessellates on
    every device: every vertex on the torus to fp32 precision, uv the knot parameters, and the GPU
    mesh the CPU one (uv within 2 fp32 ulps: an fp32 GPU forms t_i + u h_i in fp32)."""
    R, r = 3.0, 1.25
    P = [[((R + r * d[0]) * c[0], (R + r * d[0]) * c[1], r * d[1]) for d in CIRCLE] for c in CIRCLE]
    Wt = [[wi * wj for wj in CIRCLE_W] for wi in CIRCLE_W]
    s = ss.Surface(np.array(P), construction="bspline", order=[3, 3], knots=[CIRCLE_KNOTS, CIRCLE_KNOTS],
                   weights=np.array(Wt))
    meshes = {}
    for device, precision, _ in devices(maybe_gpu):
        v, tri = s.tessellate(6, device=device, precision=precision, require=device != "cpu")
        assert v.shape == ((4 * 6 + 1) ** 2, 8) and tri.shape == (2 * (4 * 6) ** 2, 3), (device, v.shape, tri.shape)
        p = v[:, :3].astype(np.float64)
        tube = np.hypot(np.hypot(p[:, 0], p[:, 1]) - R, p[:, 2])
        assert np.max(np.abs(tube - r)) <= 1e-6 * (R + r), (device, precision)
        assert np.allclose(np.linalg.norm(v[:, 3:6], axis=1), 1.0, atol=1e-5)
        assert v[:, 6:].min() == 0.0 and v[:, 6:].max() == 1.0
        meshes[(device, precision)] = (v, tri)
    vc, ic = meshes[("cpu", "double")]
    for (device, precision), (v, tri) in meshes.items():
        assert np.array_equal(tri, ic)
        assert np.abs(v[:, 6:] - vc[:, 6:]).max() <= 2 * np.finfo(np.float32).eps, (device, precision)
        assert np.abs(v[:, :3] - vc[:, :3]).max() <= 4 * FP32_REL * (R + r), (device, precision)


def test_bad_weights_name_the_entry():
    pts = np.array(CIRCLE, float)
    for w, rule in ((0.0, "positive"), (-1.0, "positive"), (math.inf, "finite")):
        weights = list(CIRCLE_W)
        weights[3] = w
        with pytest.raises(ValueError, match=r"weights\[3\].*" + rule):
            ss.Curve(pts, construction="bspline", order=3, knots=CIRCLE_KNOTS, weights=weights)
    with pytest.raises(ValueError, match="weights"):
        ss.Curve(pts, construction="extended_bspline", degree=4, weights=CIRCLE_W)
