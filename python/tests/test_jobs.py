"""The harness's other jobs from Python: the command's tables to the bit, and their arguments
checked before any run."""

import subprocess
import sys
import types

import numpy as np
import pytest

import cohesive_contact as cc

from conftest import SCENES, binary, same_bits


def rough_scene(tmp_path):
    s = cc.Scene.from_file(SCENES / "tiny-fem-rough-interface.toml")
    s.compare = {"models": ["standard", "hybrid"], "snapshot_t_over_T": 0.5}
    path = tmp_path / "rough.toml"
    s.save(path)
    return s, path


@pytest.mark.parametrize(
    "job,args",
    [("penalty", ["--factors", "100,200"]), ("rough", [])],
)
def test_a_job_gives_the_commands_tables_to_the_bit(job, args, tmp_path):
    if job == "penalty":
        s, path = cc.Scene.from_file(SCENES / "tiny-fem-center-crack.toml"), SCENES / "tiny-fem-center-crack.toml"
        r = cc.compare.penalty(s, factors=[100, 200], progress=False)
    else:
        s, path = rough_scene(tmp_path)
        r = cc.compare.rough(s, progress=False)
    cli_dir = tmp_path / "cli"
    subprocess.run([binary("compare"), job, *args, "--scene", path, "--out", cli_dir], check=True, capture_output=True)
    cli = cc.read_csv_folder(cli_dir)
    assert r.tables, "the job wrote tables"
    for name, cols in r.tables.items():
        assert list(cols) == list(cli[name]), name
        for c in cols:
            if c == "wall_s":  # wall time: each run's own
                assert np.all(cols[c] > 0)
                continue
            assert same_bits(cols[c], cli[name][c]), f"{name}.{c}"
    assert r.passed and r.failures == []


def test_job_arguments_are_checked_before_any_run(tmp_path):
    tiny = SCENES / "tiny-fem-center-crack.toml"
    with pytest.raises(ValueError, match=r"factors = \[0\]: whole numbers >= 1"):
        cc.compare.penalty(tiny, factors=[0], progress=False)
    with pytest.raises(ValueError, match=r"boxes = \[\]: whole numbers >= 1, at least one"):
        cc.compare.boundary(tiny, boxes=[], progress=False)
    with pytest.raises(ValueError, match='friction_rule = "nowhere": allowed'):
        cc.compare.gate(SCENES / "center-crack.toml", friction_rule="nowhere", progress=False)
    with pytest.raises(ValueError, match="concurrent_runs = 0"):
        cc.compare.gate(SCENES / "center-crack.toml", concurrent_runs=0, progress=False)
    s, _ = rough_scene(tmp_path)
    del s.compare.models
    with pytest.raises(cc.SceneError, match=r"compare\.models: missing"):
        cc.compare.sinusoid(s, progress=False)


def test_a_tqdm_bar_when_tqdm_is_there(monkeypatch, tmp_path):
    bars = []

    class Bar:
        def __init__(self, total, unit, desc, leave):
            self.total, self.n, self.desc, self.closed = total, 0, desc, False
            bars.append(self)

        def refresh(self):
            pass

        def close(self):
            self.closed = True

    auto = types.ModuleType("tqdm.auto")
    auto.tqdm = Bar
    monkeypatch.setitem(sys.modules, "tqdm", types.ModuleType("tqdm"))
    monkeypatch.setitem(sys.modules, "tqdm.auto", auto)
    cc.fem.run(SCENES / "tiny-fem-center-crack.toml")  # progress="auto"
    assert len(bars) == 1 and bars[0].desc == "FE" and bars[0].closed
    assert bars[0].n == bars[0].total == 655
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    with pytest.raises(ImportError, match="progress=True needs tqdm"):
        cc.fem.run(SCENES / "tiny-fem-center-crack.toml", progress=True)
    cc.fem.run(SCENES / "tiny-fem-center-crack.toml")  # "auto" without tqdm: no bar, no error
    assert len(bars) == 1
