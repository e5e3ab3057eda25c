"""sample_many: many models through one device and its pipelines, each result what the model's own
sample() gives; a failing model is named and, with errors='keep', the others are still sampled."""
import numpy as np
import pytest

import shapespline as ss
from conftest import MODELS, model

FILES = ["open_aeb.json", "surface_aeb.json", "nurbs_torus.json", "gb_curve.json", "bspline_surface.json"]


def test_each_result_is_the_models_own_sample_on_the_cpu():
    models = [MODELS / FILES[0], str(MODELS / FILES[1]), model(FILES[2]), model(FILES[3]).to_dict(),
              ss.load(str(MODELS / FILES[4]))]
    got = ss.sample_many(models, 6, fields="all", device="cpu")
    assert len(got) == len(models)
    for name, result in zip(FILES, got):
        want = model(name).sample(6, fields="all", device="cpu")
        assert result.keys() == want.keys(), name
        for key in want:
            assert result[key].dtype == want[key].dtype and np.array_equal(result[key], want[key]), (name, key)


def test_reports_and_float_output():
    got = ss.sample_many([MODELS / "surface_aeb.json"], (4, 5), device="cpu", precision="float", report=True)
    [(arrays, report)] = got
    assert arrays["point"].dtype == np.float32 and arrays["point"].shape[1:] == (4, 5, 3)
    assert report.device == "cpu" and report.output_precision == "float"


def test_gpu_results_match_the_cpu(gpu):
    models = [MODELS / name for name in FILES]
    cpu = ss.sample_many(models, 5, fields="all", device="cpu")
    for precision, rel in (("float", 4e-6), ("double", 1e-12)):
        if precision == "double" and not gpu["fp64"]:
            continue
        got = ss.sample_many(models, 5, fields=("point",), device="vulkan", precision=precision, require=True,
                             report=True)
        for name, (arrays, report), want in zip(FILES, got, cpu):
            assert report.gpu, name
            scale = np.ptp(want["point"].reshape(-1, 3), axis=0).max()
            assert np.abs(arrays["point"] - want["point"]).max() <= 4 * rel * scale, (name, precision)


def test_a_failing_model_is_named_and_the_others_are_kept():
    bad = model("open_aeb.json").to_dict()
    bad["alpha"] = [0.5] * (len(bad["points"]) - 1)
    models = [MODELS / "open_aeb.json", bad, MODELS / "no_such_model.json", 42, MODELS / "surface_aeb.json"]
    with pytest.raises(ss.ModelError) as e:
        ss.sample_many(models, 4, device="cpu")
    assert "sample_many: models[1]" in getattr(e.value, "__notes__", [])
    got = ss.sample_many(models, 4, device="cpu", errors="keep")
    assert len(got) == 5
    assert isinstance(got[1], ss.ModelError) and got[1].field == "alpha"
    assert isinstance(got[2], FileNotFoundError) and "sample_many: models[2]" in got[2].__notes__
    assert isinstance(got[3], TypeError) and "got int" in str(got[3])
    assert np.array_equal(got[0]["point"], model("open_aeb.json").sample(4, device="cpu")["point"])
    assert np.array_equal(got[4]["point"], model("surface_aeb.json").sample(4, device="cpu")["point"])
    with pytest.raises(ValueError, match="errors"):
        ss.sample_many(models, 4, errors="ignore")
    assert ss.sample_many([], 4) == []


def test_a_net_over_one_device_buffer_is_sampled_in_bands(gpu):
    """A 1450 x 1450 alpha_eb net in fp64 needs 135 MB for V and the nodes, over lavapipe's
    128 MiB storage binding: sample() takes the GPU in bands of patch rows and equals the CPU."""
    if not gpu["fp64"]:
        pytest.skip("the device has no fp64")
    n = 1450
    u, v = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
    s = ss.Surface(np.stack([u, v, 0.1 * np.sin(9 * u) * np.cos(7 * v)], axis=-1), construction="alpha_eb",
                   degree=5, alpha=0.5)
    got, report = s.sample(2, device="vulkan", precision="double", require=True, report=True)
    if report.band_rows == 0:
        pytest.skip(f"{report.device} holds the whole net in one buffer")
    assert report.gpu and 0 < report.band_rows < n - 1
    want = s.sample(2, device="cpu")
    assert np.abs(got["point"] - want["point"]).max() <= 1e-12 * np.sqrt(2.02)
    [(arrays, many)] = ss.sample_many([s], 2, device="vulkan", precision="double", require=True, report=True)
    assert many.band_rows == report.band_rows and np.array_equal(arrays["point"], got["point"])
