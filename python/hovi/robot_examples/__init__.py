"""Deprecated: moved to ``hovi.examples.paper`` (this alias goes in the next release). Its modules
stay importable under the old names (``hovi.robot_examples.report`` is ``hovi.examples.paper.report``)."""
import sys
import warnings
from importlib import import_module
from importlib.util import spec_from_loader
from typing import Any

from ..examples.paper import NAMES, build

warnings.warn("hovi.robot_examples is deprecated: use hovi.examples.paper", DeprecationWarning, stacklevel=2)

_MODULES = ("example", "report", "contact_figures", "flamingo", "littledog", "atlas")
__all__ = ["NAMES", "build"]


class _Alias:
    """Finds hovi.robot_examples.X as hovi.examples.paper.X: the same module object, loaded once."""

    @classmethod
    def find_spec(cls, fullname: str, path: Any = None, target: Any = None) -> Any:
        prefix, _, name = fullname.rpartition(".")
        if prefix != __name__ or name not in _MODULES:
            return None
        return spec_from_loader(fullname, cls())

    def create_module(self, spec: Any) -> Any:
        module = import_module(f"hovi.examples.paper.{spec.name.rpartition('.')[2]}")
        self.spec = module.__spec__
        return module

    def exec_module(self, module: Any) -> None:
        module.__spec__ = self.spec  # the import system set the alias's; the module keeps its own


sys.meta_path.insert(0, _Alias())


def __getattr__(name: str) -> Any:
    if name in _MODULES:
        return import_module(f"hovi.examples.paper.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
