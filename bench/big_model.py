#!/usr/bin/python3
"""One big α-EB net from .npy against the issue-31 ceilings, measured in the same run (issue 31).

Workload: an N x N height field (degree 5, α = 0.5) saved with numpy.save (N = 4096: 400 MB of
fp64 points), sampled 4 x 4 per patch to .f32. For each device (cpu, and vulkan when one exists)
the script runs `shapespline sample` in child processes: the whole job started three times and
stopped as soon as its output holds a byte (the time to the first sample as seen from outside the
job; the best of three, as numpy.load's time is), the whole job, a shard of one patch row's worth
of items (best of three: the whole run, which also reads and hashes the rest of the net for the
job's identity) and a shard with no items; each child's max RSS comes from wait4. The ceilings
are the issue's: time to the first sample <= 2 x the time numpy.load takes for the same file
(measured here, warm cache), max RSS <= 1.5 x the net's bytes + 100 MB. Ratios > 1 miss the
ceiling.

With --python DIR (the folder of the built module, e.g. build/python) it also builds a 2048 x 2048
α-EB Surface from a NumPy array in a child interpreter against the issue's Python ceilings: at most
0.5 s, and at most 2 x the array's bytes of memory beside it (the peak over the interpreter's RSS
with the array made, from VmHWM after resetting it through /proc/self/clear_refs).

Usage: bench/big_model.py CLI [--n N] [--python DIR] [--out PATH]
Prints a table and writes bench/results/big_model.json (or PATH).
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

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def first_bytes(cmd, out):
    """Seconds from the start of `cmd` (a whole job writing `out`) until its temporary output file
    holds a byte: the time to the first sample as a user of the job sees it. The job is then stopped."""
    folder, prefix = os.path.dirname(out), "." + os.path.basename(out) + ".tmp"
    t = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    seen = None
    while seen is None and p.poll() is None:
        for e in os.scandir(folder):
            if e.name.startswith(prefix) and e.stat().st_size > 0:
                seen = time.perf_counter() - t
        time.sleep(0.0005)
    p.kill()
    p.wait()
    for e in os.scandir(folder):
        if e.name.startswith(prefix):
            os.remove(e.path)
    if seen is None:
        sys.exit(f"big_model: {' '.join(cmd)} ended before it wrote a sample")
    return seen


def child(cmd):
    """Wall seconds and max RSS (bytes) of one child process."""
    t = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t
    err = p.stderr.read().decode()
    p.stderr.close()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"big_model: {' '.join(cmd)} failed: {err.strip()}")
    return wall, usage.ru_maxrss * 1024


MAKE_NET = r"""
import sys, time
import numpy as np
path, n = sys.argv[1], int(sys.argv[2])
u, v = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
np.save(path, np.stack([u, v, 0.1 * np.sin(8 * u) * np.cos(6 * v)], axis=-1))
del u, v
np.load(path)  # warm the page cache
loads = []
for _ in range(3):
    t = time.perf_counter()
    np.load(path)
    loads.append(time.perf_counter() - t)
print(min(loads))
"""

PYTHON_ARRAY = r"""
import json, sys, time
sys.path.insert(0, sys.argv[1])
import numpy as np
import shapespline


def rss():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096


n = int(sys.argv[2])
u, v = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
net = np.ascontiguousarray(np.stack([u, v, 0.1 * np.sin(8 * u) * np.cos(6 * v)], axis=-1))
del u, v
before = rss()
with open("/proc/self/clear_refs", "w") as f:
    f.write("5")  # the peak (VmHWM) starts again from the current RSS
t = time.perf_counter()
s = shapespline.Surface.from_dict({"kind": "surface", "construction": "alpha_eb", "degree": 5, "alpha": 0.5,
                                   "points": net})
build = time.perf_counter() - t
with open("/proc/self/status") as f:
    peak = next(int(line.split()[1]) * 1024 for line in f if line.startswith("VmHWM"))
print(json.dumps({"n": n, "array_bytes": net.nbytes, "build_s": build, "peak_extra_bytes": peak - before,
                  "kept_extra_bytes": rss() - before}))
"""


def python_array(module_dir, n=2048):
    """The issue's Python case: Surface from a 2048² NumPy array, in a fresh interpreter."""
    out = subprocess.run([sys.executable, "-c", PYTHON_ARRAY, module_dir, str(n)], capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"big_model: the Python case failed: {out.stderr.strip()}")
    r = json.loads(out.stdout)
    r["build_over_ceiling"] = r["build_s"] / 0.5
    r["peak_over_ceiling"] = r["peak_extra_bytes"] / (2 * r["array_bytes"])
    return r


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("cli")
    ap.add_argument("--n", type=int, default=4096)
    ap.add_argument("--python", help="folder of the built Python module (adds the Python Surface(array) case)")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "big_model.json"))
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="shapespline_big_")
    try:
        n = a.n
        net = os.path.join(work, "net.npy")
        # The net is made and numpy.load timed in a child interpreter: a child forked from a parent
        # that held the array would report the parent's RSS as its own max RSS (wait4 counts the
        # memory the child had before its exec).
        load_s = float(subprocess.run([sys.executable, "-c", MAKE_NET, net, str(n)], check=True, capture_output=True,
                                      text=True).stdout)
        with open(os.path.join(work, "m.json"), "w") as f:
            json.dump({"kind": "surface", "construction": "alpha_eb", "degree": 5, "alpha": 0.5,
                       "points": {"npy": "net.npy"}}, f)
        net_bytes = os.path.getsize(net)
        info = subprocess.run([a.cli, "info"], capture_output=True, text=True)
        has_vulkan = info.returncode == 0 and "selected:" in info.stdout
        rss_ceiling = 1.5 * net_bytes + 100e6
        results = []
        for device in ["cpu"] + (["vulkan"] if has_vulkan else []):
            base = [a.cli, "sample", os.path.join(work, "m.json"), "--grid", "4x4", "--device", device, "-q"]
            if device == "vulkan":
                base += ["--precision", "float", "--require-device"]
            # The first sample: the whole job's first bytes on disk (best of three, as numpy.load
            # is: the first run after making the net meets memory this VM has not handed out
            # lately, whose page faults cost several times more).
            first_s = min(first_bytes(base + ["-o", os.path.join(work, "whole.f32")], os.path.join(work, "whole.f32"))
                          for _ in range(3))
            # One shard of about one patch row, whole: its sample, and the rest of the net read
            # and hashed for the job's identity (best of three).
            def one_row_shard():  # into a fresh file each time (a shard with a record would resume)
                r = child(base + ["-o", os.path.join(work, "row.f32"), "--shard", f"1/{n - 1}"])
                for f in os.listdir(work):
                    if f.startswith("row.f32"):
                        os.remove(os.path.join(work, f))
                return r
            rows = [one_row_shard() for _ in range(3)]
            row_s, row_rss = min(rows)
            whole_s, whole_rss = child(base + ["-o", os.path.join(work, "whole.f32")])
            os.remove(os.path.join(work, "whole.f32"))
            # A shard with no items (more shards than patches): what it costs beside the net.
            empty_s, empty_rss = child(base + ["-o", os.path.join(work, "empty.f32"), "--shard", f"1/{2 * n * n}"])
            results.append({"device": device, "first_sample_s": first_s, "first_over_ceiling": first_s / (2 * load_s),
                            "one_row_shard_s": row_s, "one_row_shard_runs_s": [r for r, _ in rows],
                            "one_row_shard_max_rss": row_rss, "whole_s": whole_s, "max_rss": whole_rss,
                            "rss_over_ceiling": whole_rss / rss_ceiling, "empty_shard_s": empty_s,
                            "empty_shard_max_rss": empty_rss})
        result = {"date": datetime.datetime.now().isoformat(timespec="seconds"), "cores": os.cpu_count(), "n": n,
                  "net_bytes": net_bytes, "numpy_load_s": load_s, "rss_ceiling": rss_ceiling, "rows": results}
        if a.python:
            result["python_array"] = python_array(os.path.abspath(a.python))
        os.makedirs(os.path.dirname(a.out), exist_ok=True)
        with open(a.out, "w") as f:
            json.dump(result, f, indent=2)
        print(f"net {n} x {n}: {net_bytes / 1e6:.0f} MB; numpy.load {load_s:.3f} s; RSS ceiling {rss_ceiling / 1e6:.0f} MB")
        print("| device | first sample s | / ceiling | whole job s | max RSS MB | / ceiling | one-row shard s | "
              "its max RSS MB | empty shard s | its max RSS MB |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for r in results:
            print(f"| {r['device']} | {r['first_sample_s']:.3f} | {r['first_over_ceiling']:.2f}x | {r['whole_s']:.1f} | "
                  f"{r['max_rss'] / 1e6:.0f} | {r['rss_over_ceiling']:.2f}x | {r['one_row_shard_s']:.2f} | "
                  f"{r['one_row_shard_max_rss'] / 1e6:.0f} | {r['empty_shard_s']:.2f} | "
                  f"{r['empty_shard_max_rss'] / 1e6:.0f} |")
        if a.python:
            p = result["python_array"]
            print(f"\nPython {p['n']}² Surface(array): build {p['build_s']:.2f} s ({p['build_over_ceiling']:.2f}x the "
                  f"0.5 s ceiling); peak memory beside the array {p['peak_extra_bytes'] / p['array_bytes']:.2f}x its "
                  f"bytes ({p['peak_over_ceiling']:.2f}x the 2x ceiling), kept {p['kept_extra_bytes'] / p['array_bytes']:.2f}x")
        print(f"\nwritten: {a.out}")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
