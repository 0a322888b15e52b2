"""Insertion and rotation through a model's port, from Python: `Model.solve` takes them and the
shape gives them back; `solve_batch` takes them as arrays, one per row, and returns each row's;
the same rows solved one by one give the same tips (the batch adds nothing of its own)."""

import math

import numpy as np
import pytest

import ccrkit
from conftest import MODELS

ROD = MODELS / "soft" / "lung_rod.toml"


def test_solve_takes_and_returns_insertion_and_rotation():
    m = ccrkit.Model.load(ROD)
    tension = [0.6, 0.3, 0.2]
    s = m.solve(tension=tension, insertion=0.07, rotation=1.2)
    assert s.insertion == 0.07 and s.rotation == 1.2
    # Turning by ψ turns the tip about the port axis (z at the origin here) by ψ.
    s0 = m.solve(tension=tension, insertion=0.07, rotation=0.0)
    c, d = math.cos(1.2), math.sin(1.2)
    x, y, z = s0.tip
    assert np.allclose(s.tip, [c * x - d * y, d * x + c * y, z], atol=1e-9)
    # A model without a port has neither, and refuses them by name.
    plain = ccrkit.Model.load(MODELS / "paper" / "case1.toml")
    assert plain.solve().insertion is None and plain.solve().rotation is None
    with pytest.raises(ccrkit.SolveError, match="insertion"):
        plain.solve(insertion=0.1)


def test_solve_batch_takes_insertion_and_rotation_arrays():
    m = ccrkit.Model.load(ROD)
    n = 6
    tension = np.tile([0.6, 0.3, 0.2], (n, 1))
    insertion = np.linspace(0.02, 0.12, n)
    rotation = np.linspace(-2.0, 2.0, n)
    rotation[3] = np.nan  # no rotation in that row
    b = ccrkit.solve_batch(m, tension=tension, insertion=insertion, rotation=rotation)
    assert (b.status == "ok").all(), b.errors
    assert np.array_equal(b.insertion, insertion)
    assert np.array_equal(b.rotation, np.nan_to_num(rotation, nan=0.0))
    for r in range(n):
        one = m.solve(tension=tension[r], insertion=insertion[r], rotation=b.rotation[r])
        assert np.allclose(b.tips[r], one.tip, atol=1e-9), r
    # One value per row, named when not.
    with pytest.raises(ccrkit.SolveError, match="insertion"):
        ccrkit.solve_batch(m, tension=tension, insertion=insertion[:3])
    # Kept through concatenation.
    both = ccrkit.Batch.concat([b, b])
    assert np.array_equal(both.insertion, np.concatenate([insertion, insertion]))


BLOCK = MODELS / "port" / "behind_block.toml"
TARGET = [-0.0585, 0.0429, 0.1353]


def test_plan_through_a_port_gives_insertion_and_rotation_per_waypoint():
    m = ccrkit.Model.load(BLOCK)
    p = m.plan(to_tip=TARGET)
    n = len(p.shapes)
    assert p.shorten.shape == (n, 2)
    assert p.insertion.shape == (n,) and p.rotation.shape == (n,)
    # The arrays are the shapes' own base values, and the plan inserts past the block.
    assert np.array_equal(p.insertion, [s.insertion for s in p.shapes])
    assert np.array_equal(p.rotation, [s.rotation for s in p.shapes])
    assert p.insertion[0] == 0.06 and p.insertion.max() > 0.126
    assert np.allclose(p.tips[-1], TARGET, atol=1e-6)
    # An actuation may carry the base values; a goal of the wrong length is refused by name.
    goal = np.concatenate([p.shorten[-1], [p.insertion[-1], p.rotation[-1]]])
    again = m.plan(to_actuation=goal)
    assert np.allclose(again.tips[-1], p.tips[-1], atol=1e-9)
    with pytest.raises(ccrkit.InvalidInput, match="to_actuation"):
        m.plan(to_actuation=goal[:3])
    # Without a port, neither.
    plain = ccrkit.Model.load(MODELS / "paper" / "case1.toml")
    q = plain.plan(to_actuation=[0.001, 0.0])
    assert q.insertion is None and q.rotation is None


def test_tension_solve_reports_shortenings_that_drive_the_shape_back():
    m = ccrkit.Model.load(ROD)
    s = m.solve(tension=[0.8, 0.5, 0.2], insertion=0.09, rotation=0.4)
    u = s.shortenings
    assert u.shape == (3,) and (u != 0).all()
    back = m.solve(shorten=u, insertion=0.09, rotation=0.4)
    assert np.allclose(back.disk_positions, s.disk_positions, atol=1e-9)
    assert np.allclose(back.tensions, [0.8, 0.5, 0.2], atol=1e-6)
