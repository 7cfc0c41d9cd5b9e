"""The result of one run, and the helpers every run shares (scene argument, progress)."""

from __future__ import annotations

import os
import warnings
from typing import Any, Callable, Dict, Optional, Tuple, Union

import numpy as np

from . import _native

Tables = Dict[str, Dict[str, np.ndarray]]
ProgressArg = Union[str, bool, None, Callable[[int, int], Any]]


class Result:
    """One run of one model: its tables as numpy arrays and how it went.

    Every CSV file the command line writes is a table, ``{column: numpy array}``, reachable as an
    attribute (``result.tips``, ``result.energy``, ``result.contact``, ``result.interface``, ...)
    or through ``result.tables``. docs/outputs.md lists every file and column with its unit (SI).
    Float columns are float64 (the run's values to the bit), integer columns int64, flags bool,
    names str.
    """

    def __init__(self, native: "_native.Run") -> None:
        self._native = native
        self._tables: Optional[Tables] = None

    @property
    def tables(self) -> Tables:
        """Every table of the run, ``{name: {column: array}}``, in the order the command line
        writes them (read once, then kept)."""
        if self._tables is None:
            self._tables = self._native.tables()
        return self._tables

    @property
    def summary(self) -> Dict[str, Any]:
        """How the run went: ``model``, ``ended`` ("finished", "unstable" or "interrupted"),
        ``why`` (when and where a run stopped before T), ``steps``, ``time_step`` [s],
        ``wall_time_s`` [s], ``threads``, ``warnings`` (e.g. contacts lost to the detection
        distance) and the model's own figures."""
        return self._native.summary

    @property
    def warnings(self) -> list:
        """What the user should know about the scene and the run."""
        return self.summary["warnings"]

    def write_csv(self, folder: Union[str, os.PathLike]) -> list:
        """Writes the run's CSV files into ``folder``, the same bytes as the command line's; returns
        their paths."""
        return [str(p) for p in self._native.write_csv(os.fspath(folder))]

    def to_pandas(self, table: Optional[str] = None):
        """A table as a ``pandas.DataFrame`` (``table`` given), or every table as a dict of
        them. Needs pandas, which the package does not depend on."""
        try:
            import pandas as pd
        except ImportError as e:
            raise ImportError("to_pandas() needs pandas: pip install pandas") from e
        if table is not None:
            return pd.DataFrame(self.tables[table])
        return {name: pd.DataFrame(cols) for name, cols in self.tables.items()}

    def __getattr__(self, name: str) -> Dict[str, np.ndarray]:
        if name.startswith("_"):
            raise AttributeError(name)
        tables = self.tables
        if name in tables:
            return tables[name]
        raise AttributeError(
            f"{name}: this run has no such table (it has: {', '.join(tables)}; docs/outputs.md)"
        )

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self.tables))

    def __repr__(self) -> str:
        s = self.summary
        return (
            f"<Result {s['model']}: {s['ended']}, {s['steps']} steps, dt = {s['time_step']:.4e} s, "
            f"wall {s['wall_time_s']:.2f} s; tables: {', '.join(self.tables)}>"
        )


def as_scene(scene: Union["_native.Scene", str, os.PathLike]) -> "_native.Scene":
    """A ``Scene``, or the path of a scene file."""
    if isinstance(scene, _native.Scene):
        return scene
    if isinstance(scene, (str, os.PathLike)):
        return _native.Scene.from_file(os.fspath(scene))
    raise TypeError(f"scene: a Scene or the path of a scene file, not {type(scene).__name__}")


def progress_callback(progress: ProgressArg, label: str) -> Tuple[Optional[Callable[[int, int], Any]], Callable[[], None]]:
    """The callback for ``progress`` and what closes it: "auto" (the default) draws a tqdm bar
    when tqdm is installed and nothing otherwise; True asks for the bar (an error without tqdm);
    False or None draws nothing; a callable is called with (steps done, total steps)."""
    if progress is None or progress is False:
        return None, lambda: None
    if callable(progress):
        return progress, lambda: None
    if progress not in ("auto", True):
        raise ValueError(f"progress = {progress!r}: \"auto\", True, False, None or a callable(done, total)")
    try:
        from tqdm.auto import tqdm
    except ImportError:
        if progress is True:
            raise ImportError("progress=True needs tqdm: pip install tqdm") from None
        return None, lambda: None
    bar = tqdm(total=0, unit="step", desc=label, leave=True)

    def update(done: int, total: int) -> None:
        if bar.total != total:
            bar.total = total
        bar.n = done
        bar.refresh()

    return update, bar.close


class ModelWarning(UserWarning):
    """What a model or the harness says the user should know about a scene or a run (the command
    lines print it as ``warning: ...``)."""


def with_partial(call: Callable[[], "_native.Run"]) -> Result:
    """``call()`` as a ``Result``, its warnings issued as ``ModelWarning``; an error that carries
    the run up to where it stopped (Ctrl-C, an unstable run) carries it as a ``Result`` too, in
    ``partial``."""
    try:
        result = Result(call())
    except BaseException as e:
        partial = getattr(e, "partial", None)
        if isinstance(partial, _native.Run):
            e.partial = Result(partial)
        raise
    for w in result.warnings:
        warnings.warn(w, ModelWarning, stacklevel=3)
    return result


class ModelRun:
    """``run(scene)`` of one model (``cc.fem.run``, ``cc.spectral.run``)."""

    def __init__(self, model: str, label: str) -> None:
        self._model = model
        self._label = label

    def __call__(
        self,
        scene: Union["_native.Scene", str, os.PathLike],
        *,
        max_memory_gib: float = 8.0,
        max_steps: int = 100_000_000,
        progress: ProgressArg = "auto",
    ) -> Result:
        """Runs the model on ``scene`` (a ``Scene`` or a scene file) from t = 0 to T, as the
        model's command (``fem``, ``spectral``) does.

        The scene is checked first, as the command checks it (``SceneError`` naming every bad key),
        then the run's estimate against the budget (``BudgetError``: ``max_memory_gib`` [GiB],
        ``max_steps``). The run releases the GIL. Ctrl-C stops it at its next step and raises
        ``KeyboardInterrupt``, whose ``partial`` is the run up to there; an unstable run raises
        ``RunUnstable`` (when and where) with its ``partial`` too. ``progress``: "auto" (a tqdm bar
        when tqdm is installed), True, False/None, or a callable(done, total) called on this
        thread. The result's warnings are issued as ``ModelWarning``.
        """
        s = as_scene(scene)
        callback, close = progress_callback(progress, self._label)
        try:
            return with_partial(
                lambda: _native.run(
                    s, self._model, max_memory_gib=max_memory_gib, max_steps=max_steps, progress=callback
                )
            )
        finally:
            close()

    def __repr__(self) -> str:
        return f"<cohesive_contact.{self._model}.run>"
