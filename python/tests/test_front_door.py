"""One way in: the default method is the core's (the CLI's when no --method is given), and
every shape handed out, a batch row's too, has passed the output check (finite, not through
itself), its outcome named in the core's one vocabulary (STATUSES)."""

import json

import numpy as np

import ccrkit
from test_model import without_time


def test_the_default_method_is_the_clis(cli, case1, case1_path):
    assert ccrkit.DEFAULT_METHOD == "energy"
    text = cli("solve", case1_path, "--json", "-")
    assert json.loads(text)["method"] == ccrkit.DEFAULT_METHOD
    shape = case1.solve()
    assert without_time(shape.to_json()) == without_time(text.rstrip("\n"))
    b = ccrkit.solve_batch(case1, shorten=case1.shorten[None, :], warm_start=False)
    assert b.method == ccrkit.DEFAULT_METHOD
    assert np.array_equal(b.tips[0], shape.tip)


def test_a_row_through_itself_is_obstructed_never_ok(case1):
    # Cable 0 shortened by 99.99 % of its length instead of 4 %: the default method curls the
    # robot through itself (the CLI refuses the same file: `obstructed by self`).
    s = np.array(case1.shorten, dtype=float)
    through = s.copy()
    through[0] *= 99.99 / 4.0
    b = ccrkit.solve_batch(case1, shorten=np.stack([s, through]), warm_start=False)
    assert list(b.status) == ["ok", "obstructed"]
    assert "passes through itself" in b.errors[1]
    assert np.isnan(b.tips[1]).all()
    assert set(b.status) <= set(ccrkit.STATUSES)
    try:
        case1.solve(shorten=through)
        raise AssertionError("a shape through itself was handed out")
    except ccrkit.Obstructed as e:
        assert e.obstacle == "self" and e.kind == "obstructed"
    assert {"ok", "obstructed", "not_converged", "panicked"} <= set(ccrkit.STATUSES)
