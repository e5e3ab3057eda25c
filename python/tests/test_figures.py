"""examples/python/figures.py writes every figure, none of them blank."""
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO

FIGURES = ["xuwang_degrees.png", "butterfly_alpha.png", "surface_lambda.png", "ubp_gubp_basis.png",
           "gb_lambda_paths.png", "bspline_extension.png"]


def test_figures_script_writes_every_png(tmp_path):
    image = pytest.importorskip("matplotlib.image")
    env = dict(os.environ, MPLBACKEND="Agg")
    subprocess.run([sys.executable, str(REPO / "examples" / "python" / "figures.py"), str(tmp_path)], check=True,
                   env=env, timeout=120)
    for name in FIGURES:
        path = tmp_path / name
        assert path.is_file() and path.stat().st_size > 10_000, name
        rgb = image.imread(str(path))[..., :3]
        assert rgb.shape[0] > 200 and rgb.shape[1] > 400, name
        ink = (rgb.mean(axis=-1) < 0.9).mean()  # fraction of non-white pixels
        assert 0.01 < ink < 0.9, f"{name}: {ink:.3f} of the pixels are drawn"
        assert np.unique(rgb.reshape(-1, 3), axis=0).shape[0] > 50, f"{name} has almost no colours"
