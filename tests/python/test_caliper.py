"""Tests of the Python module `caliper` (docs/python.md), run by ctest as `python`.

Needs PYTHONPATH=<build>/python and, for the comparisons with the command line, CALIPER_CLI=<build>/bin/caliper
(tests/python/run.sh sets both).
"""
import json
import os
import re
import struct
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import caliper

DOCS = Path(__file__).resolve().parents[2] / "docs" / "python.md"
PERSON = dict(sex="female", stature_cm=165, weight_kg=60, span_cm=167)


@pytest.fixture(scope="module")
def female():
    return caliper.load_model("mannequin", sex="female")


@pytest.fixture(scope="module")
def avatar(female):
    return caliper.build_avatar(stature_cm=165, weight_kg=60, span_cm=167, model=female)


def read_obj(path):
    """Vertices (float64) and triangle vertex indices (0-based) of an OBJ, parsed here, not by caliper."""
    vertices, faces = [], []
    for line in Path(path).read_text().splitlines():
        parts = line.split()
        if parts and parts[0] == "v":
            vertices.append([float(x) for x in parts[1:4]])
        elif parts and parts[0] == "f":
            faces.append([int(corner.split("/")[0]) - 1 for corner in parts[1:]])
    return np.array(vertices), np.array(faces)


def cli(*args, cwd):
    exe = os.environ.get("CALIPER_CLI")
    if not exe:
        pytest.fail("CALIPER_CLI is not set: run these tests through ctest or tests/python/run.sh")
    return subprocess.run([exe, *args], cwd=cwd, capture_output=True, text=True, check=True)


# ---- shapes, dtypes, units -------------------------------------------------------------------

def test_avatar_arrays_have_the_documented_shapes_and_dtypes(avatar, female):
    n = female.vertex_count
    assert avatar.vertices.shape == (n, 3) and avatar.vertices.dtype == np.float64
    assert avatar.faces.shape[1] == 3 and avatar.faces.dtype == np.int32
    assert avatar.faces.min() == 0 and avatar.faces.max() == n - 1
    assert avatar.joints.shape == (len(female.joint_names), 3) and avatar.joints.dtype == np.float64
    assert avatar.beta.shape == (female.shape_count,)
    assert avatar.vertex_sd.shape == (n,) and (avatar.vertex_sd > 0).all()
    # Views, not copies to be edited by mistake.
    assert not avatar.vertices.flags.writeable


def test_avatar_is_in_metres_and_has_the_requested_size(avatar):
    height = avatar.vertices[:, 1].max() - avatar.vertices[:, 1].min()
    assert abs(height - 1.65) < 0.01
    assert abs(avatar.achieved["stature"] - 1.65) < 0.005
    assert abs(avatar.achieved["weight"] - 60) < 0.5


def test_report_is_the_cli_report_as_a_dict(avatar, tmp_path):
    report = avatar.report
    assert report["model"] == "mannequin-female" and report["sex"] == "female"
    assert len(report["beta"]) == len(avatar.beta)
    cli("avatar", "--sex", "female", "--height", "165", "--weight", "60", "--span", "167", "-q",
        "-o", "x.obj", "--report", "x.json", cwd=tmp_path)
    assert report == json.loads((tmp_path / "x.json").read_text())


def test_load_model_picks_the_variant_by_sex():
    male = caliper.load_model("mannequin", sex="male")
    assert male.sex == "male" and male.name == "mannequin-male"
    assert male.faces.shape == (male.faces.shape[0], 3) and male.template_vertices.shape == (male.vertex_count, 3)


# ---- the same avatar as the command line ------------------------------------------------------

@pytest.mark.parametrize("extra_args, extra_kwargs", [
    ([], {}),
    (["--regressor", "R4", "--sex", "male", "--crotch-height", "80"], dict(estimator="R4", sex="male", crotch_height_cm=80)),
])
def test_vertices_are_identical_to_the_cli(tmp_path, extra_args, extra_kwargs):
    kwargs = dict(PERSON, **extra_kwargs)
    args = ["--height", "165", "--weight", "60", "--span", "167"]
    if "--sex" not in extra_args:
        args += ["--sex", "female"]
    cli("avatar", *args, *extra_args, "-q", "-o", "cli.obj", cwd=tmp_path)
    cli_vertices, cli_faces = read_obj(tmp_path / "cli.obj")
    a = caliper.build_avatar(**kwargs)
    # OBJ numbers are written as the shortest decimal that reads back to the same double.
    np.testing.assert_array_equal(a.vertices, cli_vertices)
    np.testing.assert_array_equal(a.faces, cli_faces)


# ---- save round trips -------------------------------------------------------------------------

def test_obj_round_trip_is_exact(avatar, tmp_path):
    avatar.save(str(tmp_path / "me.obj"))
    vertices, faces = read_obj(tmp_path / "me.obj")
    np.testing.assert_array_equal(vertices, avatar.vertices)
    np.testing.assert_array_equal(faces, avatar.faces)


def test_glb_holds_the_vertices_in_float32(avatar, tmp_path):
    path = tmp_path / "me.GLB"
    avatar.save(str(path))
    data = path.read_bytes()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert magic == b"glTF" and version == 2 and length == len(data)
    json_length, json_type = struct.unpack_from("<I4s", data, 12)
    assert json_type == b"JSON"
    gltf = json.loads(data[20:20 + json_length])
    binary = data[20 + json_length + 8:]
    accessor = gltf["accessors"][gltf["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
    view = gltf["bufferViews"][accessor["bufferView"]]
    start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    positions = np.frombuffer(binary, "<f4", accessor["count"] * 3, start).reshape(-1, 3)
    n = len(avatar.vertices)  # seam copies follow the model's own vertices
    np.testing.assert_allclose(positions[:n], avatar.vertices, atol=1e-6)


# ---- measuring arrays -------------------------------------------------------------------------

def cube(side):
    """A closed cube standing on y = 0, faces counter-clockwise seen from outside."""
    v = np.array([[x, y, z] for x in (0, side) for y in (0, side) for z in (0, side)], dtype=float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    f = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])
    return v, f


def test_measure_a_bare_mesh_gives_stature_and_volume():
    v, f = cube(0.5)
    m = caliper.measure(v, f)
    assert m["stature"] == pytest.approx(0.5)
    assert m["volume"] == pytest.approx(0.125)
    assert m["weight"] > 0


def test_measure_the_models_topology_gives_every_measurement(avatar, female):
    m = caliper.measure(np.array(avatar.vertices), avatar.faces, model=female)
    assert m["stature"] == pytest.approx(1.65, abs=0.005)
    assert m["weight"] == pytest.approx(60, abs=0.5)
    assert "chest_circumference" in m


# ---- errors: a typed exception naming the field and the accepted range ------------------------

@pytest.mark.parametrize("value, error", [
    (float("nan"), caliper.InvalidArgumentError),
    (-165, caliper.OutOfRangeError),
    (400, caliper.OutOfRangeError),
])
def test_bad_stature_names_the_field(value, error):
    with pytest.raises(error) as info:
        caliper.build_avatar(sex="female", stature_cm=value, weight_kg=60, force=True)
    e = info.value
    assert e.field == "stature"
    lo, hi, unit = e.accepted_range
    assert unit == "cm" and lo <= 165 <= hi
    assert isinstance(e, ValueError) and isinstance(e, caliper.Error)


def test_stature_in_metres_is_refused_with_what_was_meant():
    with pytest.raises(caliper.InvalidArgumentError) as info:
        caliper.build_avatar(sex="female", stature_cm=1.65, weight_kg=60)
    assert info.value.field == "stature" and "165" in str(info.value)


@pytest.mark.parametrize("arguments, field, hint", [
    (dict(stature_cm=165, weight_cm=60), "weight", "weight_kg"),
    (dict(stature_kg=165, weight_kg=60), "stature", "stature_cm"),
    (dict(stature_cm=165, weight=60), "weight", "NAME_kg"),
])
def test_a_measurement_in_the_wrong_unit_or_without_one_is_refused(arguments, field, hint):
    with pytest.raises(caliper.InvalidArgumentError) as info:
        caliper.build_avatar(sex="female", **arguments)
    assert info.value.field == field and hint in str(info.value)


def test_unknown_or_doubled_measurements_are_refused():
    with pytest.raises(caliper.InvalidArgumentError) as info:
        caliper.build_avatar(stature_cm=165, weight_kg=60, shoe_size=42)
    assert info.value.field == "shoe_size"
    with pytest.raises(caliper.InvalidArgumentError) as info:
        caliper.build_avatar(stature_cm=165, weight_kg=60, measurements={"height": 170})
    assert info.value.field == "stature"
    with pytest.raises(caliper.InvalidArgumentError) as info:
        caliper.build_avatar(sex="female")
    assert info.value.field == "measurements"
    with pytest.raises(caliper.InvalidArgumentError) as info:
        caliper.build_avatar(stature_cm="165", weight_kg=60)
    assert info.value.field == "stature"


def test_bad_model_sex_and_estimator_are_refused(female):
    with pytest.raises(caliper.Error) as info:
        caliper.load_model("/nonexistent/model.npz")
    assert info.value.origin == "caller"
    with pytest.raises(caliper.InvalidArgumentError):
        caliper.load_model("mannequin", sex="robot")
    with pytest.raises(caliper.InvalidArgumentError) as info:
        caliper.build_avatar(sex="male", stature_cm=165, weight_kg=60, model=female)
    assert info.value.field == "sex"
    with pytest.raises(caliper.InvalidArgumentError):
        caliper.build_avatar(stature_cm=165, weight_kg=60, estimator="R99", model=female)


def test_bad_arrays_name_the_argument(avatar):
    v, f = cube(1.0)
    bad = v.copy()
    bad[3, 1] = np.nan
    with pytest.raises(caliper.InvalidArgumentError) as info:
        caliper.measure(bad, f)
    assert info.value.field == "vertices"
    with pytest.raises(caliper.FormatError) as info:
        caliper.measure(v[:, :2], f)
    assert info.value.field == "vertices"
    with pytest.raises(caliper.FormatError) as info:
        caliper.measure(v, f.astype(float))
    assert info.value.field == "faces"
    with pytest.raises(caliper.FormatError) as info:
        caliper.measure(v, f + 1)
    assert info.value.field == "faces" and "outside [0, 7]" in str(info.value)
    with pytest.raises(caliper.FormatError):  # open mesh: no volume
        caliper.measure(v, f[:-2])


def test_bad_save_paths_are_refused(avatar, tmp_path):
    with pytest.raises(caliper.InvalidArgumentError) as info:
        avatar.save(str(tmp_path / "me.png"))
    assert info.value.field == "path"
    with pytest.raises(caliper.IoError) as info:
        avatar.save(str(tmp_path / "no-such-folder" / "me.glb"))
    assert isinstance(info.value, OSError)


# ---- threads ----------------------------------------------------------------------------------

def test_threads_build_the_same_avatars_as_one_thread(female):
    statures = [150, 160, 170, 180]
    one = [caliper.build_avatar(stature_cm=s, weight_kg=65, model=female).vertices for s in statures]
    with ThreadPoolExecutor(4) as pool:
        many = list(pool.map(lambda s: caliper.build_avatar(stature_cm=s, weight_kg=65, model=female).vertices, statures))
    for a, b in zip(one, many):
        np.testing.assert_array_equal(a, b)


def _counting_rate_during(work):
    """How fast another Python thread counts while `work` runs: it can only count while the GIL is free."""
    stop, count = False, 0

    def counter():
        nonlocal count
        while not stop:
            count += 1

    thread = threading.Thread(target=counter)
    thread.start()
    start = time.perf_counter()
    work()
    seconds = time.perf_counter() - start
    stop = True
    thread.join()
    return count / seconds


def test_library_calls_release_the_gil(female):
    def builds():
        for _ in range(10):
            caliper.build_avatar(stature_cm=165, weight_kg=62, model=female)

    def held():  # one long C call that keeps the GIL: the regular-expression engine backtracking
        re.match(r"(a+)+b", "a" * 23)

    # Another thread counts many times faster during avatar builds than during a GIL-holding call.
    assert _counting_rate_during(builds) > 4 * _counting_rate_during(held)


# ---- the documentation's example ---------------------------------------------------------------

def test_the_worked_example_in_docs_runs(tmp_path):
    """Each python block of docs/python.md, run as a script the way a reader would (a pool needs a real __main__)."""
    blocks = re.findall(r"```python\n(.*?)```", DOCS.read_text(), re.S)
    assert blocks, "docs/python.md has no python example"
    for i, block in enumerate(blocks):
        script = tmp_path / f"example{i}.py"
        script.write_text(block)
        done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True)
        assert done.returncode == 0, f"docs/python.md example {i + 1} failed:\n{done.stdout}\n{done.stderr}"
