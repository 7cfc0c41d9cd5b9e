"""The FE-versus-spectral comparison: ``gate(scene)``, as ``cargo run --release -p compare``."""

from __future__ import annotations

import os
import warnings
from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np

from . import _native
from ._result import ModelWarning, ProgressArg, as_scene, progress_callback


class GateResult:
    """What the comparison gave: the metrics against their tolerances and both models' crack-tip
    histories (docs/outputs.md, "compare")."""

    def __init__(self, d: Dict[str, Any]) -> None:
        self.passed: bool = d["passed"]
        """True when every metric meets its tolerance."""
        self.metrics: Dict[str, np.ndarray] = d["metrics"]
        """metrics.csv: ``metric``, ``mu``, ``value``, ``tolerance``, ``pass``, ``note``."""
        self.tips: Dict[str, Dict[str, np.ndarray]] = d["tips"]
        """Tip histories per model and friction value (``fem_mu0``, ``spectral_mu0.3``, ...):
        ``t`` [s] (the spectral curves shifted by a/c_d), tip positions [m]."""
        self.files: List[str] = [str(p) for p in d["files"]]
        """Every file written (none when ``out`` was not given)."""
        self.warnings: List[str] = d["warnings"]
        """What the runs did that the user should know."""
        self.spacing: Tuple[float, float] = tuple(d["spacing"])
        """FE element size h and spectral grid spacing Δx of the runs [m]."""

    def to_pandas(self):
        """The metrics as a ``pandas.DataFrame`` (needs pandas)."""
        try:
            import pandas as pd
        except ImportError as e:
            raise ImportError("to_pandas() needs pandas: pip install pandas") from e
        return pd.DataFrame(self.metrics)

    def __repr__(self) -> str:
        m = self.metrics
        lines = [f"{'metric':<40} {'mu':>7} {'value':>10} {'tolerance':>10} {'pass':>5}"]
        for i in range(len(m["metric"])):
            lines.append(
                f"{m['metric'][i]:<40} {m['mu'][i]:>7} {m['value'][i]:>10.5f} {m['tolerance'][i]:>10} "
                f"{'yes' if m['pass'][i] else 'NO':>5}"
            )
        lines.append("all pass" if self.passed else "some metric fails")
        return "\n".join(lines)


def gate(
    scene: Union["_native.Scene", str, os.PathLike],
    *,
    out: Optional[Union[str, os.PathLike]] = None,
    friction_rule: Optional[str] = None,
    concurrent_runs: Optional[int] = None,
    max_memory_gib: float = 8.0,
    max_steps: int = 100_000_000,
    progress: ProgressArg = "auto",
) -> GateResult:
    """Runs the FE and the spectral model on ``scene`` for every friction value of
    ``[compare].friction_coeffs`` and compares their crack-tip histories with the paper-resolution
    tolerances, as ``cargo run --release -p compare -- --scene FILE`` does.

    ``out``: the folder of every file (tips, metrics, both models' outputs, figures), as the
    command line's ``--out``; without it they go to a temporary folder removed on return.
    ``friction_rule``: "all_faces" or "failed_only" in both models (``--friction-rule``).
    ``concurrent_runs``: runs side by side (default one per core). The scene and every run's
    budget are checked before the first run; Ctrl-C stops the runs and raises
    ``KeyboardInterrupt``.
    """
    s = as_scene(scene)
    callback, close = progress_callback(progress, "compare")
    try:
        d = _native.gate(
            s,
            out=None if out is None else os.fspath(out),
            friction_rule=friction_rule,
            concurrent_runs=concurrent_runs,
            max_memory_gib=max_memory_gib,
            max_steps=max_steps,
            progress=callback,
        )
    finally:
        close()
    result = GateResult(d)
    for w in result.warnings:
        warnings.warn(w, ModelWarning, stacklevel=2)
    return result
