"""Type stubs of the extension module (PyO3). The scene's tables are typed in ``_tables.pyi``."""

import os
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

import numpy as np

from ._tables import (
    _TableView,
    CompareTable,
    CrackTable,
    FemTable,
    FrictionTable,
    InterfaceTable,
    LoadingTable,
    MaterialTable,
    SpectralTable,
)

__version__: str

class SceneError(ValueError):
    """A scene refused by the checks every command runs before its first step; the message is the
    command line's. ``problems``: (key, line, message) per problem (line None when the key is not in
    the text)."""

    problems: List[Tuple[str, Optional[int], str]]

class BudgetError(ValueError):
    """A run above its budget of steps or memory, refused before it starts."""

class RunUnstable(RuntimeError):
    """A run that went unstable; the message says when and where, ``partial`` is the run up to
    there."""

    partial: Any

class Table(_TableView):
    """A table of a scene: a live view; setting a key changes the scene."""

    def __getattr__(self, name: str) -> Any: ...
    def __setattr__(self, name: str, value: Any) -> None: ...
    def __delattr__(self, name: str) -> None: ...

class Scene:
    """A scene: the TOML text both models and the harness read (docs/scenes.md). Every key is an
    attribute; tables nest (``scene.fem.element_size = 2e-3``). A key keeps its kind (number,
    string, bool); values are checked by ``validate()`` and by every run, with the command lines'
    messages."""

    name: str
    """Name of the scene (its output folders)."""
    material: MaterialTable
    interface: InterfaceTable
    crack: CrackTable
    friction: FrictionTable
    loading: LoadingTable
    fem: FemTable
    spectral: SpectralTable
    compare: CompareTable

    @staticmethod
    def from_file(path: Union[str, os.PathLike]) -> "Scene":
        """Reads a scene file; relative paths in it start from its folder."""
    @staticmethod
    def from_str(text: str, base_dir: Optional[Union[str, os.PathLike]] = None) -> "Scene":
        """A scene from TOML text; relative paths start from ``base_dir`` (default: the working
        directory)."""
    def to_toml(self) -> str:
        """The scene as TOML: the original text, comments included, with every change."""
    def save(self, path: Union[str, os.PathLike]) -> None: ...
    def copy(self) -> "Scene": ...
    def validate(self) -> None:
        """Checks the scene as the command lines do; raises ``SceneError`` naming every bad key."""
    def warnings(self) -> List[str]:
        """The models' warnings on this scene (printed by the commands before a run)."""
    def to_dict(self) -> Dict[str, Any]: ...
    def keys(self) -> List[str]: ...
    @property
    def base_dir(self) -> str:
        """The folder relative paths in the scene start from."""
    def __getitem__(self, key: str) -> Any: ...
    def __setitem__(self, key: str, value: Any) -> None: ...
    def __delitem__(self, key: str) -> None: ...
    def __contains__(self, key: str) -> bool: ...

class Run:
    """One run of one model (wrapped by ``cohesive_contact.Result``)."""

    def tables(self) -> Dict[str, Dict[str, np.ndarray]]: ...
    def write_csv(self, folder: Union[str, os.PathLike]) -> List[str]: ...
    @property
    def summary(self) -> Dict[str, Any]: ...

ProgressCallback = Optional[Callable[[int, int], Any]]

def run(
    scene: Scene,
    model: str,
    *,
    max_memory_gib: float = 8.0,
    max_steps: int = 100000000,
    progress: ProgressCallback = None,
) -> Run:
    """Runs ``model`` ("fem" or "spectral") on ``scene`` from t = 0 to T."""
def job(
    scene: Scene,
    job: str,
    *,
    out: Optional[Union[str, os.PathLike]] = None,
    friction_rule: Optional[str] = None,
    concurrent_runs: Optional[int] = None,
    max_memory_gib: float = 8.0,
    max_steps: int = 100000000,
    progress: ProgressCallback = None,
    values: Optional[List[int]] = None,
) -> Dict[str, Any]:
    """Runs the harness's job ``job`` ("gate", "converged", "penalty", "boundary", "sinusoid",
    "rough") on ``scene``."""
def read_csv_folder(folder: Union[str, os.PathLike]) -> Dict[str, Dict[str, np.ndarray]]:
    """Every ``.csv`` file of ``folder`` as ``{file stem: {column: array}}``."""
