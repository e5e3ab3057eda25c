"""Shared fixtures of the Python tests (run by ctest as python/pytest, PYTHONPATH at build/python)."""
import os
import pathlib

import numpy as np
import pytest

import shapespline as ss

REPO = pathlib.Path(__file__).resolve().parents[2]
MODELS = REPO / "examples" / "models"
GOLDEN = pathlib.Path(os.environ.get("SHAPESPLINE_GOLDEN_DIR", REPO / "tests" / "data" / "golden"))
if not GOLDEN.is_absolute():
    GOLDEN = REPO / GOLDEN

# tests/support/tolerances.h: relative to the control net's bounding-box diagonal.
FP64_REL = 1e-12
FP32_REL = 4e-6

# The suite has well over this many tests; fewer means a collection problem (and never exit status 5).
MIN_TESTS = 40


def pytest_collection_finish(session):
    whole = any(pathlib.Path(a).is_dir() for a in session.config.args)
    if whole and not session.config.option.keyword and len(session.items) < MIN_TESTS:
        raise pytest.UsageError(f"only {len(session.items)} tests collected (expected at least {MIN_TESTS})")


def _probe():
    c = ss.Curve([[0, 0], [1, 1], [2, 0], [3, 1]], construction="extended_bspline", degree=4)
    try:
        r = c.plan(device="vulkan", precision="float")
    except ss.DeviceError as e:  # a Vulkan failure while creating the device
        return None, str(e)
    if not r.gpu:
        return None, "; ".join(r.fallbacks) or "no GPU"
    fp64 = c.plan(device="vulkan", precision="double").gpu
    return {"name": r.device, "fp64": fp64}, None


_GPU, _NO_GPU_REASON = _probe()


@pytest.fixture(scope="session")
def gpu():
    """The Vulkan device (skips the test with the reason when there is none)."""
    if _GPU is None:
        pytest.skip(f"no Vulkan device: {_NO_GPU_REASON}")
    return _GPU


@pytest.fixture(scope="session")
def shapespline_bin():
    """The command-line tool of the same build (ctest sets SHAPESPLINE_CLI), to compare with."""
    exe = os.environ.get("SHAPESPLINE_CLI") or str(REPO / "build" / "host" / "cli" / "shapespline")
    if not pathlib.Path(exe).is_file():
        pytest.skip(f"no shapespline executable at {exe} (set SHAPESPLINE_CLI)")
    return exe


def scale_of(points):
    p = np.asarray(points, dtype=np.float64).reshape(-1, np.asarray(points).shape[-1])
    return max(float(np.linalg.norm(p.max(axis=0) - p.min(axis=0))), 1e-300)


def model(name):
    return ss.load(str(MODELS / name))
