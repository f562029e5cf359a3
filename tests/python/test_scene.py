"""Scenes from TOML files: load_scene, and its refusals as Python exceptions that name the
file, the line, the key, the value and the allowed range, as `granular run` words them."""

import re

import pytest

import granular


def test_a_scene_loads_with_its_stages(bed_path):
    scene = granular.load_scene(bed_path)
    assert scene.stage_names == ["settle", "press"]
    assert scene.path == bed_path
    assert scene.warnings == []
    assert "bed.toml" in repr(scene)


def test_a_path_may_be_a_string(bed_path):
    assert granular.load_scene(str(bed_path)).stage_names == ["settle", "press"]


def test_a_missing_file_is_a_scene_error_naming_it(tmp_path):
    missing = tmp_path / "nowhere.toml"
    with pytest.raises(granular.SceneError, match="nowhere.toml"):
        granular.load_scene(missing)


def test_a_value_out_of_range_names_the_file_line_key_value_and_range(bed_text, write_scene):
    path = write_scene(bed_text.replace("friction = 0.3", "friction = -0.3"))
    with pytest.raises(granular.SceneError) as caught:
        granular.load_scene(path)
    message = str(caught.value)
    assert re.search(r"scene\.toml:\d+:\d+", message), message
    assert "material.friction" in message, message
    assert "-0.3" in message, message
    assert "must be in [0, 10]" in message, message


def test_a_scene_error_is_a_value_error(bed_text, write_scene):
    path = write_scene(bed_text.replace("friction = 0.3", "friction = -0.3"))
    with pytest.raises(ValueError):
        granular.load_scene(path)


@pytest.mark.parametrize(
    "old, new, key",
    [
        ("friction = 0.3", "frictoin = 0.3", "frictoin"),  # an unknown key
        ("friction = 0.3", 'friction = "high"', "material.friction"),  # a wrong type
        ("density = 500.0", "density = nan", "material.density"),  # not finite
        ("count = 120", "count = -5", "count"),  # out of range
        ('integrator = "verlet"', 'integrator = "euler"', "simulation.integrator"),  # no such
        ("time_step = 1.7e-4", "time_step = 0.0", "simulation.time_step"),  # must be > 0
    ],
)
def test_each_bad_value_is_refused_with_its_key(bed_text, write_scene, old, new, key):
    assert old in bed_text
    path = write_scene(bed_text.replace(old, new))
    with pytest.raises(granular.SceneError, match=re.escape(key)):
        granular.load_scene(path)


def test_a_file_that_is_not_toml_is_refused_with_its_line(write_scene):
    path = write_scene("[material]\nfriction = = 0.3\n")
    with pytest.raises(granular.SceneError, match=r"scene\.toml:2"):
        granular.load_scene(path)


def test_a_wrong_argument_type_is_a_type_error():
    with pytest.raises(TypeError):
        granular.load_scene(42)
