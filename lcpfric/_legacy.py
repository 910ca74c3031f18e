"""Module paths of lcpfric 0.1, kept importable after the package was arranged in rooms.

``from lcpfric.sweep import sweep`` (and the other 0.1 paths below) still works: a meta-path
finder maps the old name to its new module, which is imported once and shared, so
``lcpfric.sweep`` *is* ``lcpfric.analysis.sweep``. New code should use the new paths.
"""

from __future__ import annotations

import importlib
import importlib.machinery
import sys

#: old module path -> new module path
MOVED = {
    "lcpfric.sweep": "lcpfric.analysis.sweep",
    "lcpfric.analytic": "lcpfric.analysis.analytic",
    "lcpfric.shakedown": "lcpfric.analysis.shakedown",
    "lcpfric.bench": "lcpfric.analysis.convergence",
    "lcpfric.systems": "lcpfric.model.builders",
    "lcpfric.loads": "lcpfric.model.loads",
    "lcpfric.figures": "lcpfric.paper.figures",
    "lcpfric.motor": "lcpfric.paper.motor",
}


class _Alias:
    def __init__(self, target: str):
        self.target = target

    def create_module(self, spec):
        module = importlib.import_module(self.target)
        self._spec = module.__spec__
        return module

    def exec_module(self, module):
        # already executed under its new name; the import system has overwritten its
        # ``__spec__`` with the alias's: give it back
        module.__spec__ = self._spec


class _Finder:
    def find_spec(self, fullname, path=None, target=None):
        new = MOVED.get(fullname)
        if new is None:
            return None
        return importlib.machinery.ModuleSpec(fullname, _Alias(new))


def install() -> None:
    if not any(isinstance(f, _Finder) for f in sys.meta_path):
        sys.meta_path.append(_Finder())
