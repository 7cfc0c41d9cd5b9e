"""Shared fixtures: the repository, its scenes, and the command-line binaries the package is
checked against (built by `cargo build --release --bins -p fem -p spectral -p compare`)."""

import os
import pathlib
import shutil

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
SCENES = REPO / "scenes"


def binary(name: str) -> pathlib.Path:
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    path = target / "release" / name
    if not path.exists():
        pytest.fail(
            f"{path} is missing: build the command lines first with "
            "`cargo build --release --bins -p fem -p spectral -p compare`"
        )
    return path


@pytest.fixture
def tiny_fem():
    """The tiny centre crack (FE only, 655 steps, 0.1 s)."""
    return SCENES / "tiny-fem-center-crack.toml"


@pytest.fixture
def tiny_both():
    """A tiny scene both models and the harness read (scenes/tiny-sweep.toml)."""
    return SCENES / "tiny-sweep.toml"


@pytest.fixture
def scratch(tmp_path):
    yield tmp_path
    shutil.rmtree(tmp_path, ignore_errors=True)


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal dtype, shape and values, floats to the bit (NaN included)."""
    if a.dtype != b.dtype or a.shape != b.shape:
        return False
    if a.dtype == np.float64:
        return bool(np.array_equal(a.view(np.uint64), b.view(np.uint64)))
    return bool(np.array_equal(a, b))
