"""The harness's jobs from Python: ``gate(scene)`` (the FE-versus-spectral comparison, as
``cargo run --release -p compare``), ``converged``, ``penalty``, ``boundary``, ``sinusoid`` and
``rough``, each as the command's job of that name. ``sweep`` (one process per point) and
``suite`` (scenes of its own) stay on the command line; ``read_csv_folder`` reads their output."""

from __future__ import annotations

import os
import warnings
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._result import ModelWarning, ProgressArg, as_scene, progress_callback

SceneArg = Union["_native.Scene", str, os.PathLike]


class JobResult:
    """What a job of the harness gave (docs/outputs.md lists each job's files and columns)."""

    def __init__(self, d: Dict[str, Any]) -> None:
        self.passed: bool = d["passed"]
        """True when every metric meets its tolerance (the sinusoid studies: no run unstable;
        penalty and boundary have no tolerance and always pass)."""
        self.tables: Dict[str, Dict[str, np.ndarray]] = d["tables"]
        """Every CSV file the job wrote at the top of its folder, ``{file stem: {column: array}}``."""
        self.files: List[str] = [str(p) for p in d["files"]]
        """Every file written (none when ``out`` was not given)."""
        self.warnings: List[str] = d["warnings"]
        """What the runs did that the user should know."""
        self.failures: List[str] = d["failures"]
        """Runs that went unstable, with when and where (their output is kept)."""
        self.spacing: Optional[Tuple[float, float]] = None if d["spacing"] is None else tuple(d["spacing"])
        """FE element size h and spectral grid spacing Δx of the runs [m] (comparisons only)."""

    def to_pandas(self, table: str):
        """One table as a ``pandas.DataFrame`` (needs pandas)."""
        try:
            import pandas as pd
        except ImportError as e:
            raise ImportError("to_pandas() needs pandas: pip install pandas") from e
        return pd.DataFrame(self.tables[table])

    def __repr__(self) -> str:
        return f"<{type(self).__name__}: {'passed' if self.passed else 'FAILED'}; tables: {', '.join(self.tables)}>"


class GateResult(JobResult):
    """What the comparison gave: the metrics against their tolerances and both models' crack-tip
    histories."""

    def __init__(self, d: Dict[str, Any]) -> None:
        super().__init__(d)
        self.metrics: Dict[str, np.ndarray] = self.tables["metrics"]
        """metrics.csv: ``metric``, ``mu``, ``value``, ``tolerance``, ``pass``, ``note``."""
        self.tips: Dict[str, Dict[str, np.ndarray]] = {
            k: v for k, v in self.tables.items() if k.startswith(("fem_mu", "spectral_mu"))
        }
        """Tip histories per model and friction value (``fem_mu0``, ``spectral_mu0.3``, ...):
        ``t`` [s] (the spectral curves shifted by a/c_d), tip positions [m]."""

    def to_pandas(self, table: str = "metrics"):
        """The metrics (or another table) as a ``pandas.DataFrame`` (needs pandas)."""
        return super().to_pandas(table)

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


def _job(job: str, scene: SceneArg, out, progress: ProgressArg, **options) -> Dict[str, Any]:
    s = as_scene(scene)
    callback, close = progress_callback(progress, job)
    try:
        d = _native.job(s, job, out=None if out is None else os.fspath(out), progress=callback, **options)
    finally:
        close()
    for w in d["warnings"]:
        warnings.warn(w, ModelWarning, stacklevel=3)
    return d


class Comparison:
    """A job that compares the two models: ``gate`` (the paper-resolution tolerances) or
    ``converged`` (h = 0.5 mm, onsets within 0.01 T; its ``tables`` add ``converged``)."""

    def __init__(self, job: str) -> None:
        self._job = job

    def __call__(
        self,
        scene: SceneArg,
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
    ``concurrent_runs``: runs side by side (default one per core; one per two cores for FE runs
    on mapped meshes, as in ``sinusoid`` and ``rough``). The scene and every run's
    budget (``max_memory_gib`` [GiB], ``max_steps``) are checked before the first run; Ctrl-C
    stops the runs and raises ``KeyboardInterrupt``. ``progress`` as for ``fem.run``, over every
    run's steps.
    """
        return GateResult(
            _job(self._job, scene, out, progress, friction_rule=friction_rule, concurrent_runs=concurrent_runs,
                 max_memory_gib=max_memory_gib, max_steps=max_steps)
        )

    def __repr__(self) -> str:
        return f"<cohesive_contact.compare.{self._job}>"


gate = Comparison("gate")
"""The comparison, as ``cargo run --release -p compare -- --scene FILE`` (see ``Comparison``)."""
converged = Comparison("converged")
"""The comparison at h = 0.5 mm, as ``compare converged`` (see ``Comparison``)."""


def penalty(
    scene: SceneArg,
    *,
    factors: Optional[Sequence[int]] = None,
    out: Optional[Union[str, os.PathLike]] = None,
    concurrent_runs: Optional[int] = None,
    max_memory_gib: float = 8.0,
    max_steps: int = 100_000_000,
    progress: ProgressArg = "auto",
) -> JobResult:
    """Paper Appendix D, as ``compare penalty``: the FE model at ε_n = ε_t = f × E per metre for
    each factor f (default 100, 200, 300) and the mean contact tractions as ε_n → ∞."""
    return JobResult(
        _job("penalty", scene, out, progress, values=None if factors is None else list(factors),
             concurrent_runs=concurrent_runs, max_memory_gib=max_memory_gib, max_steps=max_steps)
    )


def boundary(
    scene: SceneArg,
    *,
    boxes: Optional[Sequence[int]] = None,
    out: Optional[Union[str, os.PathLike]] = None,
    concurrent_runs: Optional[int] = None,
    max_memory_gib: float = 8.0,
    max_steps: int = 100_000_000,
    progress: ProgressArg = "auto",
) -> JobResult:
    """The comparison in FE boxes k × (4a × 2a) (``boxes``, default 1, 2, 3) with the case's
    boundary field and the exact elastic one, as ``compare boundary``."""
    return JobResult(
        _job("boundary", scene, out, progress, values=None if boxes is None else list(boxes),
             concurrent_runs=concurrent_runs, max_memory_gib=max_memory_gib, max_steps=max_steps)
    )


class Section4:
    """Paper Section 4, as ``compare sinusoid`` (or ``compare rough``, the same study on a
    self-affine rough interface's scene): every model of ``[compare].models`` on the scene's
    interface, a summary row per model, KKT violations; ``failures`` names each run that went
    unstable (its output kept)."""

    def __init__(self, job: str) -> None:
        self._job = job

    def __call__(
        self,
        scene: SceneArg,
        *,
        out: Optional[Union[str, os.PathLike]] = None,
        concurrent_runs: Optional[int] = None,
        max_memory_gib: float = 8.0,
        max_steps: int = 100_000_000,
        progress: ProgressArg = "auto",
    ) -> JobResult:
        """Runs the study on ``scene``; arguments as for ``gate``."""
        return JobResult(
            _job(self._job, scene, out, progress, concurrent_runs=concurrent_runs,
                 max_memory_gib=max_memory_gib, max_steps=max_steps)
        )

    def __repr__(self) -> str:
        return f"<cohesive_contact.compare.{self._job}>"


sinusoid = Section4("sinusoid")
"""Paper Section 4 on the sinusoidal interface, as ``compare sinusoid`` (see ``Section4``)."""
rough = Section4("rough")
"""The same study on a self-affine rough interface, as ``compare rough`` (see ``Section4``)."""
