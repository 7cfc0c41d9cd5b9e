"""The examples run, so they cannot rot: the script as a user runs it, and every code cell of the
notebook in order, in one namespace, as a kernel would (matplotlib draws off-screen)."""

import json
import os
import subprocess
import sys

import pytest

from conftest import REPO

EXAMPLES = REPO / "examples"


def test_the_script_runs_and_writes_its_figures(tmp_path):
    pytest.importorskip("matplotlib")
    out = subprocess.run(
        [sys.executable, EXAMPLES / "center_crack.py", "--out", tmp_path],
        capture_output=True, text=True, check=True,
    ).stdout
    assert "first motion [ms]" in out
    # three friction values, each with its own onset: friction delays the crack
    rows = [line.split() for line in out.splitlines() if line.strip().startswith(("0.0 ", "0.3 ", "0.6 "))]
    onsets = [float(r[1]) for r in rows]
    assert len(onsets) == 3 and onsets[0] < onsets[1] < onsets[2], out
    for png in ("tip_history.png", "friction_sweep.png"):
        assert (tmp_path / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_notebook_runs(monkeypatch):
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    nb = json.loads((EXAMPLES / "center_crack.ipynb").read_text())
    assert nb["nbformat"] == 4
    monkeypatch.chdir(EXAMPLES)
    namespace = {"__name__": "__main__"}
    cells = [c for c in nb["cells"] if c["cell_type"] == "code"]
    assert len(cells) >= 4
    for i, cell in enumerate(cells):
        exec(compile("".join(cell["source"]), f"center_crack.ipynb cell {i}", "exec"), namespace)
    onsets = namespace["onsets"]
    assert list(onsets) == [0.0, 0.3, 0.6] and onsets[0.0] < onsets[0.3] < onsets[0.6]
    assert namespace["result"].summary["ended"] == "finished"
