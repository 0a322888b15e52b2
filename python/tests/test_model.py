"""Model, Shape and the CLI: arrays equal the CLI's --json to the last bit."""

import json
import pickle
import re

import numpy as np
import pytest

import ccrkit
from conftest import MODELS, ROOT


def without_time(text):
    """JSON text without the (timing) solve_time_s line."""
    return re.sub(r'\n\s*"solve_time_s": [^\n]*', "", text)


def cli_json(cli, path, method, *extra):
    return cli("solve", path, "--method", method, "--json", "-", *extra)


@pytest.mark.parametrize(
    "method,settings,flags",
    [
        ("energy", {}, []),
        ("energy", {"length": "chord", "sub_arcs": 3}, ["--set", "length=chord", "--set", "sub-arcs=3"]),
        ("geometric", {}, []),
        ("cosserat", {}, []),
        ("constant-curvature", {}, []),
    ],
)
def test_shape_equals_cli_json(cli, case1, case1_path, method, settings, flags):
    shape = case1.solve(method, **settings)
    text = cli_json(cli, case1_path, method, *flags)
    assert without_time(shape.to_json()) == without_time(text.rstrip("\n"))
    j = json.loads(text)
    disks = j["disks"]
    assert np.array_equal(shape.disk_positions, np.array([d["position"] for d in disks]))
    assert np.array_equal(shape.disk_rotations, np.array([d["rotation"] for d in disks]))
    assert np.array_equal(shape.disk_s, np.array([d["s"] for d in disks]))
    assert np.array_equal(shape.tip, np.array(disks[-1]["position"]))
    assert np.array_equal(shape.backbone, np.array(j["backbone"]))
    for c in j["cables"]:
        assert np.array_equal(shape.cable_paths[c["name"]], np.array(c["points"]))
    want_t = [c.get("tension", np.nan) for c in j["cables"]]
    assert np.array_equal(shape.tensions, np.array(want_t), equal_nan=True)
    rep = dict(j["report"])
    got = shape.report
    rep.pop("solve_time_s"), got.pop("solve_time_s")
    assert got == rep
    assert shape.converged == rep["converged"]
    assert shape.stable == rep.get("stable")
    assert shape.disk_positions.shape == (case1.sections + 1, 3)
    assert shape.disk_rotations.shape == (case1.sections + 1, 3, 3)


def test_contacts_equal_cli_json(cli, case1, case1_path):
    wall = MODELS / "scenes" / "wall.toml"
    shape = case1.with_scene(wall).solve("energy")
    j = json.loads(cli_json(cli, case1_path, "energy", "--scene", wall))
    assert len(shape.contacts) == len(j["contacts"]) >= 1
    for got, want in zip(shape.contacts, j["contacts"]):
        assert got["obstacle"] == want["obstacle"] == "wall"
        assert got["feature"] == want["feature"]
        assert got["disk"] == want.get("disk") and got["section"] == want.get("section")
        for k in ("point_robot", "point_obstacle", "normal"):
            assert np.array_equal(got[k], np.array(want[k]))
        assert got["distance"] == want["distance"] and got["reaction"] == want["multiplier"]


def test_model_attributes(case1):
    assert case1.cables == ["A", "B"]
    assert case1.name == "paper-case-1" and case1.sections == 9
    # 4 % and 3 % of the 9 x 20 mm straight chord.
    assert np.allclose(case1.cable_lengths, [0.18, 0.18], rtol=0, atol=1e-15)
    assert np.allclose(case1.shorten, [0.04 * 0.18, 0.03 * 0.18], rtol=1e-15)
    assert np.array_equal(case1.tension, [4.16925, 3.8259])
    assert case1.obstacles == [] and case1.with_scene(MODELS / "scenes" / "wall.toml").obstacles == ["wall"]
    assert len(case1.obstacles) == 0, "with_scene returns a new model"


def test_overrides_equal_a_file_with_those_inputs(case1, case1_path):
    text = case1_path.read_text()
    edited = text.replace("shorten_percent = 4.0", "shorten = 0.005").replace(
        "shorten_percent = 3.0", "shorten = 0.002"
    )
    edited = re.sub(r"\ntension = [^\n]*", "", edited)
    want = ccrkit.Model.from_toml(edited).solve("energy")
    got = case1.solve("energy", shorten=np.array([0.005, 0.002]))
    assert np.array_equal(got.disk_positions, want.disk_positions)
    # A list works too, and NaN leaves a cable undriven (free) — by tension it is pulled.
    got = case1.solve("cosserat", tension=[4.0, float("nan")])
    free = ccrkit.Model.from_toml(re.sub(r"\n(shorten_percent|tension) = [^\n]*", "", text)
                                  .replace('angles = { straight = 0.0 }', 'angles = { straight = 0.0 }\ntension = 4.0'))
    assert np.array_equal(got.disk_positions, free.solve("cosserat").disk_positions)
    assert np.isnan(got.tensions[1]) or got.tensions[1] == 0.0


def test_settings_by_name_and_unknown_refused(case1):
    a = case1.solve("energy", sub_arcs=8)
    b = case1.solve("energy", **{"sub-arcs": "8"})
    assert np.array_equal(a.disk_positions, b.disk_positions)
    assert a.backbone.shape != case1.solve("energy").backbone.shape
    with pytest.raises(ccrkit.InvalidInput) as e:
        case1.solve("energy", rk4_steps=3)
    assert e.value.field == "rk4-steps" and "cosserat" in e.value.reason
    with pytest.raises(ccrkit.InvalidInput) as e:
        case1.solve("energy", no_such_setting=1)
    assert e.value.field == "no-such-setting"
    with pytest.raises(ccrkit.InvalidInput) as e:
        case1.solve("energy", sub_arcs=0)
    assert e.value.field == "sub-arcs"
    with pytest.raises(ccrkit.InvalidInput) as e:
        case1.solve("nonsense")
    assert e.value.field == "method" and "energy" in e.value.reason


def test_errors_are_named_exceptions(case1, tmp_path):
    with pytest.raises(ccrkit.Infeasible) as e:
        case1.solve("energy", shorten=[0.5, 0.0])
    assert e.value.cable == "A" and e.value.field == "A" and e.value.kind == "infeasible"
    with pytest.raises(ccrkit.NotConverged) as e:
        case1.solve("energy", length="chord", max_iterations=1)
    assert e.value.iterations >= 1 and e.value.residual > 0 and e.value.method == "energy"
    with pytest.raises(ccrkit.Unsupported) as e:
        case1.with_scene(MODELS / "scenes" / "wall.toml").solve("constant-curvature")
    assert e.value.method == "constant-curvature" and "obstacles" in e.value.reason
    with pytest.raises(ccrkit.InvalidInput) as e:
        case1.solve("energy", shorten=[0.001, 0.001, 0.001])
    assert e.value.field == "shorten"
    with pytest.raises(ccrkit.InvalidInput) as e:
        case1.solve("energy", tension=[-1.0, 1.0], control="force")
    assert e.value.field == "cables[0].tension"
    with pytest.raises(ccrkit.ModelError) as e:
        ccrkit.Model.load(tmp_path / "missing.toml")
    assert "missing.toml" in e.value.path
    bad = (ROOT / "models" / "paper" / "case1.toml").read_text().replace("sections = 9", "sections = 0")
    with pytest.raises(ccrkit.ModelError) as e:
        ccrkit.Model.from_toml(bad)
    assert e.value.field == "robot.sections"
    for cls in (ccrkit.InvalidInput, ccrkit.ModelError, ccrkit.Infeasible, ccrkit.NotConverged,
                ccrkit.Obstructed, ccrkit.Unsupported, ccrkit.ExportError):
        assert issubclass(cls, ccrkit.SolveError)


def test_obstructed(case1_path):
    text = case1_path.read_text() + (
        '\n[[obstacles]]\nname = "ball"\nshape = "sphere"\nposition = [0.0, 0.0, 0.0]\nradius = 0.05\n'
    )
    with pytest.raises(ccrkit.Obstructed) as e:
        ccrkit.Model.from_toml(text).solve("geometric")
    assert e.value.obstacle == "ball" and e.value.field == "ball"


def test_methods_list_the_registry(cli):
    ms = ccrkit.methods()
    names = [m["name"] for m in ms]
    text = cli("methods")
    listed = [line for line in text.splitlines() if line and not line.startswith(" ")]
    assert names == listed
    energy = next(m for m in ms if m["name"] == "energy")
    assert "sub-arcs" in [s["name"] for s in energy["settings"]]
    assert energy["obstacles"] is True and energy["contact_unit"] == "N"


def test_export_urdf_equals_cli(cli, case1, case1_path, tmp_path):
    shape = case1.solve("energy")
    written = case1.export_urdf(tmp_path / "py" / "robot.urdf", shape)
    assert [p.name for p in map(__import__("pathlib").Path, written)] == [
        "robot.urdf", "robot.srdf", "robot.joints.json"]
    cli("export", "urdf", case1_path, "--method", "energy", "--out", tmp_path / "cli" / "robot.urdf")
    for name in ("robot.urdf", "robot.srdf", "robot.joints.json"):
        assert (tmp_path / "py" / name).read_text() == (tmp_path / "cli" / name).read_text()
    with pytest.raises(ccrkit.InvalidInput) as e:
        case1.export_urdf(tmp_path / "x.urdf", shape, mode="bent")
    assert e.value.field == "mode"


def test_pickling(case1, case1_path, tmp_path):
    m = pickle.loads(pickle.dumps(case1.with_scene(MODELS / "scenes" / "wall.toml")))
    assert m.obstacles == ["wall"] and m.source == case1_path
    a, b = m.solve("energy"), case1.with_scene(MODELS / "scenes" / "wall.toml").solve("energy")
    assert np.array_equal(a.disk_positions, b.disk_positions)
    # A model from text keeps its base directory for relative scene paths.
    text = case1_path.read_text().replace('name = "paper-case-1"', 'name = "x"\nscene = "../scenes/wall.toml"')
    t = ccrkit.Model.from_toml(text, base_dir=case1_path.parent)
    t2 = pickle.loads(pickle.dumps(t))
    assert t2.obstacles == ["wall"] and t2.source is None
    s = case1.solve("cosserat")
    s2 = pickle.loads(pickle.dumps(s))
    assert s2.to_json() == s.to_json()
    for k in ("disk_positions", "disk_rotations", "backbone", "tensions"):
        assert np.array_equal(getattr(s, k), getattr(s2, k), equal_nan=True)


def test_check_unique_is_the_cli_check():
    """`check_unique=True` is `ccrkit solve --check unique`: the report's `unique` object."""
    m = ccrkit.Model.load(str(MODELS / "paper" / "case1.toml"))
    u = m.solve("energy", check_unique=True).report["unique"]
    assert u["only"] is True and u["equilibria"] == 1
    assert u["other_model"]["verdict"] == "agrees"
    assert "unique" not in m.solve("energy").report
