"""The hybrid (or standard) cohesive-contact FE model: ``run(scene)``, as the ``fem`` command."""

from ._result import ModelRun

run = ModelRun("fem", "FE")
"""Runs the FE model on a scene, as ``fem SCENE`` does (see ``ModelRun.__call__``)."""
