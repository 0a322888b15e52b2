"""Model.reach and Model.plan against the command line (`ccrkit reach`, `ccrkit plan`): the
same JSON (all but the wall times), arrays equal to its numbers to the last bit,
the named exceptions Unreachable and NoPath, and bad arguments refused by name."""

import json
import subprocess

import numpy as np
import pytest

import ccrkit
from conftest import MODELS, _cli

BALL = (
    '[[obstacles]]\nname = "ball"\nshape = "sphere"\n'
    "position = [0.064, 0.111, 0.104]\nradius = 0.012\n"
)


def untimed(text):
    """The JSON without its wall times (`solve_time_s` of each shape, plan's `time_s`)."""

    def strip(x):
        if isinstance(x, dict):
            return {k: strip(v) for k, v in x.items() if k not in ("solve_time_s", "time_s")}
        if isinstance(x, list):
            return [strip(v) for v in x]
        return x

    return strip(json.loads(text))


def csv3(v):
    return ",".join(repr(float(x)) for x in v)


def actuation_file(path, cables, u):
    path.write_text(json.dumps({"actuation": [{"cable": c, "shorten": x} for c, x in zip(cables, u)]}))
    return path


def test_reach_matches_the_cli(case1, case1_path, cli):
    tip = case1.solve("energy", shorten=[0.006, 0.002]).tip
    r = case1.reach(tip)
    out = cli("reach", case1_path, "--tip", csv3(tip), "--json", "-")
    assert untimed(r.to_json()) == untimed(out)
    j = json.loads(out)
    assert r.reached and j["reached"]
    assert np.array_equal(r.shorten, [a["shorten"] for a in j["actuation"]])
    assert np.array_equal(r.tensions, [a["tension"] for a in j["actuation"]])
    assert np.array_equal(r.tip, j["tip"]) and np.array_equal(r.target, tip)
    assert r.tip_error_m == j["tip_error_m"] <= 1e-7
    assert r.effort_m2 == j["effort"]["value_m2"] == float(np.sum(r.shorten**2))
    assert np.array_equal(r.shape.disk_positions, [d["position"] for d in j["shape"]["disks"]])
    assert np.array_equal(r.shape.disk_rotations, [d["rotation"] for d in j["shape"]["disks"]])
    # The reported actuation solved forward gives the reported tip (1e-9 m).
    again = case1.solve("energy", shorten=r.shorten).tip
    assert np.linalg.norm(again - r.tip) <= 1e-9


def test_reach_with_a_tangent_matches_the_cli(case1, case1_path, cli):
    s = case1.solve("energy", shorten=[0.004, 0.004])
    tangent = s.disk_rotations[-1][:, 2] * 3.0  # normalized on both sides
    r = case1.reach(s.tip, tangent)
    out = cli("reach", case1_path, "--tip", csv3(s.tip), "--tangent", csv3(tangent), "--json", "-")
    assert untimed(r.to_json()) == untimed(out)
    assert r.reached and r.tangent_error_rad is not None


def test_unreachable_is_named_and_carries_the_closest_answer(case1, case1_path, cli):
    target = [0.0, 0.0, 0.5]
    with pytest.raises(ccrkit.Unreachable) as e:
        case1.reach(target)
    err = e.value
    assert isinstance(err, ccrkit.SolveError)
    assert err.kind == "unreachable" and err.field == "tip"
    assert err.target == target and len(err.closest) == 3
    assert err.distance == err.result.tip_error_m > 0.1
    assert not err.result.reached and err.result.reason
    # The command line exits ≠ 0 and still writes the same closest answer.
    out = subprocess.run(
        [_cli(), "reach", str(case1_path), "--tip", csv3(target), "--json", "-"],
        capture_output=True,
        text=True,
    )
    assert out.returncode != 0 and "unreachable" in out.stderr
    assert untimed(err.result.to_json()) == untimed(out.stdout)
    # Without `require`, the closest answer is returned.
    r = case1.reach(target, require=False)
    assert not r.reached and untimed(r.to_json()) == untimed(err.result.to_json())


def ball_model(tmp_path, case1_path):
    text = "clearance = 0.0005\n" + case1_path.read_text() + "\n" + BALL
    path = tmp_path / "ball.toml"
    path.write_text(text)
    return ccrkit.Model.load(path), path


def test_plan_matches_the_cli(tmp_path, case1_path, cli):
    model, path = ball_model(tmp_path, case1_path)
    start, goal = [0.014, 0.0], [0.0, 0.014]
    p = model.plan(to_actuation=goal, from_actuation=start, seed=3)
    fa = actuation_file(tmp_path / "from.json", model.cables, start)
    ta = actuation_file(tmp_path / "to.json", model.cables, goal)
    traj = tmp_path / "traj.csv"
    out = cli(
        "plan", path, "--from-actuation", fa, "--to-actuation", ta, "--seed", 3,
        "--json", "-", "--trajectory", traj,
    )
    theirs = untimed(out)
    assert untimed(p.to_json()) == theirs
    assert p.trajectory_csv() == traj.read_text()
    w = theirs["waypoints"]
    assert np.array_equal(p.shorten, [[a["shorten"] for a in x["actuation"]] for x in w])
    assert np.array_equal(p.tips, [x["tip"] for x in w])
    assert np.array_equal(p.clearances, [x["clearance_m"] for x in w])
    assert p.shorten[0].tolist() == start and p.shorten[-1].tolist() == goal
    assert p.min_clearance_m >= p.margin_m == 0.0005
    assert [s.tip.tolist() for s in p.shapes] == p.tips.tolist()
    assert p.statistics["planner"] == "rrt-connect" and p.cables == model.cables
    # Deterministic for a seed.
    assert model.plan(to_actuation=goal, from_actuation=start, seed=3).shorten.tolist() == p.shorten.tolist()


def test_plan_to_a_tip_and_no_path(tmp_path, case1_path):
    model, _ = ball_model(tmp_path, case1_path)
    tip = model.solve("energy", shorten=[0.0, 0.014]).tip
    p = model.plan(to_tip=tip, from_actuation=[0.014, 0.0])
    assert np.linalg.norm(p.tips[-1] - tip) <= 1e-7
    # Cable B held at zero: a one-dimensional actuation space, cut by a ball on the tip at
    # the middle shortening of A, so no path joins A = 14 mm and A = 0 (NoPath for certain).
    text = case1_path.read_text()
    mid = [float(x) for x in model.solve("energy", shorten=[0.007, 0.0]).tip]
    cut = (
        "clearance = 0.0005\n" + text + "\n[limits.B]\nshorten = [0.0, 0.0]\n"
        '[[obstacles]]\nname = "ball"\nshape = "sphere"\n'
        f"position = [{mid[0]!r}, {mid[1]!r}, {mid[2]!r}]\nradius = 0.002\n"
    )
    cut = ccrkit.Model.from_toml(cut, base_dir=case1_path.parent)
    with pytest.raises(ccrkit.NoPath) as e:
        cut.plan(to_actuation=[0.0, 0.0], from_actuation=[0.014, 0.0], max_samples=200)
    assert isinstance(e.value, ccrkit.SolveError)
    assert e.value.kind == "no_path" and e.value.samples == 200


def test_bad_arguments_are_named(case1, tmp_path, case1_path):
    with pytest.raises(ccrkit.InvalidInput) as e:
        case1.reach([0.0, 0.1])
    assert e.value.field == "tip"
    with pytest.raises(ccrkit.InvalidInput) as e:
        case1.reach([0.0, 0.0, 0.1], [0.0, 0.0, 0.0])
    assert e.value.field == "tangent"
    with pytest.raises(ccrkit.InvalidInput) as e:
        case1.reach([0.0, 0.0, 0.1], tolerance=-1.0)
    assert e.value.field == "tolerance"
    with pytest.raises(ccrkit.InvalidInput) as e:
        case1.reach([0.0, 0.0, 0.1], no_such_setting=1)
    model, _ = ball_model(tmp_path, case1_path)
    with pytest.raises(ccrkit.InvalidInput) as e:
        model.plan(to_tip=[0, 0, 0.1], to_actuation=[0.0, 0.0])
    assert e.value.field == "goal"
    with pytest.raises(ccrkit.InvalidInput) as e:
        model.plan(to_actuation=[0.0])
    assert e.value.field == "to_actuation"
    with pytest.raises(ccrkit.InvalidInput) as e:
        model.plan(to_actuation=[0.0, 0.014], from_actuation=[0.5, 0.0])
    assert e.value.field == "start"
    with pytest.raises(ccrkit.ModelError):
        model.plan(to_actuation=[0.0, 0.014], roadmap=tmp_path / "missing.json")


def test_plan_in_tension_space_matches_the_cli(cli):
    """The method's `control` chooses the space, as for `reach`: the soft rod planned by
    tension round the nodule gives the CLI's plan, with tensions [N] as the inputs."""
    rod = MODELS / "soft" / "lung_rod.toml"
    nodule = MODELS / "soft" / "nodule.toml"
    model = ccrkit.Model.load(rod).with_scene(nodule)
    p = model.plan(to_actuation=[1.0, 1.0, 1.0], method="energy", control="force")
    assert p.space == "tension"
    out = cli(
        "plan", rod, "--scene", nodule, "--set", "control=force",
        "--to-actuation", MODELS / "soft" / "nodule_goal.json", "--json", "-",
    )
    theirs = untimed(out)
    assert theirs["space"] == "tension"
    assert untimed(p.to_json()) == theirs
    w = theirs["waypoints"]
    assert np.array_equal(p.tensions, [[a["tension"] for a in x["actuation"]] for x in w])
    assert np.array_equal(p.shorten, [[a["shorten"] for a in x["actuation"]] for x in w])
    assert p.tensions[0].tolist() == [0.0, 0.0, 0.0] and p.tensions[-1].tolist() == [1.0, 1.0, 1.0]
