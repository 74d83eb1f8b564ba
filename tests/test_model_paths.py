"""hovi.examples.models.urdf_path finds the URDFs installed with hovi from any working directory,
and refuses an unknown name by listing the ones there are."""
import os

import pytest

import hovi
from hovi.examples.models import urdf_path

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHIPPED = sorted(f[:-len(".urdf")] for f in os.listdir(os.path.join(ROOT, "models")) if f.endswith(".urdf"))


def test_every_shipped_urdf_is_found_from_anywhere(tmp_path, monkeypatch):
    """Every URDF of models/ is installed and found, with or without '.urdf', from a folder that is
    not the repository; the file is the repository's, byte for byte, and loads. urdf_path's
    docstring names each of them."""
    monkeypatch.chdir(tmp_path)
    assert SHIPPED, "models/ holds no URDF"
    for name in SHIPPED:
        path = urdf_path(name)
        assert path.is_absolute() and path.is_file() and path == urdf_path(name + ".urdf")
        with open(os.path.join(ROOT, "models", name + ".urdf"), "rb") as f:
            assert path.read_bytes() == f.read(), f"the installed {name}.urdf differs from models/ (reinstall hovi)"
        assert f"'{name}'" in urdf_path.__doc__, f"urdf_path's docstring does not name '{name}'"
    assert hovi.Model.from_urdf(urdf_path("two_link_arm")).joint_names == ["shoulder", "elbow"]


def test_unknown_name_lists_the_available_ones():
    with pytest.raises(ValueError, match="no URDF named 'ur5'") as e:
        urdf_path("ur5")
    for name in SHIPPED:
        assert name in str(e.value)
