#!/usr/bin/env python3
"""Reproduces the papers' figures with the shapespline Python module and matplotlib (Agg backend).

    python3 examples/python/figures.py OUTPUT_FOLDER [--device auto|vulkan|cpu]

Writes six PNGs (docs/figures/ holds the committed ones; README.md shows them):

  xuwang_degrees.png    Xu-Wang extended cubic B-spline curves of degree 4, 5, 6 for
                        lambda = -4, -3, -2, -1, 0, 1 (one panel per degree, one control polygon)
  butterfly_alpha.png   the butterfly-like closed alpha-EB curve (examples/models/butterfly_aeb.json)
                        at several alpha
  surface_lambda.png    the alpha-EB surface (examples/models/surface_aeb.json) at lambda = -2, 0, 1
  ubp_gubp_basis.png    UBP bell functions of order 4 and 6 for several lambda, GUBP of order 5 for
                        several mu
  gb_lambda_paths.png   a GB curve (examples/models/gb_curve.json) with its straight lambda-paths, and
                        the constrained modification through a target point (as `shapespline gb-fit`)
  bspline_extension.png a clamped B-spline curve (examples/models/clamped_bspline.json) extended to
                        one and to two target points (as `shapespline extend`)

Mathematics: docs/math.md. Run from anywhere; the models are found relative to this file.
"""
import argparse
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import shapespline as ss  # noqa: E402

MODELS = pathlib.Path(__file__).resolve().parents[1] / "models"
LAMBDAS = [-4, -3, -2, -1, 0, 1]
DPI = 110


def save(fig, path):
    """Lays the figure out, writes it as a PNG and frees it."""
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def equal_with_grid(axes):
    """Equal axis scales (curves keep their shape) and a light grid on every panel."""
    for ax in axes:
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)


def polyline(curve, samples, device):
    """The sampled curve as one (N, 3) polyline (the shared span ends appear once)."""
    p = curve.sample(samples, device=device)["point"]
    return np.concatenate([p[0]] + [s[1:] for s in p[1:]])


def control_polygon(ax, pts, closed=False, **kw):
    p = np.asarray(pts)
    if closed:
        p = np.vstack([p, p[:1]])
    ax.plot(p[:, 0], p[:, 1], "--o", color="0.55", lw=0.8, ms=3, zorder=1, **kw)


def lambda_colors(n):
    return plt.cm.viridis(np.linspace(0.0, 0.9, n))


def xuwang_degrees(out, device):
    pts = np.array([[0, 0], [1, 3], [3, 4], [4.5, 1], [6, 0.5], [7.5, 3.5], [9, 4], [10, 1]], dtype=float)
    fig, axes = plt.subplots(1, 3, figsize=(15, 3.4))
    for ax, degree in zip(axes, (4, 5, 6)):
        control_polygon(ax, pts, label="control polygon")
        for lam, col in zip(LAMBDAS, lambda_colors(len(LAMBDAS))):
            c = ss.Curve(pts, construction="extended_bspline", degree=degree, lambda_=lam)
            p = polyline(c, 64, device)
            ax.plot(p[:, 0], p[:, 1], color=col, lw=1.6, label=f"λ = {lam}")
        ax.set_title(f"Xu–Wang extended cubic B-spline, degree {degree}")
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="upper left")
    save(fig, out / "xuwang_degrees.png")


def butterfly_alpha(out, device):
    base = ss.load(str(MODELS / "butterfly_aeb.json"))
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.6))
    variants = [(f"α = {a:g} at every vertex", a) for a in (1.0, 0.6, 0.3, 0.15)]
    ax = axes[0]
    control_polygon(ax, base.points, closed=True)
    for (label, a), col in zip(variants, plt.cm.plasma(np.linspace(0.0, 0.8, len(variants)))):
        c = base.copy()
        c.set_alpha(a)
        p = polyline(c, 48, device)
        ax.plot(p[:, 0], p[:, 1], color=col, lw=1.5, label=label)
    ax.set_title(f"butterfly α-EB curve (degree {base.degree}, λ = {base.lambda_:g}), uniform α")
    ax.legend(fontsize=8, loc="lower right")
    ax = axes[1]
    control_polygon(ax, base.points, closed=True)
    p = polyline(base, 48, device)
    ax.plot(p[:, 0], p[:, 1], color="tab:red", lw=1.8, label="α of the model file (1 at the body)")
    for lam, col in zip((-6, 0, 1), ("tab:blue", "tab:green", "tab:orange")):
        c = base.copy()
        c.set_lambda(lam)
        q = polyline(c, 48, device)
        ax.plot(q[:, 0], q[:, 1], color=col, lw=1.0, alpha=0.8, label=f"same α, λ = {lam}")
    ax.set_title("butterfly α-EB curve, per-vertex α")
    ax.legend(fontsize=8, loc="lower right")
    equal_with_grid(axes)
    save(fig, out / "butterfly_alpha.png")


def surface_lambda(out, device):
    s = ss.load(str(MODELS / "surface_aeb.json"))
    net = s.points
    fig = plt.figure(figsize=(18, 4.8))
    sections = []
    (u0, u1), (v0, v1) = s.parameter_range
    mid_v = 0.5 * (v0 + v1)
    uu = np.linspace(u0, u1, 300)
    for k, lam in enumerate((-2, 0, 1)):
        s.set_lambda(lam)  # on the GPU: rewrites the parameter block only, the net stays resident
        v, tri = s.tessellate(12, device=device)
        ax = fig.add_subplot(1, 4, k + 1, projection="3d")
        ax.plot_trisurf(v[:, 0], v[:, 1], v[:, 2], triangles=tri, cmap="viridis", linewidth=0, antialiased=True,
                        alpha=0.95)
        for row in net:
            ax.plot(row[:, 0], row[:, 1], row[:, 2], color="0.3", lw=0.6)
        for col in net.transpose(1, 0, 2):
            ax.plot(col[:, 0], col[:, 1], col[:, 2], color="0.3", lw=0.6)
        ax.scatter(net[..., 0], net[..., 1], net[..., 2], color="k", s=6)
        ax.set_title(f"α-EB surface, λ = {lam}", pad=2)
        ax.view_init(elev=28, azim=-60)
        sections.append((lam, s.evaluate(np.column_stack([uu, np.full_like(uu, mid_v)]), device=device)["point"]))
    ax = fig.add_subplot(1, 4, 4)
    for (lam, p), col in zip(sections, ("tab:blue", "tab:green", "tab:orange")):
        ax.plot(p[:, 0], p[:, 2], color=col, lw=1.6, label=f"λ = {lam}")
    ax.set_title(f"section V = {mid_v:g} (x, z)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save(fig, out / "surface_lambda.png")


def ubp_gubp_basis(out):
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.3))
    for ax, order, lams in ((axes[0], 4, (-8, -4, -2, 0, 1)), (axes[1], 6, (-3, -2, -1, 0, 1))):
        x = np.linspace(0, order, 601)
        for lam, col in zip(lams, lambda_colors(len(lams))):
            try:
                b = ss.bell("ubp", x, order=order, lambda_=lam)
            except ValueError:  # below lambda_min(k)
                continue
            ax.plot(x, b["N"], color=col, lw=1.5, label=f"λ = {lam}")
        ax.set_title(f"UBP bell function N(x), order {order}")
        ax.legend(fontsize=8)
        ax.set_xlabel("x")
        ax.grid(alpha=0.3)
    ax = axes[2]
    x = np.linspace(0, 5, 601)
    for mu, col in zip(([0.25, 0.5, 0.25], [0.5, 0.25, 0.25], [0.1, 0.8, 0.1], [0.0, 1.0, 0.0], [0.5, 0.5, 0.0]),
                       plt.cm.plasma(np.linspace(0, 0.8, 5))):
        b = ss.bell("gubp", x, order=5, mu=mu)
        ax.plot(x, b["N"], color=col, lw=1.5, label=f"μ = {mu}")
    ax.set_title("GUBP bell function N(x), order 5")
    ax.legend(fontsize=8)
    ax.set_xlabel("x")
    ax.grid(alpha=0.3)
    save(fig, out / "ubp_gubp_basis.png")


def gb_lambda_paths(out, device):
    c = ss.load(str(MODELS / "gb_curve.json"))
    fig, axes = plt.subplots(1, 2, figsize=(14, 5.2))
    ax = axes[0]
    control_polygon(ax, c.points)
    span = 2
    t = np.linspace(0, 1, 9)
    path = c.gb_lambda_path(span, t)
    for k in range(t.size):  # the straight lambda-path of each t: from C(-8, t) through C(0, t) towards E(t)
        seg = np.vstack([path["c_minus8"][k], path["e"][k]])
        ax.plot(seg[:, 0], seg[:, 1], color="0.4", lw=0.8)
        ax.plot(*path["c0"][k], "k.", ms=4)
    for lam, col in zip((-6, -3, 0, 4, 50), lambda_colors(5)):
        g = c.copy()
        g.set_lambda(lam)
        p = polyline(g, 64, device)
        ax.plot(p[:, 0], p[:, 1], color=col, lw=1.4, label=f"λ = {lam}")
    ax.set_title(f"GB curve and the straight λ-paths of span {span}")
    ax.legend(fontsize=8, loc="lower right")
    ax = axes[1]
    control_polygon(ax, c.points)
    target = np.array([2.5, 2.6])
    fit = c.gb_constrained_modify(1, target)
    p0 = polyline(c, 64, device)
    ax.plot(p0[:, 0], p0[:, 1], color="tab:blue", lw=1.3, label=f"λ = {c.lambda_:g}")
    p1 = polyline(fit["curve"], 64, device)
    ax.plot(p1[:, 0], p1[:, 1], color="tab:red", lw=1.8, label=f"modified: λ0 = {fit['lambda0']:.4f}")
    path = c.gb_lambda_path(1, [fit["t0"]])
    seg = np.vstack([path["c_minus8"][0], path["e"][0]])
    ax.plot(seg[:, 0], seg[:, 1], color="0.4", lw=0.8, label=f"λ-path of t0 = {fit['t0']:.4f}")
    ax.plot(*target, "*", color="k", ms=12, label=f"target {tuple(target)}")
    ax.set_title("constrained modification: span 1 through the target")
    ax.legend(fontsize=8, loc="lower right")
    equal_with_grid(axes)
    save(fig, out / "gb_lambda_paths.png")


def bspline_extension(out, device):
    c = ss.load(str(MODELS / "clamped_bspline.json"))
    fig, axes = plt.subplots(1, 2, figsize=(14, 5))
    u = np.linspace(*c.parameter_range, 400)
    base = c.evaluate(u, device=device)["point"]
    for ax, targets in zip(axes, ([[10, 5]], [[10, 5], [12, 3]])):
        r = c.extend(targets)
        ext = r["curve"]
        ue = np.linspace(*ext.parameter_range, 800)
        p = ext.evaluate(ue, device=device)["point"]
        control_polygon(ax, ext.points, label="extended control polygon")
        ax.plot(p[:, 0], p[:, 1], color="tab:red", lw=2.2, label="extended curve")
        ax.plot(base[:, 0], base[:, 1], color="tab:blue", lw=1.4, label="original curve")
        tg = np.asarray(targets, dtype=float)
        ax.plot(tg[:, 0], tg[:, 1], "*", color="k", ms=12, label="targets")
        ax.set_title(f"clamped cubic B-spline extended to {len(targets)} target point{'s' if len(targets) > 1 else ''}")
        ax.legend(fontsize=8, loc="lower left")
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
    save(fig, out / "bspline_extension.png")


FIGURES = ["xuwang_degrees.png", "butterfly_alpha.png", "surface_lambda.png", "ubp_gubp_basis.png",
           "gb_lambda_paths.png", "bspline_extension.png"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("output", type=pathlib.Path, help="folder for the PNGs (created)")
    ap.add_argument("--device", default="auto", choices=("auto", "vulkan", "cpu"))
    a = ap.parse_args(argv)
    a.output.mkdir(parents=True, exist_ok=True)
    xuwang_degrees(a.output, a.device)
    butterfly_alpha(a.output, a.device)
    surface_lambda(a.output, a.device)
    ubp_gubp_basis(a.output)
    gb_lambda_paths(a.output, a.device)
    bspline_extension(a.output, a.device)
    for name in FIGURES:
        print(a.output / name)
    return 0


if __name__ == "__main__":
    sys.exit(main())
