"""ss.load_part(DIR), Part.mesh and Part.sample (docs/python.md "Parts"): a part written here as
`shapespline import` writes one (a cube of six planar faces with their coedges), meshed into NumPy
arrays that are welded, closed and wound outwards, and sampled into the trimmed point cloud the
command line writes (a hole's samples left out); bad arguments raise ValueError naming the argument."""
import json
import subprocess

import numpy as np
import pytest

import shapespline as ss


def write_cube(folder, size=2.0):
    """DIR/part.json and six planar faces of the cube [0, size]^3, each edge run from its
    lower-numbered corner (t = 0) to the other (t = 1), as import writes coedges."""
    axes = np.eye(3)
    corner_of = lambda p: int(round(p[0] / size)) + 2 * int(round(p[1] / size)) + 4 * int(round(p[2] / size))
    edge_ids, faces, edges = {}, [], []
    fid = 0
    for a in range(3):
        for side in range(2):
            fid += 1
            u, v = size * axes[(a + 1) % 3], size * axes[(a + 2) % 3]
            o = side * size * axes[a]
            net = [[list(o + i * u + j * v) for j in range(2)] for i in range(2)]
            face = {"kind": "surface", "construction": "bspline", "order": [2, 2],
                    "knots": [[0, 0, 1, 1], [0, 0, 1, 1]], "closed": [False, False],
                    "trim": {"loops": [[[0, 0], [1, 0], [1, 1], [0, 1]]], "tolerance": 1e-9}, "points": net}
            name = f"face_{fid}.json"
            (folder / name).write_text(json.dumps(face))
            uv = [(0, 0), (1, 0), (1, 1), (0, 1)]
            loop = []
            for k in range(4):
                p0 = o + uv[k][0] * u + uv[k][1] * v
                p1 = o + uv[(k + 1) % 4][0] * u + uv[(k + 1) % 4][1] * v
                a0, a1 = corner_of(p0), corner_of(p1)
                key = (min(a0, a1), max(a0, a1))
                if key not in edge_ids:
                    edge_ids[key] = len(edge_ids) + 1
                    edges.append({"id": edge_ids[key], "curve": "Geom_Line", "model": None})
                loop.append({"edge": edge_ids[key], "start": k, "t": [0.0, 1.0] if a0 < a1 else [1.0, 0.0]})
            faces.append({"id": fid, "model": name, "reversed": side == 0, "surface": "Geom_Plane",
                          "coedges": [loop]})
    manifest = {"format": "shapespline-part", "faces": faces, "edges": edges,
                "shells": [{"id": 1, "faces": [f["id"] for f in faces]}]}
    (folder / "part.json").write_text(json.dumps(manifest))
    return folder


def signed_volume(m):
    p = m["positions"][m["triangles"].astype(np.int64)]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0)


def test_cube_mesh_is_welded_closed_and_outward(tmp_path):
    part = ss.load_part(str(write_cube(tmp_path)))
    assert part.faces == [1, 2, 3, 4, 5, 6]
    assert part.edges == 12 and part.skipped == 0
    assert part.diagonal == pytest.approx(2.0 * np.sqrt(3.0))
    m = part.mesh(device="cpu")
    assert m["positions"].shape == (8, 3) and m["positions"].dtype == np.float64
    assert m["triangles"].shape == (12, 3) and m["triangles"].dtype == np.uint32
    assert sorted(set(m["face_ids"].tolist())) == [1, 2, 3, 4, 5, 6]
    assert m["open_edges"] == 0 and m["non_manifold_edges"] == 0
    assert signed_volume(m) == pytest.approx(8.0, rel=1e-12)
    assert np.allclose(np.linalg.norm(m["normals"], axis=1), 1.0)
    # Every directed edge once, and its reverse once: closed and consistently wound.
    t = m["triangles"]
    directed = {(int(a), int(b)) for tri in t for a, b in zip(tri, np.roll(tri, -1))}
    assert len(directed) == 36 and all((b, a) in directed for a, b in directed)
    # Also DIR/part.json.
    assert ss.load_part(str(tmp_path / "part.json")).faces == part.faces


def test_vulkan_fp64_gives_the_cpu_mesh(tmp_path, gpu):
    if not gpu["fp64"]:
        pytest.skip("the device has no fp64")
    part = ss.load_part(str(write_cube(tmp_path)))
    cpu = part.mesh(device="cpu")
    dev = part.mesh(device="vulkan", require=True)
    assert dev["device"] == gpu["name"]
    assert np.array_equal(dev["triangles"], cpu["triangles"])
    assert np.allclose(dev["positions"], cpu["positions"], rtol=0, atol=1e-12 * part.diagonal)


@pytest.mark.parametrize("kwargs, named", [
    (dict(deflection=0.0), "deflection: must be a finite number > 0"),
    (dict(deflection=float("nan")), "deflection: must be a finite number > 0"),
    (dict(relative_deflection=-1.0), "relative_deflection: must be a finite number > 0"),
    (dict(deflection=1.0, relative_deflection=1e-3), "deflection: give deflection"),
    (dict(angle=3.5), "angle: must be a finite number in (0, pi)"),
    (dict(max_triangles=0), "max_triangles: must be > 0"),
    (dict(max_triangles=5), "needs more than the budget of 5 triangles"),
    (dict(device="tpu"), "device: expected"),
])
def test_bad_arguments_raise_value_error_naming_them(tmp_path, kwargs, named):
    part = ss.load_part(str(write_cube(tmp_path)))
    with pytest.raises(ValueError, match=None) as e:
        part.mesh(**{"device": "cpu", **kwargs})
    assert named in str(e.value)


def test_a_missing_part_or_faces_without_coedges_raise(tmp_path):
    with pytest.raises(Exception) as missing:
        ss.load_part(str(tmp_path / "nowhere"))
    assert "nowhere" in str(missing.value)
    folder = write_cube(tmp_path)
    manifest = json.loads((folder / "part.json").read_text())
    for face in manifest["faces"]:
        del face["coedges"]
    (folder / "part.json").write_text(json.dumps(manifest))
    part = ss.load_part(str(folder))
    with pytest.raises(ss.ModelError) as e:
        part.mesh(device="cpu")
    assert e.value.field == "faces[0].coedges"


def sample_params(n):
    """A patch's n sample parameters a / (n - 1), as the grid sampler spaces them."""
    return np.arange(n) / (n - 1)


def test_sample_keeps_every_grid_sample_of_whole_faces_on_the_cube(tmp_path):
    part = ss.load_part(str(write_cube(tmp_path)))
    c = part.sample(grid=(5, 4), fields=("point", "normal"), device="cpu")
    assert c["uv"].shape == (6 * 20, 2) and c["point"].shape == (120, 3) and c["face_ids"].dtype == np.int32
    assert c["face_ids"].tolist() == [f for f in range(1, 7) for _ in range(20)]
    u, v = np.meshgrid(sample_params(5), sample_params(4), indexing="ij")
    axes = np.eye(3)
    for fid in range(1, 7):
        a, side = (fid - 1) // 2, (fid - 1) % 2
        mine = c["face_ids"] == fid
        assert np.array_equal(c["uv"][mine], np.stack([u.ravel(), v.ravel()], axis=1))
        # The face's plane o + U u + V v, evaluated here.
        want = side * 2.0 * axes[a] + np.outer(c["uv"][mine, 0], 2.0 * axes[(a + 1) % 3]) + \
            np.outer(c["uv"][mine, 1], 2.0 * axes[(a + 2) % 3])
        assert np.allclose(c["point"][mine], want, rtol=0, atol=1e-12)
        assert np.allclose(np.abs(c["normal"][mine] @ axes[a]), 1.0)


def test_sample_leaves_out_a_hole_and_matches_the_cli_point_cloud(tmp_path, shapespline_bin):
    folder = write_cube(tmp_path)
    face = json.loads((folder / "face_1.json").read_text())
    face["trim"]["loops"].append([[0.3, 0.3], [0.7, 0.3], [0.7, 0.7], [0.3, 0.7]])
    (folder / "face_1.json").write_text(json.dumps(face))
    manifest = json.loads((folder / "part.json").read_text())  # the hole is one edge of its own
    manifest["edges"].append({"id": 13, "curve": "Geom_BSplineCurve", "model": None})
    manifest["faces"][0]["coedges"].append([{"edge": 13, "start": 0, "t": [0, 1, 2, 3, 4]}])
    (folder / "part.json").write_text(json.dumps(manifest))
    part = ss.load_part(str(folder))
    c = part.sample(grid=11, device="cpu")
    u, v = np.meshgrid(sample_params(11), sample_params(11), indexing="ij")
    in_hole = (u > 0.3) & (u < 0.7) & (v > 0.3) & (v < 0.7)
    assert int((c["face_ids"] == 1).sum()) == 121 - int(in_hole.sum())
    uv = c["uv"][c["face_ids"] == 1]
    assert not ((uv[:, 0] > 0.3 + 1e-9) & (uv[:, 0] < 0.7 - 1e-9) & (uv[:, 1] > 0.3 + 1e-9) & (uv[:, 1] < 0.7 - 1e-9)).any()
    # `sample part.json -o cloud.npy` keeps the same records, read back by NumPy.
    subprocess.run([shapespline_bin, "sample", str(folder / "part.json"), "--grid", "11", "--device", "cpu",
                    "-o", str(tmp_path / "cloud.npy"), "-q"], check=True)
    cloud = np.load(tmp_path / "cloud.npy")
    assert np.array_equal(cloud["face"].ravel(), c["face_ids"])
    assert np.array_equal(cloud["uv"], c["uv"])
    assert np.array_equal(cloud["point"], c["point"])
    f32 = part.sample(grid=11, device="cpu", precision="float")
    assert f32["point"].dtype == np.float32 and np.allclose(f32["point"], c["point"], rtol=0, atol=1e-6)


@pytest.mark.parametrize("kwargs, named", [
    (dict(grid=1), "grid"),
    (dict(fields="bogus"), "fields"),
    (dict(device="tpu"), "device"),
])
def test_sample_bad_arguments_raise_value_error_naming_them(tmp_path, kwargs, named):
    part = ss.load_part(str(write_cube(tmp_path)))
    with pytest.raises(ValueError) as e:
        part.sample(**kwargs)
    assert named in str(e.value)
