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


def test_noise_sds_and_a_real_to_virtual_map_give_the_clis_avatar(tmp_path):
    pairs = Path(__file__).resolve().parents[2] / "examples" / "real-virtual-pairs.csv"
    cli("map", "fit", str(pairs), "-o", "map.json", cwd=tmp_path)
    cli("avatar", "--sex", "female", "--height", "165", "--weight", "60", "--span", "167", "--hip-width", "36",
        "--noise", "self", "--noise-sd", "stature=3", "--noise-sd", "hip_breadth=0.5", "--map", "map.json", "-q",
        "-o", "cli.obj", cwd=tmp_path)
    a = caliper.build_avatar(**PERSON, hip_breadth_cm=36, noise="self", noise_sd={"height": 3, "hip_breadth": 0.5},
                             real_to_virtual=str(tmp_path / "map.json"))
    np.testing.assert_array_equal(a.vertices, read_obj(tmp_path / "cli.obj")[0])
    assert a.input_fits["stature"]["noise_sd"] == pytest.approx(0.03)
    plain = caliper.build_avatar(**PERSON, hip_breadth_cm=36, noise="self")
    assert not np.array_equal(a.vertices, plain.vertices)
    with pytest.raises(caliper.OutOfRangeError) as info:
        caliper.build_avatar(**PERSON, noise_sd={"stature": 0})
    assert info.value.field == "noise_sd.stature"
    with pytest.raises(caliper.IoError):
        caliper.build_avatar(**PERSON, real_to_virtual=str(tmp_path / "none.json"))


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


def box(width, height, depth):
    """A closed box standing on y = 0: the cube scaled per axis (still counter-clockwise from outside)."""
    v, f = cube(1.0)
    return v * [width, height, depth], f


def test_measure_a_bare_mesh_gives_stature_and_volume():
    v, f = box(0.4, 1.7, 0.25)
    m = caliper.measure(v, f)
    assert set(m) == {"stature", "volume", "weight"}
    assert m["stature"] == pytest.approx(1.7)
    assert m["volume"] == pytest.approx(0.4 * 1.7 * 0.25)
    assert m["weight"] > 0


@pytest.mark.parametrize("scale, unit", [(100, "centimetres"), (1000, "millimetres"), (0.1, "decimetres")])
def test_a_mesh_not_in_metres_is_refused_like_the_cli(scale, unit, avatar, female, tmp_path):
    v, f = box(0.4, 1.7, 0.25)
    for vertices, faces, model in ((v * scale, f, "mannequin"), (avatar.vertices * scale, avatar.faces, female)):
        with pytest.raises(caliper.OutOfRangeError) as info:
            caliper.measure(vertices, faces, model=model)
        assert info.value.field == "vertices", unit
        assert "read in metres" in str(info.value) and "[50, 250] cm" in str(info.value)
    # The command line says the same about the same mesh (its field is its option).
    avatar.save(str(tmp_path / "me.obj"))
    scaled = [" ".join(["v"] + [repr(float(x) * scale) for x in line.split()[1:]]) if line.startswith("v ") else line
              for line in (tmp_path / "me.obj").read_text().splitlines()]
    (tmp_path / "scaled.obj").write_text("\n".join(scaled) + "\n")
    done = subprocess.run([os.environ["CALIPER_CLI"], "measure", "--mesh", "scaled.obj"], cwd=tmp_path,
                          capture_output=True, text=True)
    assert done.returncode == 3 and "read in metres" in done.stderr


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
    with pytest.raises(caliper.SuspectInputError) as info:
        caliper.build_avatar(sex="female", stature_cm=1.65, weight_kg=60)
    assert info.value.field == "stature" and "165" in str(info.value)
    assert isinstance(info.value, caliper.InvalidArgumentError)
    # Swapped values too; force=True builds with the values as given.
    with pytest.raises(caliper.SuspectInputError) as info:
        caliper.build_avatar(sex="female", stature_cm=60, weight_kg=165)
    assert "swapped" in str(info.value)
    assert caliper.build_avatar(sex="female", stature_cm=60, weight_kg=165, force=True).warnings


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
    v, f = box(0.4, 1.7, 0.25)
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
    with ThreadPoolExecutor(2) as pool:
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


# ---- the documentation's examples, taken from the page itself --------------------------------

def doc_blocks(uses_dask):
    blocks = re.findall(r"```python\n(.*?)```", DOCS.read_text(), re.S)
    assert blocks, "docs/python.md has no python example"
    return [b for b in blocks if ("dask" in b) == uses_dask]


def run_as_script(block, path, cwd):
    """A block run the way a reader runs it: as a script (a process pool needs a real __main__)."""
    path.write_text(block)
    done = subprocess.run([sys.executable, str(path)], cwd=cwd, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, f"{path.name} from docs/python.md failed:\n{done.stdout}\n{done.stderr}"
    return done.stdout


def test_the_worked_example_in_docs_runs(tmp_path):
    blocks = doc_blocks(uses_dask=False)
    assert len(blocks) == 1
    out = run_as_script(blocks[0], tmp_path / "example.py", tmp_path)
    assert "meshes are read in metres" in out and "→ avatar of" in out
    for name in ("me.glb", "me-unity.glb", "me.vrm", "me.fbx", "me.obj"):
        assert (tmp_path / name).stat().st_size > 1000, name


def test_the_dask_batch_in_docs_runs(tmp_path):
    try:
        import distributed  # noqa: F401
    except ImportError:
        message = "dask.distributed is missing (Debian: python3-distributed, scripts/install-deps.sh)"
        if os.environ.get("CALIPER_REQUIRE_TOOLS") == "1":
            pytest.fail(message)
        pytest.skip(message)
    blocks = doc_blocks(uses_dask=True)
    assert len(blocks) == 1
    out = run_as_script(blocks[0], tmp_path / "dask_batch.py", tmp_path)
    assert out.count("waist") == 4


# ---- skin weights, posing ---------------------------------------------------------------------

def test_skin_weights_are_a_dense_matrix_whose_rows_sum_to_one(female, avatar):
    w = female.skin_weights
    assert w.shape == (female.vertex_count, len(female.joint_names)) and w.dtype == np.float64
    np.testing.assert_allclose(w.sum(axis=1), 1.0, atol=1e-12)
    assert (w >= 0).all()
    np.testing.assert_array_equal(avatar.skin_weights, w)
    assert len(female.parents) == len(female.joint_names) and female.parents[0] == -1


def rotation_about_y(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def test_a_global_rotation_turns_the_whole_body_about_the_root_joint(avatar):
    pose = np.zeros((24, 3))
    pose[0] = [0, np.pi / 2, 0]  # joint 0 carries the global orientation
    vertices, joints = avatar.pose(pose)
    r = rotation_about_y(np.pi / 2)
    root = avatar.joints[0]
    np.testing.assert_allclose(vertices, (avatar.vertices - root) @ r.T + root, atol=1e-12)
    np.testing.assert_allclose(joints, (avatar.joints - root) @ r.T + root, atol=1e-12)


def test_pose_shapes_and_the_rest_pose(avatar, female):
    n, j = female.vertex_count, len(female.joint_names)
    vertices, joints = avatar.pose(np.zeros(72))
    assert vertices.shape == (n, 3) and joints.shape == (j, 3) and vertices.dtype == np.float64
    np.testing.assert_allclose(vertices, avatar.vertices, atol=1e-12)
    np.testing.assert_allclose(joints, avatar.joints, atol=1e-12)
    # 72 values, 24×3 and a list are the same pose; the built-in rig takes its own 54×3 (fingers).
    bend = np.zeros((24, 3))
    bend[18] = [0, 0, -1.2]  # left elbow
    flat, _ = avatar.pose(bend.reshape(-1).tolist())
    np.testing.assert_array_equal(flat, avatar.pose(bend)[0])
    assert j == 54
    rig = np.zeros((54, 3))
    rig[:24] = bend
    np.testing.assert_array_equal(avatar.pose(rig)[0], flat)
    moved = np.linalg.norm(flat - avatar.vertices, axis=1) > 1e-9
    assert 0 < moved.sum() < n / 4  # the forearm and hand moved, the rest did not


def test_bad_poses_name_the_pose(avatar):
    for bad in (np.zeros(71), np.zeros((24, 2)), np.zeros((2, 24, 3))):
        with pytest.raises(caliper.InvalidArgumentError) as info:
            avatar.pose(bad)
        assert info.value.field == "pose"
    nan = np.zeros(72)
    nan[5] = np.nan
    with pytest.raises(caliper.InvalidArgumentError) as info:
        avatar.pose(nan)
    assert info.value.field == "pose"


# ---- plausibility and uncertainty --------------------------------------------------------------

def test_plausibility_and_uncertainty_are_the_reports(avatar):
    report = avatar.report
    p = avatar.plausibility
    assert p["verdict"] == report["plausibility"]["verdict"] == "plausible"
    assert p["per_value"] == report["plausibility"]["per_value"] and len(p["per_value"]) == len(avatar.beta)
    assert p["mahalanobis_sq"] == pytest.approx(float(avatar.beta @ avatar.beta))
    assert avatar.noise == "exact" and set(avatar.requested) == {"stature", "weight", "span"}
    sd = avatar.uncertainty
    assert set(sd) <= set(avatar.achieved) and all(v >= 0 for v in sd.values())
    assert report["measurements"]["chest_circumference"]["uncertainty_cm"] == pytest.approx(
        sd["chest_circumference"] * 100, abs=0.006)
    assert avatar.beta_covariance.shape == (len(avatar.beta), len(avatar.beta))
    fits = avatar.input_fits
    assert set(fits) == {"stature", "weight", "span"}
    assert fits["stature"]["value"] == pytest.approx(1.65) and fits["stature"]["fitted"] == pytest.approx(1.65, abs=1e-3)


def test_the_papers_regressors_have_no_uncertainty(female):
    a = caliper.build_avatar(stature_cm=165, weight_kg=60, estimator="R2", model=female)
    assert a.estimator == "R2" and a.uncertainty == {} and a.vertex_sd.shape == (0,) and a.input_fits == {}
    assert a.plausibility["verdict"] in ("plausible", "unusual", "implausible")


# ---- every file the CLI writes -----------------------------------------------------------------

def glb_json(path):
    data = Path(path).read_bytes()
    json_length, json_type = struct.unpack_from("<I4s", data, 12)
    assert json_type == b"JSON"
    return json.loads(data[20:20 + json_length])


@pytest.mark.parametrize("name, options, cli_options", [
    ("me.glb", {}, []),
    ("me.glb", dict(skeleton="humanoid", morphs=True), ["--skeleton", "humanoid", "--morphs"]),
    ("me.vrm", {}, []),
    ("me.fbx", dict(skeleton="humanoid"), ["--skeleton", "humanoid"]),
    ("me.obj", {}, []),
])
def test_saved_files_are_byte_for_byte_the_clis(name, options, cli_options, tmp_path):
    a = caliper.build_avatar(**PERSON)
    a.save(str(tmp_path / name), **options)
    cli("avatar", "--sex", "female", "--height", "165", "--weight", "60", "--span", "167", *cli_options, "-q",
        "-o", "cli-" + name, cwd=tmp_path)
    ours, theirs = (tmp_path / name).read_bytes(), (tmp_path / ("cli-" + name)).read_bytes()
    assert len(ours) > 1000 and ours == theirs


def test_save_options_change_the_file(avatar, tmp_path):
    avatar.save(str(tmp_path / "smpl.glb"))
    avatar.save(str(tmp_path / "humanoid.glb"), skeleton="humanoid", morphs=True)
    smpl, humanoid = glb_json(tmp_path / "smpl.glb"), glb_json(tmp_path / "humanoid.glb")
    names = lambda g: {node.get("name") for node in g["nodes"]}
    assert "left_elbow" in names(smpl) and "LeftLowerArm" in names(humanoid)
    assert "targets" not in smpl["meshes"][0]["primitives"][0]
    assert len(humanoid["meshes"][0]["primitives"][0]["targets"]) == len(avatar.beta)


def test_bad_save_options_are_refused(avatar, tmp_path):
    with pytest.raises(caliper.InvalidArgumentError) as info:
        avatar.save(str(tmp_path / "me.glb"), skeleton="mixamo")
    assert info.value.field == "skeleton"
    with pytest.raises(caliper.InvalidArgumentError):
        avatar.save(str(tmp_path / "me.obj"), morphs=True)
    assert not (tmp_path / "me.glb").exists() and not (tmp_path / "me.obj").exists()


# ---- evaluation -----------------------------------------------------------------------------------

EXAMPLE_PEOPLE = Path(__file__).resolve().parents[2] / "examples" / "people.csv"


def test_evaluate_gives_the_figures_of_caliper_eval(tmp_path):
    ours = caliper.evaluate(str(EXAMPLE_PEOPLE), estimators=["R2", "auto"], noise="self", seed=7)
    cli("eval", "--subjects", str(EXAMPLE_PEOPLE), "--regressor", "R2,auto", "--noise", "self", "--seed", "7",
        "-q", "--json", "eval.json", cwd=tmp_path)
    assert ours == json.loads((tmp_path / "eval.json").read_text())
    assert ours["subjects"] == 3 and set(ours["regressors"]) == {"R2", "auto"}


def test_evaluate_refuses_bad_input(tmp_path):
    with pytest.raises(caliper.IoError):
        caliper.evaluate(str(tmp_path / "none.csv"))
    (tmp_path / "bad.csv").write_text("SubjectId,Gender,stature\nx,Female,abc\n")
    with pytest.raises(caliper.Error):
        caliper.evaluate(str(tmp_path / "bad.csv"))
    with pytest.raises(caliper.InvalidArgumentError):
        caliper.evaluate(str(EXAMPLE_PEOPLE), noise="loud")
    with pytest.raises(caliper.OutOfRangeError) as info:
        caliper.evaluate(str(EXAMPLE_PEOPLE), threads=0)
    assert info.value.field == "threads"


# ---- other models ---------------------------------------------------------------------------------

SMPL_PARENTS = [-1, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 9, 12, 13, 14, 16, 17, 18, 19, 20, 21]


def synthetic_smpl(path, n=40, shapes=10, seed=3):
    """A small file with SMPL's arrays and 24 joints (not SMPL's mesh), written here with NumPy."""
    rng = np.random.default_rng(seed)
    arrays = dict(
        v_template=rng.uniform(-0.5, 0.5, (n, 3)) + [0, 0.9, 0],
        shapedirs=rng.normal(0, 0.01, (n, 3, shapes)),
        J_regressor=rng.dirichlet(np.ones(n), 24),
        weights=rng.dirichlet(np.ones(24), n),
        kintree_table=np.array([[2**32 - 1 if p < 0 else p for p in SMPL_PARENTS], list(range(24))], dtype=np.uint32),
        f=np.array([[i, i + 1, i + 2] for i in range(n - 2)], dtype=np.uint32),
    )
    np.savez(path, **arrays)
    return arrays


def test_an_smpl_file_loads_with_its_arrays(tmp_path):
    arrays = synthetic_smpl(tmp_path / "SMPL_TEST.npz")
    m = caliper.load_model(str(tmp_path / "SMPL_TEST.npz"), sex="male")
    assert m.sex == "male" and m.vertex_count == 40 and m.shape_count == 10
    assert m.joint_names[0] == "pelvis" and m.joint_names[23] == "right_hand" and m.parents == SMPL_PARENTS
    np.testing.assert_array_equal(m.faces, arrays["f"])
    np.testing.assert_allclose(m.skin_weights, arrays["weights"], atol=1e-12)
    # Stood on the floor: y shifted so the lowest vertex is at 0, x and z as in the file.
    t = arrays["v_template"]
    np.testing.assert_allclose(m.template_vertices, t - [0, t[:, 1].min(), 0], atol=1e-12)


def test_a_broken_smpl_file_names_the_array(tmp_path):
    arrays = synthetic_smpl(tmp_path / "ok.npz")
    arrays["weights"] = arrays["weights"][:, :5]
    np.savez(tmp_path / "bad.npz", **arrays)
    with pytest.raises(caliper.FormatError) as info:
        caliper.load_model(str(tmp_path / "bad.npz"))
    assert info.value.field == "weights" and info.value.origin == "caller"


def test_a_makehuman_build_loads(tmp_path):
    # The installed build if there is one; else a small one built here from ../shared's CC0
    # assets (60 subjects, a few seconds), as docs/makehuman.md builds it.
    try:
        m = caliper.load_model("makehuman", sex="female")
    except caliper.IoError:
        shared = Path(__file__).resolve().parents[3] / "shared" / "data"
        if not (shared / "makehuman").is_dir() or not (shared / "ansur2").is_dir():
            pytest.skip(f"no MakeHuman build and no assets to build one: {shared} has no makehuman/ and ansur2/")
        cli("model", "build", "makehuman", "--assets", str(shared / "makehuman"), "--ansur", str(shared / "ansur2"),
            "--sex", "female", "--subjects", "60", "-o", "makehuman-female.npz", cwd=tmp_path)
        m = caliper.load_model(str(tmp_path / "makehuman-female.npz"), sex="female")
    assert m.name == "makehuman-female" and m.vertex_count > 10000
    a = caliper.build_avatar(stature_cm=165, weight_kg=60, model=m)
    assert a.achieved["stature"] == pytest.approx(1.65, abs=0.005)
