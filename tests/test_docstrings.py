"""Every public name (``lcpfric`` and each subpackage's ``__all__``, the API reference's pages)
has a numpydoc docstring whose sections match its signature: a summary, every parameter in
Parameters and none that does not exist, a Returns section where it returns; the same for the
public methods of each class. Checked with numpydoc's own validator."""

import importlib
import inspect
from pathlib import Path

import pytest

from support import need_modules

PACKAGES = [
    "lcpfric",
    "lcpfric.model",
    "lcpfric.model.continuum",
    "lcpfric.periodic",
    "lcpfric.steppers",
    "lcpfric.backends",
    "lcpfric.exact",
    "lcpfric.linalg",
    "lcpfric.analysis",
    "lcpfric.harmonic",
]
# GL08: no docstring; SS01: no summary; PR01: a parameter not documented; PR02: a documented
# parameter that does not exist; RT01: no Returns section
CHECKS = {"GL08", "SS01", "PR01", "PR02", "RT01"}


def _public():
    names = {}
    for package in PACKAGES:
        module = importlib.import_module(package)
        for name in module.__all__:
            obj = getattr(module, name)
            if name != "__version__" and (inspect.isclass(obj) or inspect.isroutine(obj)):
                names.setdefault(id(obj), f"{package}.{name}")
    targets = []
    for qualified in names.values():
        targets.append(qualified)
        module, _, name = qualified.rpartition(".")
        obj = getattr(importlib.import_module(module), name)
        if inspect.isclass(obj):
            targets += [
                f"{qualified}.{a}"
                for a, v in vars(obj).items()
                if not a.startswith("_") and inspect.isfunction(v)
            ]
    return targets


def test_the_api_reference_lists_every_package():
    conf = (Path(__file__).resolve().parents[1] / "docs" / "conf.py").read_text()
    for package in PACKAGES:
        assert f'"{package}":' in conf


@pytest.mark.parametrize("target", _public())
def test_numpydoc_sections(target):
    need_modules("numpydoc")
    from numpydoc.validate import validate

    errors = [f"{code}: {msg}" for code, msg in validate(target)["errors"] if code in CHECKS]
    assert not errors, f"{target}: {errors}"
