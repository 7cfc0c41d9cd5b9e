"""Bad values raise `SceneError` naming their key, with the command lines' own messages, before
any work; bad budgets raise `BudgetError` or `ValueError`."""

import subprocess

import pytest

import cohesive_contact as cc

from conftest import SCENES, binary

# (table, key, bad value): at least one per table, both models and the harness
BAD = [
    ("material", "density", -1.0),
    ("interface", "sigma_c", 0.0),
    ("crack", "half_length", -0.1),
    ("friction", "friction_coeff", -0.3),
    ("friction", "contact_friction", "nowhere"),
    ("loading", "duration", 0.0),
    ("fem", "element_size", -1.0),
    ("fem", "model", "nonsense"),
    ("fem", "eps_n", -1.0),
    ("fem", "damping", "x"),
    ("spectral", "grid_points", 3),
    ("spectral", "kernel_cutoff", -1.0),
    ("spectral", "t_star", -1.0),
    ("compare", "friction_coeffs", [0.0, 0.0]),
]


@pytest.mark.parametrize("table,key,value", BAD, ids=[f"{t}.{k}" for t, k, _ in BAD])
def test_each_bad_value_is_refused_naming_its_key(table, key, value):
    s = cc.Scene.from_file(SCENES / "center-crack.toml")
    s[table][key] = value
    with pytest.raises(cc.SceneError) as e:
        s.validate()
    name = f"{table}.{key}"
    assert name in str(e.value)
    assert [p[0] for p in e.value.problems] == [name]
    line = e.value.problems[0][1]
    assert s.to_toml().splitlines()[line - 1].startswith(key), "the line points into to_toml()"


def test_every_problem_at_once():
    s = cc.Scene.from_file(SCENES / "center-crack.toml")
    for table, key, value in BAD:
        s[table][key] = value
    with pytest.raises(cc.SceneError) as e:
        s.validate()
    keys = {p[0] for p in e.value.problems}
    # the shared tables' problems come first and stop the models' own sections, as on the
    # command line (docs/scenes.md, "Checks before any step")
    shared = {f"{t}.{k}" for t, k, _ in BAD if t in ("material", "interface", "crack", "friction", "loading")}
    assert shared <= keys, shared - keys
    assert str(e.value).startswith(f"{len(e.value.problems)} problems in the scene")


@pytest.mark.parametrize("model", ["fem", "spectral"])
def test_the_messages_are_the_command_lines(model, tmp_path):
    s = cc.Scene.from_file(SCENES / "center-crack.toml")
    s.fem.element_size = -1.0
    s.spectral.grid_points = 3
    s.interface.sigma_c = 0.0
    path = tmp_path / "bad.toml"
    s.save(path)
    run = getattr(cc, model).run
    with pytest.raises(cc.SceneError) as e:
        run(s, progress=False)
    cli = subprocess.run([binary(model), path, "--out", tmp_path / "out"], capture_output=True, text=True)
    assert cli.returncode == 1
    assert str(e.value) in cli.stderr, (str(e.value), cli.stderr)
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_a_run_above_its_budget_is_refused_before_it_starts(tiny_fem):
    with pytest.raises(cc.BudgetError, match=r"the run needs 655 time steps, above the budget of 10: .* max_steps=655"):
        cc.fem.run(tiny_fem, max_steps=10, progress=False)
    with pytest.raises(cc.BudgetError, match="max_memory_gib="):
        cc.fem.run(tiny_fem, max_memory_gib=1e-9, progress=False)
    for bad in (float("nan"), 0.0, -1.0, float("inf")):
        with pytest.raises(ValueError, match="max_memory_gib"):
            cc.fem.run(tiny_fem, max_memory_gib=bad, progress=False)
    with pytest.raises(OverflowError):
        cc.fem.run(tiny_fem, max_steps=-1, progress=False)


def test_a_scene_argument_that_is_neither_scene_nor_path():
    with pytest.raises(TypeError, match="scene: a Scene or the path of a scene file, not int"):
        cc.fem.run(3)
    with pytest.raises(ValueError, match="progress = 'bar'"):
        cc.fem.run(SCENES / "tiny-fem-center-crack.toml", progress="bar")
