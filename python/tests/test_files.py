"""Files Python writes and reads are under the command line's checks (`ccrkit::output`,
`ccrkit::model::read`): an output never lands on a file of the same call (the model file, a
scene file, a mesh), by its path, through `..` or a link, and is refused before any work by an
`InvalidInput` naming the argument and the reason; outputs are atomic, their folders created;
a model file is read once, capped like every model file."""

import os
import resource
import subprocess
import sys
import textwrap

import pytest

import ccrkit
from conftest import MODELS

TET = "v 1 1 1\nv 1.1 1 1\nv 1 1.1 1\nv 1 1 1.1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"


@pytest.fixture
def files(tmp_path):
    """`M.toml`: case 1 naming `scenes/room.toml` (the mesh `../meshes/tet.obj`, 1 m away);
    `extra.toml`: a scene of the mesh `meshes/extra.obj`."""
    (tmp_path / "meshes").mkdir()
    (tmp_path / "scenes").mkdir()
    (tmp_path / "meshes" / "tet.obj").write_text(TET)
    (tmp_path / "meshes" / "extra.obj").write_text(TET)
    mesh = 'name = "{}"\nshape = "mesh"\npath = "{}"\n'
    (tmp_path / "scenes" / "room.toml").write_text(
        "[[obstacles]]\n" + mesh.format("room", "../meshes/tet.obj"))
    (tmp_path / "extra.toml").write_text("[[obstacles]]\n" + mesh.format("extra", "meshes/extra.obj"))
    case1 = (MODELS / "paper" / "case1.toml").read_text()
    (tmp_path / "M.toml").write_text('scene = "scenes/room.toml"\n' + case1)
    return tmp_path


def snapshot(d):
    return {p: p.read_bytes() for p in sorted(d.rglob("*")) if p.is_file()}


def refused(call, argument, says):
    with pytest.raises(ccrkit.InvalidInput) as e:
        call()
    assert e.value.field == argument, str(e.value)
    assert says in str(e.value) and "would be overwritten: refused" in str(e.value), str(e.value)
    assert e.value.path is not None


def test_export_urdf_never_writes_over_a_file_of_the_model(files, case1):
    """Before, `export_urdf` wrote the URDF over the model file (or its scene, its mesh)."""
    model = ccrkit.Model.load(files / "M.toml").with_scene(files / "extra.toml")
    shape = case1.solve("energy")
    (files / "sub").mkdir()
    os.symlink(files / "M.toml", files / "link.toml")
    before = snapshot(files)
    for path, says in [
        ("M.toml", "the model file"),
        ("sub/../M.toml", "the model file"),
        ("link.toml", "the model file"),
        ("scenes/room.toml", "the scene file named in the model"),
        ("meshes/tet.obj", "the mesh file of obstacle `room`"),
        ("extra.toml", "the scene file added by `with_scene`"),
        ("meshes/extra.obj", "the mesh file of obstacle `extra`"),
    ]:
        for mode in ("articulated", "fixed"):
            refused(lambda: model.export_urdf(files / path, shape, mode=mode), "path", says)
    # The SRDF and joint values beside the URDF are outputs too: a JSON scene `w.joints.json`
    # is where `w.urdf`'s joint values would go.
    (files / "w.joints.json").write_text(
        '{"obstacles": [{"name": "w", "shape": "sphere", "position": [1, 1, 1], "radius": 0.1}]}')
    before = snapshot(files)
    with_json = model.with_scene(files / "w.joints.json")
    refused(lambda: with_json.export_urdf(files / "w.urdf", shape), "path",
            "the joint values (beside `path`) is the scene file added by `with_scene`")
    with_json.export_urdf(files / "w.urdf", shape, mode="fixed")
    assert (files / "w.urdf").exists() and snapshot(files)[files / "w.joints.json"] == before[
        files / "w.joints.json"]
    (files / "w.urdf").unlink()
    # Two outputs of one call on one file.
    with pytest.raises(ccrkit.InvalidInput, match="same file as the URDF") as e:
        model.export_urdf(files / "a.srdf", shape)
    assert e.value.field == "path"
    assert snapshot(files) == before, "nothing written"
    # A new folder is created, and no temporary file is left.
    written = model.export_urdf(files / "new" / "r.urdf", shape)
    assert sorted(os.listdir(files / "new")) == ["r.joints.json", "r.srdf", "r.urdf"]
    assert len(written) == 3


def test_build_roadmap_never_writes_over_a_file_of_the_model(files):
    """Before, `build_roadmap(out=)` built, then wrote the roadmap over the model file."""
    model = ccrkit.Model.load(files / "M.toml").with_scene(files / "extra.toml")
    before = snapshot(files)
    tiny = dict(samples=2, expand=0, neighbours=1)
    for out, says in [
        ("M.toml", "the model file"),
        ("scenes/../M.toml", "the model file"),
        ("scenes/room.toml", "the scene file named in the model"),
        ("extra.toml", "the scene file added by `with_scene`"),
        ("meshes/extra.obj", "the mesh file of obstacle `extra`"),
    ]:
        refused(lambda: model.build_roadmap(files / out, **tiny), "out", says)
    assert snapshot(files) == before, "nothing written"
    # A pickled model (a Dask worker's) keeps its files.
    import pickle

    again = pickle.loads(pickle.dumps(model))
    refused(lambda: again.build_roadmap(files / "M.toml", **tiny), "out", "the model file")


def test_a_model_file_is_read_capped(tmp_path):
    """Before, `Model.load` read the whole file into memory (a device never ended)."""
    big = tmp_path / "big.toml"
    with open(big, "wb") as f:
        f.truncate((64 << 20) + 1)
    with pytest.raises(ccrkit.ModelError) as e:
        ccrkit.Model.load(big)
    assert "64 MiB limit" in e.value.reason and e.value.path == str(big)


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="no /dev/zero")
def test_a_device_as_model_file_ends_in_a_named_error(tmp_path):
    """`Model.load("/dev/zero")` in a child with 2 GiB of address space: a named error, not
    an exhausted memory. The child runs in a scratch folder: `python -c` puts its working
    directory first on `sys.path`, and from `python/` that is the source tree's `ccrkit`
    without its compiled module, not the installed package."""
    code = textwrap.dedent("""
        import ccrkit
        try:
            ccrkit.Model.load("/dev/zero")
        except ccrkit.ModelError as e:
            print("refused:", e.reason)
    """)

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))

    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120, preexec_fn=limit, env=env, cwd=tmp_path)
    assert "refused: larger than the 64 MiB limit" in out.stdout, out.stdout + out.stderr


def test_a_shard_of_an_absurd_count_is_refused_by_name(case1):
    """`build_roadmap(shard=(0, 10**18))` built a shard no merge could hold, and
    `merge_roadmaps` of it aborted the interpreter (one flag per shard: 10¹⁸ bytes)."""
    tiny = dict(samples=2, expand=0, neighbours=1)
    with pytest.raises(ccrkit.InvalidInput) as e:
        case1.build_roadmap(shard=(0, 10**18), **tiny)
    assert e.value.field == "shard" and "10000" in e.value.reason
    part = case1.build_roadmap(shard=(0, 2), **tiny)
    lie = part.replace('"count":2', '"count":1000000000000000000')
    assert lie != part
    with pytest.raises(ccrkit.ModelError) as e:
        ccrkit.merge_roadmaps([lie])
    assert e.value.field == "shard" and "10000" in e.value.reason
