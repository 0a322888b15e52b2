"""solve_batch: rows equal single solves, bad rows never abort, threads change nothing,
the GIL is released, batches pickle and concatenate."""

import pickle
import threading

import numpy as np
import pytest

import ccrkit


def rows(model, n, lo=0.3, hi=1.0):
    """n rows: the file's shortenings scaled from lo to hi."""
    return np.outer(np.linspace(lo, hi, n), model.shorten)


def test_cold_rows_equal_single_solves(case1):
    s = rows(case1, 7)
    b = ccrkit.solve_batch(case1, shorten=s, warm_start=False, full=True)
    assert list(b.status) == ["ok"] * 7 and b.ok.all() and b.converged.all()
    for r in range(7):
        shape = case1.solve("energy", shorten=s[r])
        assert np.array_equal(b.tips[r], shape.tip)
        assert np.array_equal(b.disk_positions[r], shape.disk_positions)
        assert np.array_equal(b.disk_rotations[r], shape.disk_rotations)
        assert np.array_equal(b.tensions[r], shape.tensions)
        assert b.iterations[r] == shape.report["iterations"]
        assert b.residual[r] == shape.report["residual"]


def test_bad_rows_never_abort(case1):
    s = rows(case1, 6)
    s[1, 0] = np.inf  # invalid input
    s[3, 1] = 1.0  # longer than the cable: infeasible
    b = ccrkit.solve_batch(case1, shorten=s)
    assert list(b.status) == ["ok", "invalid_input", "ok", "infeasible", "ok", "ok"]
    assert np.isnan(b.tips[[1, 3]]).all() and not np.isnan(b.tips[[0, 2, 4, 5]]).any()
    assert "cables[0].shorten" in b.errors[1] and b.errors[0] is None
    assert b.counts() == {"ok": 4, "invalid_input": 1, "infeasible": 1}
    assert set(b.status) <= set(ccrkit.STATUSES)
    # Not converging is a row status too.
    nc = ccrkit.solve_batch(case1, shorten=s[:1], length="chord", max_iterations=1)
    assert list(nc.status) == ["not_converged"] and nc.iterations[0] >= 1


def test_threads_change_nothing_and_warm_starts_stay_within_tolerance(case1):
    s = rows(case1, 40)
    one = ccrkit.solve_batch(case1, shorten=s, threads=1, chunk=8, length="chord")
    two = ccrkit.solve_batch(case1, shorten=s, threads=2, chunk=8, length="chord")
    assert np.array_equal(one.tips, two.tips) and np.array_equal(one.iterations, two.iterations)
    cold = ccrkit.solve_batch(case1, shorten=s, warm_start=False, length="chord")
    assert np.abs(one.tips - cold.tips).max() < 1e-8
    assert one.iterations.sum() < cold.iterations.sum()


def test_tension_rows_and_settings(case1):
    t = np.outer(np.linspace(0.2, 1.0, 5), case1.tension)
    b = ccrkit.solve_batch(case1, tension=t, method="cosserat", warm_start=False)
    for r in range(5):
        assert np.array_equal(b.tips[r], case1.solve("cosserat", tension=t[r]).tip)
    assert np.allclose(b.tensions, t)
    with pytest.raises(ccrkit.InvalidInput) as e:
        ccrkit.solve_batch(case1, tension=t, method="cosserat", sub_arcs=3)
    assert e.value.field == "sub-arcs"
    with pytest.raises(ccrkit.InvalidInput) as e:
        ccrkit.solve_batch(case1, shorten=np.zeros((3, 3)))
    assert e.value.field == "shorten"
    with pytest.raises(ccrkit.InvalidInput) as e:
        ccrkit.solve_batch(case1, shorten=np.zeros((3, 2)), tension=np.zeros((2, 2)))
    assert e.value.field == "tension"
    with pytest.raises(ccrkit.InvalidInput):
        ccrkit.solve_batch(case1)
    with pytest.raises(ccrkit.InvalidInput) as e:
        ccrkit.solve_batch(case1, shorten=np.zeros((3, 2)), threads=0)
    assert e.value.field == "threads"


def test_gil_is_released(case1):
    s = rows(case1, 3000)
    done = threading.Event()
    out = {}

    def work():
        out["b"] = ccrkit.solve_batch(case1, shorten=s, threads=1, warm_start=False)
        done.set()

    t = threading.Thread(target=work)
    spins = 0
    t.start()
    while not done.is_set():
        spins += 1
    t.join()
    assert out["b"].ok.all()
    # Holding the GIL would leave this thread a handful of switch intervals at most.
    assert spins > 10_000, spins


def test_batches_pickle_and_concatenate(case1):
    s = rows(case1, 20)
    whole = ccrkit.solve_batch(case1, shorten=s, chunk=4, full=True)
    parts = [ccrkit.solve_batch(case1, shorten=s[i:i + 8], chunk=4, full=True) for i in (0, 8, 16)]
    joined = ccrkit.Batch.concat(pickle.loads(pickle.dumps(p)) for p in parts)
    for k in ("tips", "iterations", "residual", "tensions", "disk_positions", "disk_rotations"):
        assert np.array_equal(getattr(whole, k), getattr(joined, k)), k
    assert list(whole.status) == list(joined.status) and len(joined) == 20


def test_rows_carry_the_single_solves_estimate_when_asked(case1):
    s = rows(case1, 4)
    plain = ccrkit.solve_batch(case1, shorten=s, warm_start=False)
    assert np.isnan(plain.error_estimate).all()
    b = ccrkit.solve_batch(case1, shorten=s, warm_start=False, estimate=True)
    assert b.ok.all()
    for r in range(4):
        one = case1.solve("energy", shorten=s[r], estimate=True)
        assert one.error_estimate is not None and one.error_estimate > 0.0
        assert b.error_estimate[r] == one.error_estimate
    both = ccrkit.Batch.concat([plain, b])
    assert np.isnan(both.error_estimate[:4]).all()
    assert np.array_equal(both.error_estimate[4:], b.error_estimate)
    back = pickle.loads(pickle.dumps(b))
    assert np.array_equal(back.error_estimate, b.error_estimate)
