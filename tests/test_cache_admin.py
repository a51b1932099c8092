"""The compile cache's report and pruning (wingmdao.utils.cache_admin, `wingmdao cache`): last use
recorded at every load, only entries unused for longer than asked removed, manifest and library
together, leftovers of killed compiles, the command's JSON on standard output only."""

import json
import os
import time

import casadi as ca
import numpy as np
import pytest

from wingmdao.cli import main
from wingmdao.utils import cache_admin
from wingmdao.utils import casadi_cache as cc

DAY = 86400.0


def _library(folder, stem, age_days, now, size=100):
    lib = folder / f"{stem}.so"
    lib.write_bytes(b"x" * size)
    man = folder / f"{stem}.so.sha256"
    man.write_text(f"{size} 0\n")
    t = now - age_days * DAY
    os.utime(man, (t, t))
    os.utime(lib, (now, now))          # a library's own time is not its last use
    return lib, man


@pytest.fixture
def cache(tmp_path):
    now = time.time()
    folder = tmp_path / "cache"
    (folder / "functions").mkdir(parents=True)
    old = _library(folder, "beam20_jacobian_x_" + "a" * 32, 40, now)
    new = _library(folder, "beam20_jacobian_x_" + "b" * 32, 1, now)
    fun = folder / "functions" / ("BoxStress_f_" + "c" * 32 + ".npz")
    fun.write_bytes(b"y" * 50)
    os.utime(fun, (now - 35 * DAY, now - 35 * DAY))
    partial = folder / ".beam20_newton_abc.123.456.so"
    partial.write_bytes(b"z")
    os.utime(partial, (now - 2 * DAY, now - 2 * DAY))
    fresh_partial = folder / ".beam20_newton_abc.124.456.d"
    fresh_partial.mkdir()
    return folder, now, old, new, fun, partial, fresh_partial


def test_report_counts_without_removing(cache):
    folder, now, old, new, fun, partial, _ = cache
    s = cache_admin.prune(folder, 30, dry_run=True, now=now)
    assert (s["entries"], s["libraries"], s["functions"]) == (3, 2, 1)
    assert s["unused_entries"] == 2 and s["unused_bytes"] == 100 + len("100 0\n") + 50
    assert s["unused_names"] == ["BoxStress_f", "beam20_jacobian_x"]
    assert s["removed_entries"] == 0
    assert all(p.exists() for p in (*old, *new, fun, partial))


def test_prune_removes_only_the_unused_entries_and_stale_leftovers(cache):
    folder, now, old, new, fun, partial, fresh_partial = cache
    s = cache_admin.prune(folder, 30, now=now)
    assert s["removed_entries"] == 2 and s["removed_leftovers"] == 1
    assert not any(p.exists() for p in (*old, fun, partial))
    assert all(p.exists() for p in (*new, fresh_partial))       # used yesterday; a compile running now
    assert cache_admin.prune(folder, 0.5, now=now)["removed_entries"] == 1     # the 1-day-old one
    assert cache_admin.entries(folder) == []


def test_bad_day_count_is_refused(cache):
    with pytest.raises(ValueError, match="allowed range"):
        cache_admin.prune(cache[0], -1.0)
    with pytest.raises(ValueError, match="allowed range"):
        cache_admin.prune(cache[0], float("nan"))


@pytest.mark.skipif(cc.compiler() is None, reason="needs gcc")
def test_loading_a_library_records_its_use(tmp_path, monkeypatch):
    monkeypatch.setenv(cc.ENV_JIT, "1")
    monkeypatch.setenv(cc.ENV_CACHE, str(tmp_path / "cache"))
    x = ca.SX.sym("x", 2)
    f = ca.Function("use_probe", [x], [ca.sin(x) * x[1]])
    cc.compiled(f)
    (entry,) = cache_admin.entries(tmp_path / "cache")
    man = [p for p in entry.files if p.name.endswith(".sha256")][0]
    long_ago = time.time() - 100 * DAY
    os.utime(man, (long_ago, long_ago))
    assert cache_admin.prune(tmp_path / "cache", 30, dry_run=True)["unused_entries"] == 1
    g = cc.compiled(ca.Function("use_probe", [x], [ca.sin(x) * x[1]]))     # a cache hit
    assert g.class_name() == "External"
    assert time.time() - man.stat().st_mtime < 60
    assert cache_admin.prune(tmp_path / "cache", 30, dry_run=True)["unused_entries"] == 0
    np.testing.assert_allclose(np.array(g([0.3, 2.0]).full()).ravel(), np.sin([0.3, 2.0]) * 2.0)


def test_command_writes_only_json_to_stdout(cache, monkeypatch, capsys):
    folder, now, old, new, fun, partial, _ = cache
    monkeypatch.setenv(cc.ENV_CACHE, str(folder))
    assert main(["cache", "--json", "-"]) == 0
    out, err = capsys.readouterr()
    data = json.loads(out)
    assert data["unused_entries"] == 2 and data["dry_run"] is True and old[0].exists()
    assert "unused for more than 30 days" in err
    assert main(["cache", "--prune", "--json", "-"]) == 0
    out, _ = capsys.readouterr()
    assert json.loads(out)["removed_entries"] == 2 and not old[0].exists() and new[0].exists()
    assert main(["cache", "--unused-days", "-2"]) == 2
    assert "--unused-days = -2.0" in capsys.readouterr().err
