"""Memory check before a long march (estimate and the largest step count that fits) and march progress."""

import numpy as np
import pytest

from wingmdao.groups.load_case import LoadCase
from wingmdao.limits import (BASE_BYTES, BYTES_PER_NODE_STEP, BYTES_PER_NODE_STEP_CHECKPOINTED, PER_CASE_BYTES,
                             check_memory, estimate_bytes, fitting_steps, full_storage_steps, march_progress)


def test_estimate_is_piecewise_linear_in_steps_and_covers_the_measurements():
    assert estimate_bytes(20, [1, 1]) == BASE_BYTES + 2 * PER_CASE_BYTES  # static cases: no history
    full = full_storage_steps(20)
    assert 1000 < full < 1100   # 200 MB of blocks at 188 kB per step
    assert estimate_bytes(20, [4001]) == pytest.approx(BASE_BYTES + PER_CASE_BYTES + 20 * (
        BYTES_PER_NODE_STEP * full + BYTES_PER_NODE_STEP_CHECKPOINTED * (4001 - full)))
    # the benchmark's 20-node peaks (2026-12-03: 228 MB at 251 steps, 374 MB at 1001, 645 MB at
    # 4001) lie under it, by at most 45 %
    for steps, peak in ((251, 228e6), (1001, 374e6), (4001, 645e6)):
        assert peak < estimate_bytes(20, [steps]) < 1.45 * peak
    # 1-3 gusts of 101 steps over 14 design points: 287, 357, 426 MB (bench_envelope.py, docs/gust-envelope.md)
    assert estimate_bytes(20, [101]) > 287e6 and estimate_bytes(20, [101] * 3) > 426e6


def test_fitting_steps_is_the_largest_that_fits():
    for avail in (0.5e9, 0.8e9, 1.2e9, 3e9):
        fit = fitting_steps(20, 3, 2, avail)
        assert estimate_bytes(20, [1, fit, fit]) <= avail < estimate_bytes(20, [1, fit + 1, fit + 1])


def test_too_long_march_fails_before_it_starts_with_largest_fitting_steps(monkeypatch):
    monkeypatch.delenv("WINGMDAO_SKIP_MEMORY_CHECK", raising=False)
    cases = [LoadCase("m"), LoadCase("g1", np.arange(4001) * 1e-3), LoadCase("g2", np.arange(4001) * 1e-3)]
    avail = 1.2e9
    fit = fitting_steps(20, 3, 2, avail)
    need = estimate_bytes(20, [1, 4001, 4001])
    with pytest.raises(ValueError, match=rf"need an estimated {need / 1e6:.0f} MB .* 1200 MB available; the largest "
                                         rf"step count that fits is {fit} steps per dynamic case"):
        check_memory(cases, 20, available=avail)
    assert check_memory(cases[:1], 20, available=avail) == BASE_BYTES + PER_CASE_BYTES
    short = [LoadCase("g", np.arange(fit) * 1e-3)] * 2
    check_memory(short, 20, available=avail)


def test_cli_memory_limit_error(monkeypatch, capsys):
    from wingmdao.cli import main

    monkeypatch.delenv("WINGMDAO_SKIP_MEMORY_CHECK", raising=False)
    monkeypatch.setenv("WINGMDAO_MAX_MEMORY_MB", "500")
    rc = main(["size", "pegasus", "--loads", "gust", "--t-final", "4", "--dt", "0.001", "--no-plots", "--quiet",
               "--analysis-only"])
    assert rc != 0
    err = capsys.readouterr().err
    fit = fitting_steps(20, 1, 1, 500e6)   # 1237 steps (was 145 with the 2026-12-02 estimate)
    assert "500 MB available" in err and f"largest step count that fits is {fit} steps" in err


def test_progress_of_long_marches(monkeypatch, capsys):
    assert march_progress(100) is None
    monkeypatch.setenv("WINGMDAO_PROGRESS_STEPS", "50")
    cb = march_progress(101, "gust")
    for k in range(101):
        cb(k, 0.01 * k, None)
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 10 and lines[-1].startswith("  gust: step 100/100")


def test_progress_steps_switch_that_is_not_an_integer_is_refused(monkeypatch):
    """A bad WINGMDAO_PROGRESS_STEPS is an error naming the switch, not a silent default."""
    import pytest

    from wingmdao.limits import march_progress

    monkeypatch.setenv("WINGMDAO_PROGRESS_STEPS", "lots")
    with pytest.raises(ValueError, match=r"WINGMDAO_PROGRESS_STEPS = 'lots'; allowed an integer"):
        march_progress(5000)
    monkeypatch.setenv("WINGMDAO_PROGRESS_STEPS", "10")
    assert march_progress(5000) is not None and march_progress(5) is None
