"""Two threads evaluate concurrently (the GIL is released); results equal the sequential ones."""
import threading

import numpy as np
import pytest

import shapespline as ss
from conftest import model


def run_pair(jobs):
    results = [None] * len(jobs)
    errors = []
    barrier = threading.Barrier(len(jobs))

    def work(i):
        try:
            barrier.wait()
            results[i] = jobs[i]()
        except Exception as e:  # pragma: no cover - reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(len(jobs))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    return results


def devices():
    out = ["cpu"]
    try:
        if model("open_aeb.json").plan(device="vulkan", precision="float").gpu:
            out.append("vulkan")
    except ss.DeviceError:
        pass
    return out


@pytest.mark.parametrize("device", devices())
def test_two_threads_equal_sequential(device):
    s = model("surface_aeb.json")
    c = model("butterfly_aeb.json")
    kw = dict(device=device, precision="float" if device == "vulkan" else "double")
    jobs = [
        lambda: s.sample((64, 64), fields=("point", "normal"), **kw),
        lambda: c.evaluate(np.linspace(0, 20, 5001), **kw),
        lambda: s.sample((64, 64), fields=("point", "normal"), **kw),  # the same object from two threads
        lambda: s.tessellate(8, **kw),
    ]
    sequential = [j() for j in jobs]
    for _ in range(2):
        concurrent = run_pair(jobs)
        for a, b in zip(sequential, concurrent):
            items = a.items() if isinstance(a, dict) else enumerate(a)
            for k, v in items:
                assert np.array_equal(v, b[k])


def test_gil_is_released_while_sampling():
    s = model("surface_aeb.json")
    done = threading.Event()
    ticks = 0

    def job():
        s.sample((300, 300), fields="all", device="cpu")
        done.set()

    t = threading.Thread(target=job)
    t.start()
    while not done.is_set():
        ticks += 1
    t.join()
    assert ticks > 1000  # the Python thread ran meanwhile
