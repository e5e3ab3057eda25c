#!/usr/bin/python3
"""Many small models: one `sample` process per model against one `sample` of them all (issue 31).

Workload: N extended B-spline surfaces (degree 4) of 8 x 8 points with random heights (fixed seed),
32 x 32 samples per patch (25 patches, 25,600 points per model), written as .npy. For each device
(cpu, and vulkan when one exists) the script times one `shapespline sample DIR -o 'out/{stem}.npy'`
of all N models and, interleaved, K single-model processes `shapespline sample MODEL -o OUT`; the
ratio is the per-model time of the processes over that of the batch. Before timing it checks that
the batch's files are byte for byte the single processes' (data and sidecar) for those K models.

For scale, the same run times the files alone: the batch's own bytes, already in memory, written as
the same files in the way `sample` must write them (a temporary file each, fsync, rename, then an
fsync of the folder) by a Python loop that does nothing else, one model after the other; the
fastest of three runs. It is not a floor (the batch overlaps one model's fsync with the next
model's work), but where creating files is slow (an ext4 without a journal scans for recently
deleted inodes on every create) it shows what a batch is made of.

Usage: bench/batch_models.py CLI [--models N] [--singles K] [--out PATH]
Prints a table and writes bench/results/batch_models.json (or PATH).
"""
import argparse
import datetime
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def write_models(folder, n):
    rng = np.random.default_rng(31)
    i, j = np.meshgrid(np.arange(8), np.arange(8), indexing="ij")
    for k in range(n):
        P = np.zeros((8, 8, 3))
        P[..., 0], P[..., 1], P[..., 2] = i, j, rng.normal(size=(8, 8))
        with open(os.path.join(folder, f"m{k:05d}.json"), "w") as f:
            json.dump({"kind": "surface", "construction": "extended_bspline", "degree": 4, "points": P.tolist()}, f)


def write_files_only(batch_out, folder):
    """Seconds to write the files of `batch_out` into `folder` as `sample` commits them."""
    sets = []
    for name in sorted(n for n in os.listdir(batch_out) if n.endswith(".npy")):
        files = [(n, open(os.path.join(batch_out, n), "rb").read()) for n in (name, name + ".json")]
        sets.append(files)
    os.makedirs(folder)
    t = time.perf_counter()
    for files in sets:
        opened = []
        for name, data in files:
            temp = os.path.join(folder, "." + name + ".tmp")
            fd = os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
            os.write(fd, data)
            os.fsync(fd)
            opened.append((fd, temp, name))
        dirfd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
        for fd, temp, name in opened:
            os.close(fd)
            os.rename(temp, os.path.join(folder, name))
        os.fsync(dirfd)
        os.close(dirfd)
    return time.perf_counter() - t


def run(cmd):
    t = time.perf_counter()
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit(f"batch_models: {' '.join(cmd)} failed ({r.returncode}): {r.stderr.strip()}")
    return time.perf_counter() - t


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("cli")
    ap.add_argument("--models", type=int, default=1000)
    ap.add_argument("--singles", type=int, default=50, help="single-model processes timed (default 50)")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "batch_models.json"))
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="shapespline_batch_")
    try:
        models = os.path.join(work, "models")
        os.makedirs(models)
        write_models(models, a.models)
        names = sorted(os.listdir(models))
        info = subprocess.run([a.cli, "info"], capture_output=True, text=True)
        has_vulkan = info.returncode == 0 and "selected:" in info.stdout
        rows = []
        for device in ["cpu"] + (["vulkan"] if has_vulkan else []):
            batch_out, single_out = os.path.join(work, "batch"), os.path.join(work, "single")
            for d in (batch_out, single_out):
                shutil.rmtree(d, ignore_errors=True)
                os.makedirs(d)
            opts = ["--grid", "32", "--device", device, "-q"]
            batch_s = run([a.cli, "sample", models, "-o", os.path.join(batch_out, "{stem}.npy")] + opts)
            singles = []
            for name in names[: a.singles]:
                out = os.path.join(single_out, name.replace(".json", ".npy"))
                singles.append(run([a.cli, "sample", os.path.join(models, name), "-o", out] + opts))
                for ext in (".npy", ".npy.json"):
                    with open(out.replace(".npy", ext), "rb") as f1, \
                         open(os.path.join(batch_out, name.replace(".json", ext)), "rb") as f2:
                        if f1.read() != f2.read():
                            sys.exit(f"batch_models: {name}{ext} differs between the batch and its own process")
            # The fastest of three, each into a new folder (files created where files were just
            # deleted are slower on ext4).
            files_s = min(write_files_only(batch_out, os.path.join(work, f"files-{device}-{k}")) for k in range(3))
            per_single = sum(singles) / len(singles)
            per_batch = batch_s / a.models
            rows.append({"device": device, "models": a.models, "batch_s": batch_s, "per_model_batch_ms": 1e3 * per_batch,
                         "single_processes": len(singles), "per_model_single_ms": 1e3 * per_single,
                         "ratio": per_single / per_batch, "files_only_s": files_s,
                         "batch_over_files_only": batch_s / files_s})
        result = {"date": datetime.datetime.now().isoformat(timespec="seconds"), "cores": os.cpu_count(),
                  "folder": os.path.dirname(work), "rows": rows}
        os.makedirs(os.path.dirname(a.out), exist_ok=True)
        with open(a.out, "w") as f:
            json.dump(result, f, indent=2)
        print(f"files under {os.path.dirname(work)} (TMPDIR)")
        print("| device | models | batch s | ms/model batch | ms/model as processes | ratio | files only s | batch/files only |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|")
        for r in rows:
            print(f"| {r['device']} | {r['models']} | {r['batch_s']:.2f} | {r['per_model_batch_ms']:.2f} | "
                  f"{r['per_model_single_ms']:.1f} | {r['ratio']:.1f}x | {r['files_only_s']:.2f} | "
                  f"{r['batch_over_files_only']:.2f} |")
        print(f"\nwritten: {a.out}")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
