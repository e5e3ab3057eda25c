"""A large job streams chunk by chunk in bounded memory (>= 10^7 points, RSS measured)."""
import resource
import time

import numpy as np

import shapespline as ss
from conftest import model


def rss_bytes():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def test_ten_million_points_in_bounded_memory():
    s = model("surface_aeb.json")
    items = s.item_count
    side = int(np.ceil(np.sqrt(1.0e7 / items)))
    total = items * side * side
    assert total >= 10**7
    before = rss_bytes()
    peak, seen, chunks, checksum = before, 0, 0, 0.0
    start = time.monotonic()
    for ch in s.sample_chunks((side, side), fields="point", device="cpu", chunk_points=1 << 18):
        assert ch["first_point"] == seen
        seen += ch["point"].shape[0]
        checksum += float(ch["point"][:, 2].sum())
        chunks += 1
        peak = max(peak, rss_bytes())
    elapsed = time.monotonic() - start
    growth = peak - before
    full = total * 3 * 8
    print(f"\n{total} points in {chunks} chunks, {elapsed:.2f} s, RSS growth {growth / 2**20:.1f} MiB "
          f"(the whole job: {full / 2**20:.0f} MiB)")
    assert seen == total
    assert np.isfinite(checksum)
    assert growth < 64 * 2**20, f"RSS grew by {growth / 2**20:.1f} MiB"
    assert elapsed < 20


def test_closing_early_cancels_the_producer():
    c = model("butterfly_aeb.json")
    it = c.sample_chunks(200000, device="cpu", chunk_points=4096)
    next(it)
    next(it)
    it.close()
    assert it.report is None or it.report.device == "cpu"
    # An abandoned iterator is cancelled when it is collected.
    it2 = c.sample_chunks(200000, device="cpu", chunk_points=4096)
    next(it2)
    del it2
