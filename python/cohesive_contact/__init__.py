"""The hybrid cohesive-contact FE model of Pundir & Anciaux (2020), the spectral boundary-integral
model and their comparison, from Python.

>>> import cohesive_contact as cc
>>> scene = cc.Scene.from_file("scenes/tiny-fem-center-crack.toml")
>>> scene.friction.friction_coeff = 0.3
>>> result = cc.fem.run(scene)
>>> result.tips["t"], result.tips["half_length"]      # numpy arrays, SI units

The package is a thin layer over the Rust library the command lines use: a scene is checked by
the same functions, with the same messages; a run gives the same numbers, to the bit, as the
``fem`` and ``spectral`` commands on the same scene, and its tables are their CSV files
(docs/outputs.md lists every column with its unit).
"""

from ._native import (
    BudgetError,
    RunUnstable,
    Scene,
    SceneError,
    Table,
    __version__,
    read_csv_folder,
)
from ._result import ModelWarning, Result
from . import compare, fem, spectral

__all__ = [
    "BudgetError",
    "ModelWarning",
    "Result",
    "RunUnstable",
    "Scene",
    "SceneError",
    "Table",
    "__version__",
    "compare",
    "fem",
    "read_csv_folder",
    "spectral",
]
