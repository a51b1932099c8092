"""Memory check before a long march (estimate and the largest step count that fits) and march progress."""

import numpy as np
import pytest

from wingmdao.groups.load_case import LoadCase
from wingmdao.limits import (BASE_BYTES, BYTES_PER_NODE_STEP, PER_CASE_BYTES, check_memory, estimate_bytes,
                             march_progress)


def test_estimate_is_linear_in_nodes_and_steps():
    assert estimate_bytes(20, [1, 1]) == BASE_BYTES + 2 * PER_CASE_BYTES  # static cases: no history
    assert estimate_bytes(20, [4001]) == pytest.approx(BASE_BYTES + PER_CASE_BYTES + BYTES_PER_NODE_STEP * 20 * 4001)
    # the benchmark's 20-node peaks (360 MB at 251 steps, 601 MB at 1001, 1806 MB at 4001) lie under it
    assert estimate_bytes(20, [251]) > 360e6 and estimate_bytes(20, [1001]) > 601e6
    assert estimate_bytes(20, [4001]) > 1806e6
    # 1-3 gusts of 101 steps over 14 design points: 287, 357, 426 MB (bench_envelope.py, docs/gust-envelope.md)
    assert estimate_bytes(20, [101]) > 287e6 and estimate_bytes(20, [101] * 3) > 426e6


def test_too_long_march_fails_before_it_starts_with_largest_fitting_steps(monkeypatch):
    monkeypatch.delenv("WINGMDAO_SKIP_MEMORY_CHECK", raising=False)
    cases = [LoadCase("m"), LoadCase("g1", np.arange(4001) * 1e-3), LoadCase("g2", np.arange(4001) * 1e-3)]
    avail = 1.2e9
    fit = int((avail - BASE_BYTES - 3 * PER_CASE_BYTES) / (BYTES_PER_NODE_STEP * 20 * 2))  # 739 steps per case
    with pytest.raises(ValueError, match=rf"need an estimated 4331 MB .* 1200 MB available; the largest step "
                                         rf"count that fits is {fit} steps per dynamic case"):
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
    assert "500 MB available" in err and "largest step count that fits is 145 steps" in err


def test_progress_of_long_marches(monkeypatch, capsys):
    assert march_progress(100) is None
    monkeypatch.setenv("WINGMDAO_PROGRESS_STEPS", "50")
    cb = march_progress(101, "gust")
    for k in range(101):
        cb(k, 0.01 * k, None)
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 10 and lines[-1].startswith("  gust: step 100/100")
