#!/usr/bin/python3
"""shapespline against SciPy on one knot-vector bicubic B-spline surface (issue 30, part 4).

Workload: a 64 x 64 control net (x, y on a regular grid, smooth random heights, fixed seed), order
4 in u and v, with two knot vectors per direction: "uniform" (0, 1, ..., 67, unclamped: the domain
is [3, 64]) and "clamped" (four-fold end knots 0 and 1, 60 random distinct interior knots, fixed
seed). Both have 61 x 61 = 3,721 patches. Each peer evaluates, for every patch, the S x S grid that
shapespline's Surface.sample((S, S)) evaluates (u_a = a/(S-1) of the knot interval, both ends
included, so neighbouring patches repeat their shared edge) and the same fields: the point and the
partials d/du, d/dv with respect to the knot parameters.

Peers (all measured in the same run, interleaved, best-of-N wall time):
  scipy bisplev       FITPACK, 3 coordinates x (value, dx=1, dy=1) = 9 calls on the tensor grid of
                      the per-direction parameter lists. bisplev accepts non-decreasing lists, so
                      the lists keep the repeated patch edges: it evaluates exactly shapespline's
                      points (patches x S x S), only in another order.
  scipy design_matrix BSpline.design_matrix in u and v (and of the derivative basis: the degree-2
                      design matrix on t[1:-1] times the difference matrix of the derivative's
                      control points), then B_u @ P @ B_v.T per coordinate and field: what a
                      NumPy user writes. Building the matrices is timed too.
  scipy NdBSpline     only where SciPy has it (1.12+): one call per field on the (Nu, Nv, 2) points.
  shapespline         Surface.sample(device="cpu") fp64 with 1 thread (the process's affinity mask
                      cut to one CPU: the library sizes its pool from that mask, core/cores.h) and
                      with the default threads; device="vulkan" fp32 when a Vulkan device exists.

Every peer produces the same number of points (patches x S^2, each with its 3 fields), so Mpts/s
is comparable; the peers' own output layout is kept (reordering to patch order is not timed).
Before timing, each peer's first (untimed) result is checked against shapespline's CPU fp64
result: max |difference| per field over the largest side of that field's bounding box must be at
most 1e-9 (fp64 peers) or 4e-6 (Vulkan fp32, tests/support/tolerances.h kFp32Rel); otherwise the
script compares different things and exits 1.

Memory: every peer returns fresh arrays (0.27 GB of output at S = 32, 1.1 GB at S = 64). On a VM
whose freed memory goes back to the host (Firecracker's page reporting here), touching fresh pages
ran at about 0.9 GB/s and made the fastest SciPy peer 8x slower than its arithmetic. So by default
the script re-executes itself with glibc malloc tunables that keep freed memory in the process's
heap (no mmap for large blocks, no trimming): each repetition then measures evaluation into
already-mapped memory, as in a process that samples repeatedly. --fresh-memory keeps the default
allocator (first-touch page faults included); the JSON records which.

Usage: PYTHONPATH=build/python bench/scipy_peers.py [--quick] [--reps N] [--fresh-memory] [--out PATH]
Prints a table and writes bench/results/scipy_peers.json (or PATH).
"""
import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
import time

import numpy as np
import scipy
import scipy.interpolate as si
import scipy.sparse as sp

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NET = 64             # control points per direction
ORDER = 4            # bicubic
NET_SEED = 20240530  # heights
KNOT_SEEDS = (30, 31)  # clamped random knots in u, v
FIELDS = ("point", "du", "dv")
TOL_FP64 = 1e-9
TOL_FP32 = 4e-6
# Keep freed blocks in the heap (see "Memory" above); read by glibc at process start only.
HEAP_TUNABLES = "glibc.malloc.mmap_max=0:glibc.malloc.trim_threshold=1099511627776"


def import_shapespline():
    """The module from PYTHONPATH, else from build/python (the default build tree)."""
    try:
        import shapespline
    except ImportError:
        sys.path.insert(0, os.path.join(ROOT, "build", "python"))
        try:
            import shapespline
        except ImportError as e:
            sys.exit(f"scipy_peers: cannot import shapespline ({e}); set PYTHONPATH to the build's python/ folder")
    return shapespline


# ---- workload ------------------------------------------------------------------------------------

def control_net():
    """(NET, NET, 3): x, y a regular grid on [0, 1]^2, z a few random smooth waves plus small noise."""
    rng = np.random.default_rng(NET_SEED)
    g = np.linspace(0.0, 1.0, NET)
    x, y = np.meshgrid(g, g, indexing="ij")
    z = np.zeros_like(x)
    for _ in range(6):
        fx, fy = rng.uniform(0.5, 4.0, 2)
        px, py = rng.uniform(0.0, 2 * np.pi, 2)
        z += rng.uniform(0.02, 0.1) * np.sin(2 * np.pi * fx * x + px) * np.cos(2 * np.pi * fy * y + py)
    z += 0.005 * rng.standard_normal(z.shape)
    return np.ascontiguousarray(np.stack([x, y, z], axis=-1))


def knot_vector(kind, seed):
    """NET + ORDER knots. uniform: 0..67 (unclamped, as in issue 30). clamped: ORDER-fold 0 and 1 and
    NET - ORDER distinct interior knots with random gaps (ratio up to 9 between neighbours)."""
    if kind == "uniform":
        return np.arange(NET + ORDER, dtype=float)
    gaps = np.random.default_rng(seed).uniform(0.2, 1.8, NET - ORDER + 1)
    interior = np.cumsum(gaps)[:-1] / gaps.sum()
    return np.concatenate([np.zeros(ORDER), interior, np.ones(ORDER)])


def knot_intervals(t):
    """The non-empty intervals [t_j, t_j+1] of the domain [t_{k-1}, t_n]: shapespline's patch rows."""
    n = len(t) - ORDER  # number of control points
    return [(t[j], t[j + 1]) for j in range(ORDER - 1, n) if t[j] < t[j + 1]]


def patch_parameters(t, S):
    """(intervals, S): the knot parameters of a patch's samples, s = a/(S-1), both ends included.
    (1-s) a + s b hits both ends exactly, so no sample leaves the domain by an ulp."""
    s = np.arange(S) / (S - 1)
    return np.array([(1 - s) * a + s * b for a, b in knot_intervals(t)])


# ---- peers: each returns {field: [x, y, z]} of (Nu, Nv) arrays on the grid xu x xv ---------------

def scipy_bisplev(P, U, V, xu, xv):
    out = {f: [] for f in FIELDS}
    k = ORDER - 1
    for d in range(3):
        tck = [U, V, P[:, :, d].ravel(), k, k]
        out["point"].append(si.bisplev(xu, xv, tck))
        out["du"].append(si.bisplev(xu, xv, tck, dx=1))
        out["dv"].append(si.bisplev(xu, xv, tck, dy=1))
    return out


def design_matrices(x, t):
    """B (len(x), n) and its derivative D: d/dt sum_i c_i N_i,k = sum_i w_i (c_i+1 - c_i) N_i+1,k-1,
    w_i = k / (t_i+k+1 - t_i+1) (0 on an empty support), and the N_i+1,k-1 are the degree k-1
    B-splines on t[1:-1]."""
    k = ORDER - 1
    n = len(t) - k - 1
    B = si.BSpline.design_matrix(x, t, k)
    span = t[k + 1:k + n] - t[1:n]
    w = np.divide(k, span, out=np.zeros_like(span), where=span > 0)
    diff = sp.diags([-w, w], [0, 1], shape=(n - 1, n), format="csr")
    D = si.BSpline.design_matrix(x, t[1:-1], k - 1) @ diff
    return B, D


def scipy_design_matrix(P, U, V, xu, xv):
    Bu, Du = design_matrices(xu, U)
    Bv, Dv = design_matrices(xv, V)
    out = {f: [] for f in FIELDS}
    for d in range(3):
        Pd = P[:, :, d]
        out["point"].append(Bu @ Pd @ Bv.T)
        out["du"].append(Du @ Pd @ Bv.T)
        out["dv"].append(Bu @ Pd @ Dv.T)
    return out


def scipy_ndbspline(P, U, V, xu, xv):
    spline = si.NdBSpline((U, V), P, (ORDER - 1, ORDER - 1))
    xi = np.stack(np.meshgrid(xu, xv, indexing="ij"), axis=-1)
    out = {}
    for f, nu in zip(FIELDS, ((0, 0), (1, 0), (0, 1))):
        r = spline(xi, nu=nu)  # (Nu, Nv, 3)
        out[f] = [r[..., d] for d in range(3)]
    return out


def shapespline_sample(surface, S, device, precision, cpus=None):
    """A closure running Surface.sample; cpus: the affinity mask during the call (None: unchanged)."""
    def run():
        saved = os.sched_getaffinity(0)
        if cpus is not None:
            os.sched_setaffinity(0, cpus)
        try:
            return surface.sample((S, S), fields=FIELDS, device=device, precision=precision, require=True)
        finally:
            os.sched_setaffinity(0, saved)
    return run


# ---- checks and timing ---------------------------------------------------------------------------

def to_patches(a, n_u, n_v, S):
    """(Nu, Nv) on the grid of per-direction lists -> (patches, S, S) in sample() order (u outer)."""
    return np.asarray(a).reshape(n_u, S, n_v, S).transpose(0, 2, 1, 3).reshape(n_u * n_v, S, S)


def max_errors(result, ref, n_u, n_v, S):
    """{field: max |result - ref| / largest side of ref's bounding box}; result is a grid peer's
    {field: [x, y, z]} or a sample() dict."""
    errors = {}
    for f in FIELDS:
        r = ref[f]
        box = max(float(r[..., d].max() - r[..., d].min()) for d in range(3)) or 1.0
        worst = 0.0
        for d in range(3):
            got = to_patches(result[f][d], n_u, n_v, S) if isinstance(result[f], list) else result[f][..., d]
            worst = max(worst, float(np.max(np.abs(got.astype(np.float64) - r[..., d]))))
        errors[f] = worst / box
    return errors


def timed(fn):
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def machine_info(ss, vulkan_device):
    cpu = "?"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    try:
        commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown"
    return {"cpu": cpu, "nproc": os.cpu_count(), "affinity_cpus": len(os.sched_getaffinity(0)),
            "python": platform.python_version(), "numpy": np.__version__, "scipy": scipy.__version__,
            "shapespline": f"{ss.__version__} ({ss.git_commit})", "commit": commit,
            "vulkan_device": vulkan_device}


# ---- main ----------------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="S = 8 only, one repetition (a smoke test)")
    ap.add_argument("--reps", type=int, default=3, help="timed repetitions per peer (default 3; best is kept)")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "scipy_peers.json"))
    ap.add_argument("--fresh-memory", action="store_true",
                    help="keep the default allocator: fresh output pages (first-touch faults) in every repetition")
    args = ap.parse_args()
    if args.reps < 1:
        ap.error("--reps must be at least 1")
    if not args.fresh_memory and os.environ.get("GLIBC_TUNABLES") != HEAP_TUNABLES:
        os.execve(sys.executable, [sys.executable] + sys.argv, {**os.environ, "GLIBC_TUNABLES": HEAP_TUNABLES})
    allocator = "glibc default (fresh pages)" if args.fresh_memory else f"GLIBC_TUNABLES={HEAP_TUNABLES}"
    sizes, reps = ((8,), 1) if args.quick else ((32, 64), args.reps)

    ss = import_shapespline()
    P = control_net()
    cpus = sorted(os.sched_getaffinity(0))
    unavailable = []

    if hasattr(si, "NdBSpline"):
        scipy_peers = [("scipy bisplev", scipy_bisplev), ("scipy design_matrix", scipy_design_matrix),
                       ("scipy NdBSpline", scipy_ndbspline)]
    else:
        scipy_peers = [("scipy bisplev", scipy_bisplev), ("scipy design_matrix", scipy_design_matrix)]
        unavailable.append(("scipy NdBSpline", f"scipy.interpolate has no NdBSpline in SciPy {scipy.__version__} "
                                               "(added in 1.12)"))

    probe = ss.Surface(P, construction="bspline", order=[ORDER, ORDER],
                       knots=[knot_vector("uniform", 0), knot_vector("uniform", 0)])
    plan = probe.plan(device="vulkan", precision="float")
    vulkan_device = plan.device if plan.gpu else None
    if vulkan_device is None:
        unavailable.append(("shapespline vulkan fp32", "; ".join(plan.fallbacks) or "no Vulkan device"))
    for name, why in unavailable:
        print(f"unavailable: {name}: {why}")

    load_before = " ".join(f"{x:.2f}" for x in os.getloadavg())
    rows, checks, failed = [], [], False
    for kind in ("uniform", "clamped"):
        U, V = knot_vector(kind, KNOT_SEEDS[0]), knot_vector(kind, KNOT_SEEDS[1])
        surface = ss.Surface(P, construction="bspline", order=[ORDER, ORDER], knots=[U, V])
        for S in sizes:
            pu, pv = patch_parameters(U, S), patch_parameters(V, S)
            n_u, n_v = len(pu), len(pv)
            assert n_u * n_v == surface.item_count, (n_u, n_v, surface.item_count)
            xu, xv = pu.ravel(), pv.ravel()  # non-decreasing, shared patch edges repeated
            points = n_u * n_v * S * S

            peers = [(name, (lambda f=f: f(P, U, V, xu, xv)), TOL_FP64) for name, f in scipy_peers]
            if len(cpus) > 1:
                peers.append(("shapespline cpu fp64 1 thread", shapespline_sample(surface, S, "cpu", "double", {cpus[0]}),
                              TOL_FP64))
            peers.append((f"shapespline cpu fp64 {len(cpus)} threads (default)",
                          shapespline_sample(surface, S, "cpu", "double"), TOL_FP64))
            if vulkan_device:
                peers.append(("shapespline vulkan fp32", shapespline_sample(surface, S, "vulkan", "float"), TOL_FP32))

            # The reference, then every peer once, untimed: the cross-check, and a warm-up (GPU
            # pipelines, resident net, page faults of the first large allocation).
            ref = shapespline_sample(surface, S, "cpu", "double")()
            for name, fn, tol in peers:
                errors = max_errors(fn(), ref, n_u, n_v, S)
                ok = all(e <= tol for e in errors.values())
                failed |= not ok
                checks.append({"peer": name, "knots": kind, "S": S, "max_error_over_box": errors,
                               "tolerance": tol, "ok": ok})
                print(f"check: {name:40s} {kind:8s} S={S:<3d} " +
                      " ".join(f"{f} {e:.1e}" for f, e in errors.items()) + ("" if ok else f"  > {tol:g}: FAILED"))
            del ref
            if failed:
                continue

            # Interleaved repetitions: a load change on this shared machine hits every peer alike.
            best = {name: float("inf") for name, _, _ in peers}
            for _ in range(reps):
                for name, fn, _ in peers:
                    best[name] = min(best[name], timed(fn))
            fastest_scipy = max(points / best[name] for name, _ in scipy_peers)
            for name, _, _ in peers:
                rate = points / best[name]
                rows.append({"peer": name, "knots": kind, "S": S, "points": points, "best_s": best[name],
                             "mpts_per_s": rate / 1e6, "ratio_to_fastest_scipy": rate / fastest_scipy})

    machine = machine_info(ss, vulkan_device)
    machine["load_average_before"] = load_before
    machine["load_average_after"] = " ".join(f"{x:.2f}" for x in os.getloadavg())
    result = {
        "date": datetime.datetime.now().isoformat(timespec="seconds"),
        "machine": machine,
        "workload": {"net": [NET, NET], "order": [ORDER, ORDER], "patches": 61 * 61, "fields": list(FIELDS),
                     "samples_per_patch": [[S, S] for S in sizes], "net_seed": NET_SEED,
                     "knots": {"uniform": "0..67 in u and v (unclamped; domain [3, 64])",
                               "clamped": f"4-fold 0 and 1, 60 random distinct interior knots (seeds {KNOT_SEEDS})"},
                     "points": "patches x S x S, each with point, du, dv (shared patch edges repeated, as sample())"},
        "statistic": f"best of {reps} wall-time repetitions (interleaved), after one untimed checked run",
        "allocator": allocator,
        "results": rows, "cross_checks": checks,
        "unavailable": [{"peer": n, "why": w} for n, w in unavailable],
    }
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump(result, f, indent=2)
        f.write("\n")

    print(f"\nMachine: {machine['cpu']}, {machine['nproc']} CPUs, SciPy {scipy.__version__}, NumPy {np.__version__}, "
          f"Vulkan: {vulkan_device or 'none'} (load average {load_before} before, "
          f"{machine['load_average_after']} after); {result['statistic']}; allocator {allocator}\n")
    print("| peer | knots | S | points | best s | Mpts/s | vs fastest SciPy |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['peer']} | {r['knots']} | {r['S']} | {r['points']:,} | {r['best_s']:.3f} | "
              f"{r['mpts_per_s']:.1f} | {r['ratio_to_fastest_scipy']:.2f}x |")
    for name, why in unavailable:
        print(f"| {name} | - | - | - | - | unavailable: {why} | |")
    print(f"\nwritten: {args.out}")
    if failed:
        print("scipy_peers: a peer disagrees with shapespline's CPU fp64 result (see the check lines): "
              "the benchmark would compare different things", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
