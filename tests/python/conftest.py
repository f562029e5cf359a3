"""Fixtures of the Python module's tests: the bed's scene, and scene files written for a test."""

import pathlib

import pytest

HERE = pathlib.Path(__file__).resolve().parent


@pytest.fixture
def bed_path():
    """The bed's scene file (tests/python/bed.toml)."""
    return HERE / "bed.toml"


@pytest.fixture
def bed_text(bed_path):
    """The bed's scene as text, to write changed copies of."""
    return bed_path.read_text()


@pytest.fixture
def write_scene(tmp_path):
    """Writes `text` to a scene file in the test's own folder; returns its path."""

    def write(text, name="scene.toml"):
        path = tmp_path / name
        path.write_text(text)
        return path

    return write
