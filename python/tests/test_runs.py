"""Runs from Python: tables as numpy arrays, the command lines' numbers to the bit, progress,
Ctrl-C and the GIL released."""

import filecmp
import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import cohesive_contact as cc

from conftest import SCENES, binary, same_bits


def test_tables_are_numpy_arrays_of_the_documented_columns(tiny_fem):
    r = cc.fem.run(tiny_fem, progress=False)
    assert r.summary["ended"] == "finished" and r.summary["steps"] == 655
    assert list(r.tips) == ["t", "tip_right", "tip_left", "cz_tip_right", "cz_tip_left"]
    n = len(r.tips["t"])
    for col in r.tips.values():
        assert col.dtype == np.float64 and col.shape == (n,)
    assert r.run["steps"].dtype == np.int64 and r.run["steps"][0] == 655
    assert r.run["lateral_contraction"].dtype == bool
    assert r.run["model"].dtype.kind == "U" and r.run["model"][0] == "hybrid"
    assert np.all(np.diff(r.tips["t"]) > 0)
    # the tip grows under the rising shear: a record that was read, not a default
    assert r.tips["tip_right"][-1] > r.tips["tip_right"][0]


def test_to_pandas():
    pd = pytest.importorskip("pandas")
    r = cc.fem.run(SCENES / "tiny-fem-center-crack.toml", progress=False)
    df = r.to_pandas("tips")
    assert isinstance(df, pd.DataFrame) and list(df.columns) == list(r.tips)


@pytest.mark.parametrize(
    "model,scene", [("fem", "tiny-fem-center-crack.toml"), ("fem", "tiny-fem-plate-tri.toml"), ("spectral", "tiny-sweep.toml")]
)
def test_the_command_lines_numbers_to_the_bit(model, scene, tmp_path):
    path = SCENES / scene
    r = getattr(cc, model).run(path, progress=False)
    cli_dir, py_dir = tmp_path / "cli", tmp_path / "py"
    subprocess.run([binary(model), path, "--out", cli_dir], check=True, capture_output=True)
    written = r.write_csv(py_dir)
    names = sorted(os.path.basename(p) for p in written)
    assert names == sorted(p.name for p in cli_dir.glob("*.csv"))
    for name in names:
        assert filecmp.cmp(cli_dir / name, py_dir / name, shallow=False), name
    cli = cc.read_csv_folder(cli_dir)
    assert sorted(cli) == sorted(r.tables)
    for table, cols in r.tables.items():
        assert list(cols) == list(cli[table]), table
        for c in cols:
            assert same_bits(cols[c], cli[table][c]), f"{table}.{c}"


def test_the_comparison_gives_the_command_lines_metrics_and_tips(tiny_both, tmp_path):
    s = cc.Scene.from_file(tiny_both)
    with pytest.raises(cc.SceneError, match=r"compare\.friction_coeffs: missing"):
        cc.compare.gate(s, progress=False)
    s.compare = {"friction_coeffs": [0.0, 0.3]}
    path = tmp_path / "both.toml"
    s.save(path)
    g = cc.compare.gate(s, progress=False)
    cli_dir = tmp_path / "cli"
    subprocess.run([binary("compare"), "--scene", path, "--out", cli_dir], capture_output=True)
    cli = cc.read_csv_folder(cli_dir)
    for c in g.metrics:
        assert same_bits(g.metrics[c], cli["metrics"][c]), c
    assert sorted(g.tips) == ["fem_mu0", "fem_mu0.3", "spectral_mu0", "spectral_mu0.3"]
    for name, cols in g.tips.items():
        for c in cols:
            assert same_bits(cols[c], cli[name][c]), f"{name}.{c}"
    assert g.passed == bool(np.all(g.metrics["pass"]))
    assert g.files == []
    kept = cc.compare.gate(s, out=tmp_path / "py", progress=False)
    assert all(os.path.exists(f) for f in kept.files) and any(f.endswith("metrics.csv") for f in kept.files)


def test_progress_reaches_the_total_on_the_calling_thread(tiny_fem):
    seen = []
    caller = threading.get_ident()
    cc.fem.run(tiny_fem, progress=lambda d, t: seen.append((d, t, threading.get_ident())))
    assert seen, "the callback was called"
    assert seen[-1][0] == seen[-1][1] == 655
    assert all(a[0] <= b[0] for a, b in zip(seen, seen[1:]))
    assert {s[2] for s in seen} == {caller}


# A run long enough to be stopped or watched: the paper's centre crack, FE model (~10 s)
LONG = SCENES / "center-crack.toml"


def test_an_error_in_the_progress_callback_stops_the_run():
    def boom(done, total):
        if done > 0:
            raise ValueError("enough")

    started = time.monotonic()
    with pytest.raises(ValueError, match="enough") as e:
        cc.fem.run(LONG, progress=boom)
    assert time.monotonic() - started < 5.0
    p = e.value.partial
    assert isinstance(p, cc.Result) and p.summary["ended"] == "interrupted"
    assert 0 < p.summary["steps"] < 20000 and "stopped on request at step" in p.summary["why"]
    assert len(p.tips["t"]) > 0


@pytest.fixture
def ctrl_c_raises():
    # Python raises KeyboardInterrupt on SIGINT only if SIGINT was not ignored when it started,
    # and a shell's background job (`cmd &` without job control) starts with it ignored: the
    # handler a user's interactive session has is set here, and the one before put back after.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_ctrl_c_stops_the_run_at_its_next_step(ctrl_c_raises):
    stopped = {}

    def interrupt():
        time.sleep(0.5)
        stopped["at"] = time.monotonic()
        os.kill(os.getpid(), signal.SIGINT)

    threading.Thread(target=interrupt, daemon=True).start()
    with pytest.raises(KeyboardInterrupt) as e:
        cc.fem.run(LONG, progress=False)
    # the calling thread looks every 20 ms; one step takes ~1 ms
    assert time.monotonic() - stopped["at"] < 1.0
    p = e.value.partial
    assert isinstance(p, cc.Result) and p.summary["ended"] == "interrupted"
    assert p.summary["steps"] > 0 and len(p.energy["t"]) > 0


def test_the_gil_is_released_while_a_model_runs():
    ticks = []
    running = threading.Event()
    done = threading.Event()

    def count():
        running.wait()
        while not done.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    s = cc.Scene.from_file(LONG)
    s.loading.duration = 0.004  # ~1 s of run
    running.set()
    started = time.monotonic()
    r = cc.fem.run(s, progress=False)
    ended = time.monotonic()
    done.set()
    t.join()
    during = [x for x in ticks if started < x < ended]
    assert ended - started > 0.3, "the run is long enough to watch"
    # a thread that sleeps 1 ms between ticks makes hundreds of them in 0.3 s when the GIL is
    # free; with the GIL held for the run it would make none until the run ends
    assert len(during) > 100, (len(during), ended - started)
    assert r.summary["ended"] == "finished"


def test_warnings_are_issued_and_kept(tiny_fem):
    s = cc.Scene.from_file(tiny_fem)
    s.fem.paraview = {"interval": 1e-4}
    with pytest.warns(cc.ModelWarning, match="fem.paraview: the ParaView snapshots are written by the fem command"):
        r = cc.fem.run(s, progress=False)
    assert any("fem.paraview" in w for w in r.warnings)


def test_to_pandas_without_pandas_says_how_to_get_it(tiny_fem, monkeypatch):
    import sys

    r = cc.fem.run(tiny_fem, progress=False)
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas raises ImportError
    with pytest.raises(ImportError, match="to_pandas\\(\\) needs pandas: pip install pandas"):
        r.to_pandas("tips")
