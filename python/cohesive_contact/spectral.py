"""The spectral boundary-integral model: ``run(scene)``, as the ``spectral`` command."""

from ._result import ModelRun

run = ModelRun("spectral", "spectral")
"""Runs the spectral model on a scene, as ``spectral SCENE`` does (see ``ModelRun.__call__``)."""
