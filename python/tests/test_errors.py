"""Bad inputs raise ValueError (ModelError naming the field) or RuntimeError (DeviceError); never a crash."""
import math

import numpy as np
import pytest

import shapespline as ss
from conftest import model

CURVE = {"kind": "curve", "construction": "alpha_eb", "degree": 5, "points": [[0, 0], [1, 2], [3, 3], [5, 1], [6, 4]], "alpha": 0.5}


@pytest.mark.parametrize(
    "change, field",
    [
        ({"alpha": [0.5, 1.5, 0.5, 0.5, 0.5]}, "alpha[1]"),
        ({"alpha": 0.0}, "alpha"),
        ({"lambda": 7.0}, "lambda"),
        ({"degree": 9}, "degree"),
        ({"points": [[0, 0]]}, "points"),
        ({"points": [[0, 0], [1, math.nan], [3, 3], [5, 1], [6, 4]]}, "points[1][1]"),
        ({"points": [[0, 0], [1, 2, 3, 4], [3, 3], [5, 1], [6, 4]]}, "points[1]"),
        ({"colour": "red"}, "colour"),
        ({"construction": "nurbs"}, "construction"),
    ],
)
def test_model_errors_name_the_field(change, field):
    d = dict(CURVE, **change)
    with pytest.raises(ValueError) as info:
        ss.from_dict(d)
    e = info.value
    assert isinstance(e, ss.ModelError)
    assert e.field.startswith(field) and field in str(e)


def test_keyword_and_type_errors():
    with pytest.raises(ss.ModelError, match="alpha"):
        ss.Curve(np.zeros((5, 2)), construction="alpha_eb", degree=5, alpha=np.array([1, 1, 2, 1, 1.0]))
    with pytest.raises(ValueError):
        ss.Curve.from_dict(model("surface_aeb.json").to_dict())
    with pytest.raises(ValueError):
        ss.from_dict({"kind": "curve", "points": object()})
    nested = []
    nested.append(nested)  # a cycle must not recurse forever
    with pytest.raises(ValueError):
        ss.from_dict({"kind": "curve", "construction": "extended_bspline", "degree": 4, "points": nested})
    with pytest.raises(ValueError):
        ss.from_dict({"kind": "curve", "points": np.array(["a", "b"])})
    with pytest.raises((ValueError, TypeError)):
        ss.from_dict([1, 2, 3])


def test_file_errors(tmp_path):
    with pytest.raises(FileNotFoundError):
        ss.load(str(tmp_path / "missing.json"))
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(ss.ModelError):
        ss.load(str(bad))


def test_argument_errors():
    c = model("butterfly_aeb.json")
    s = model("surface_aeb.json")
    cases = [
        (lambda: c.sample(1), "samples|grid"),
        (lambda: c.sample((4, 4)), "grid"),
        (lambda: s.sample((4, 1)), "grid"),
        (lambda: c.sample(8, fields="normal"), "fields"),
        (lambda: c.sample(8, device="tpu"), "device"),
        (lambda: c.sample(8, precision="half"), "precision"),
        (lambda: c.sample(8, first_item=999), "first_item"),
        (lambda: c.sample(8, item_count=999), "item_count"),
        (lambda: c.sample_chunks(8, queue=0), "queue"),
        (lambda: c.evaluate([0.5, 1e9]), r"params\[1\]"),
        (lambda: c.evaluate(span=[0, 99], t=[0.5, 0.5]), r"params\[1\]"),
        (lambda: c.evaluate(span=[0.5], t=[0.5]), "span"),
        (lambda: s.evaluate([[0.5, 0.5, 0.5]]), "params"),
        (lambda: s.evaluate(patch=[[0, 0]], uv=[[2.0, 0.5]]), r"params\[0\]"),
        (lambda: s.tessellate(0), "rate"),
        (lambda: c.set_control_point(99, [0, 0]), "index"),
        (lambda: c.set_control_point(0, [0, 0, 0]), "point"),
        (lambda: s.set_alpha(0.5, index=(9, 9)), "index"),
        (lambda: ss.basis("nope", [0.5]), "family"),
        (lambda: ss.basis("xuwang", [0.5]), "degree"),
        (lambda: ss.basis("ubp", [0.5], order=4, lambda_=5.0), "lambda"),
        (lambda: c.gb_lambda_path(1, [0.5]), "construction"),
        (lambda: c.extend([[1, 1]]), "knots"),
        (lambda: model("clamped_bspline.json").extend([[1, 1, 1]]), "targets"),
    ]
    for call, pattern in cases:
        with pytest.raises(ValueError, match=pattern):
            call()


def test_failed_setter_changes_nothing():
    c = model("butterfly_aeb.json")
    before = c.sample(8, device="cpu")["point"]
    with pytest.raises(ss.ModelError) as info:
        c.set_lambda(5.0)  # Xu-Wang: lambda <= 1
    assert info.value.field == "lambda"
    with pytest.raises(ss.ModelError):
        c.set_alpha(0.0, index=3)
    with pytest.raises(ss.ModelError):
        c.set_mu([0.5, 0.5])
    assert c.lambda_ == -1
    assert np.array_equal(c.sample(8, device="cpu")["point"], before)


def test_required_device_refused_is_a_runtime_error():
    # alpha below the fp32 kernels' limit: the GPU refuses, so require=True cannot fall back. Without
    # a device the refusal is "no Vulkan device"; either way a DeviceError (RuntimeError).
    c = ss.Curve([[0, 0], [1, 2], [3, 3], [5, 1], [6, 4]], construction="alpha_eb", degree=5, alpha=1e-31)
    with pytest.raises(RuntimeError) as info:
        c.sample(8, device="vulkan", precision="float", require=True)
    assert isinstance(info.value, ss.DeviceError) and info.value.fallback_refused
    r = c.plan(device="vulkan", precision="float")
    assert not r.gpu and r.fallbacks
