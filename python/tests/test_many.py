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
