"""A scene from Python: round trip, typed attribute access, changes kept in the text."""

import copy

import pytest

import cohesive_contact as cc

from conftest import SCENES


def test_round_trip_keeps_the_text_to_the_byte():
    for path in sorted(SCENES.glob("**/*.toml")):
        text = path.read_text()
        scene = cc.Scene.from_file(path)
        assert scene.to_toml() == text, path
        assert cc.Scene.from_str(scene.to_toml()).to_toml() == text, path


def test_values_read_as_python_types():
    s = cc.Scene.from_file(SCENES / "center-crack.toml")
    assert s.name == "center-crack"
    assert isinstance(s.material.youngs_modulus, float) and s.material.youngs_modulus == 70e6
    assert isinstance(s.spectral.grid_points, int) and s.spectral.grid_points == 4096
    assert s.fem.lateral_contraction is True
    assert s.fem.model == "hybrid"
    assert s.fem.x_range == [-0.25, 0.25]
    assert s.loading.normal.final == -0.05e6  # an inline table reads as a table
    assert s["loading"]["shear"]["ramp_end"] == 0.02
    assert isinstance(s.fem, cc.Table) and s.fem.name == "fem"
    assert "element_size" in s.fem and "element_size" in dir(s.fem)
    assert s.compare.friction_coeffs == [0.0, 0.3]


def test_a_change_keeps_its_line_and_comment_and_nothing_else():
    path = SCENES / "center-crack.toml"
    s = cc.Scene.from_file(path)
    s.fem.element_size = 2e-3
    s.loading.shear.final = 1.5e5
    before = path.read_text().splitlines()
    after = s.to_toml().splitlines()
    assert len(before) == len(after)
    changed = [(b, a) for b, a in zip(before, after) if b != a]
    assert len(changed) == 2, changed
    assert changed[0][1].startswith("shear = { initial = 0.0, final = 150000.0")
    assert changed[1][1].startswith("element_size = 0.002") and changed[1][1].endswith(
        "# m   (domain and crack tips must fall on nodes)"
    )
    assert cc.Scene.from_str(s.to_toml()).fem.element_size == 2e-3


def test_a_key_keeps_its_kind():
    s = cc.Scene.from_file(SCENES / "center-crack.toml")
    s.fem.element_size = 2  # an int where the scene has a float stays a float
    assert isinstance(s.fem.element_size, float) and "element_size = 2.0" in s.to_toml()
    with pytest.raises(TypeError, match=r"fem\.element_size: the scene has a number here, not a string"):
        s.fem.element_size = "2e-3"
    with pytest.raises(TypeError, match=r"fem\.lateral_contraction: the scene has a bool here, not a number"):
        s.fem.lateral_contraction = 1
    with pytest.raises(TypeError, match=r"fem\.model: a scene value is .* not object"):
        s.fem.model = object()


def test_numpy_values_are_taken():
    np = pytest.importorskip("numpy")
    s = cc.Scene.from_file(SCENES / "center-crack.toml")
    s.fem.element_size = np.float64(2e-3)
    s.spectral.grid_points = np.int64(2048)
    s.fem.x_range = np.array([-0.5, 0.5])
    assert (s.fem.element_size, s.spectral.grid_points, s.fem.x_range) == (2e-3, 2048, [-0.5, 0.5])


def test_keys_are_added_and_removed():
    s = cc.Scene.from_file(SCENES / "center-crack.toml")
    s.fem.t_star = 1e-5
    assert s.fem.t_star == 1e-5
    del s.fem.t_star
    assert "t_star" not in s.fem
    with pytest.raises(AttributeError, match=r"fem\.t_star: not in the scene \(the table has: x_range, "):
        s.fem.t_star
    s.fem.paraview = {"interval": 1e-3}
    assert s.fem.paraview.interval == 1e-3
    s.material = {"top": {"youngs_modulus": 1e8, "poisson_ratio": 0.3, "density": 2000.0},
                  "bottom": {"youngs_modulus": 7e7, "poisson_ratio": 0.35, "density": 1230.0}}
    assert s.material.top.density == 2000.0
    again = cc.Scene.from_str(s.to_toml())
    assert again.material.to_dict() == s.material.to_dict()
    assert again.fem.paraview == {"interval": 1e-3}


def test_copies_are_independent():
    s = cc.Scene.from_file(SCENES / "center-crack.toml")
    for c in (s.copy(), copy.copy(s), copy.deepcopy(s)):
        c.friction.friction_coeff = 0.6
        assert s.friction.friction_coeff == 0.3
    assert s == s.copy()


def test_a_file_that_is_not_toml_is_refused(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[fem\nelement_size = 1\n")
    with pytest.raises(cc.SceneError, match="scene does not parse"):
        cc.Scene.from_file(bad)
    with pytest.raises(OSError, match="missing.toml"):
        cc.Scene.from_file(tmp_path / "missing.toml")
