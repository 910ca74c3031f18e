"""Sphinx configuration of lcpfric's documentation.

Build it with ``python -m sphinx -W --keep-going -b html docs docs/_build/html`` (the ``docs``
extra installs what it needs: ``pip install ".[docs]"``).

Why Sphinx: the scientific-Python stack documents itself this way (numpy, scipy, xarray,
matplotlib): numpydoc renders the docstrings' sections, autosummary generates one page per
public name from the packages' ``__all__``, sphinx-gallery runs ``examples/`` during the build
(so the gallery cannot go stale), and MyST lets the guide pages stay Markdown, like the rest of
the repository's prose.
"""

import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MPLBACKEND", "Agg")

import lcpfric  # noqa: E402

project = "lcpfric"
author = "lcpfric developers"
copyright = "the lcpfric developers"
version = release = lcpfric.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.intersphinx",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = [
    "_build",
    "auto_examples/*.ipynb",
    "auto_examples/*.py",
    "auto_examples/*.zip",
    "auto_examples/*.json",
    "auto_examples/*.md5",
]
root_doc = "index"

# -- API reference ------------------------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": False, "inherited-members": False}
autodoc_typehints = "none"  # the numpydoc sections carry the types
numpydoc_show_class_members = True
numpydoc_class_members_toctree = False
numpydoc_show_inherited_class_members = False
numpydoc_xref_param_type = False
numpydoc_validation_checks = set()
add_module_names = False

intersphinx_mapping = {
    "python": ("https://docs.python.org/3", None),
    "numpy": ("https://numpy.org/doc/stable/", None),
    "scipy": ("https://docs.scipy.org/doc/scipy/", None),
}
# the build runs offline (CI has no network): no inventories are fetched
intersphinx_disabled_reftypes = ["*"]
intersphinx_mapping = {}

# -- MyST -------------------------------------------------------------------------------------
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3

# -- the gallery: examples/ run during the build ------------------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r".*\.py",  # every example runs (and its output is shown)
    "ignore_pattern": r"__init__\.py",
    "download_all_examples": False,
    "remove_config_comments": True,
    "matplotlib_animations": False,
    "within_subsection_order": "FileNameSortKey",
    "abort_on_example_error": True,
    "show_memory": False,
    "show_signature": False,
    "image_scrapers": ("matplotlib",),
}

# -- HTML -----------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"lcpfric {version}"
html_static_path = []
html_theme_options = {
    "navigation_depth": 2,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": [],
}
html_context = {"default_mode": "light"}
nitpicky = False
suppress_warnings = ["myst.header"]

# -- the API reference's pages, from the packages' __all__ (kept in step with the code) ---------
PACKAGES = {
    "lcpfric": "The top level: the driver, the models, the results and the registry",
    "lcpfric.model": "Models: loads, normal models, discrete systems, the single node",
    "lcpfric.model.continuum": "Continuum contacts: the MDR sphere, the half-plane, the half-space",
    "lcpfric.periodic": "The periodic steady state: the driver and its convergence measure",
    "lcpfric.steppers": "Time steppers",
    "lcpfric.backends": "Convex-solver backends",
    "lcpfric.exact": "The exact steady states",
    "lcpfric.linalg": "Linear algebra of the steppers",
    "lcpfric.analysis": "Analyses: closed forms and shakedown",
    "lcpfric.harmonic": "Harmonic balance: Fourier conventions, the AFT of Jenkins elements",
}


def _where(package, name: str) -> str:
    """A value (a constant) under the module that defines it, where its ``#:`` comment is (the
    autodoc reads it there); a class or function under the package."""
    import importlib
    import inspect
    import pkgutil
    import re

    obj = getattr(package, name)
    if inspect.isclass(obj) or inspect.isroutine(obj) or inspect.ismodule(obj):
        return name
    paths = getattr(package, "__path__", None) or []
    for info in pkgutil.iter_modules(paths, package.__name__ + "."):
        sub = importlib.import_module(info.name)
        if getattr(sub, name, None) is obj and re.search(
            rf"^{re.escape(name)}\s*[:=]", inspect.getsource(sub), re.M
        ):
            return f"{info.name[len(package.__name__) + 1 :]}.{name}"
    return name


def _write_api_index() -> None:
    import importlib

    lines = [
        "API reference",
        "=============",
        "",
        "Every public name: those of ``lcpfric`` and of each subpackage's ``__all__``",
        "(modules deeper in the tree are documented by their own docstrings in the source).",
        "A name that a subpackage shares with an earlier section links to its page there.",
        "",
    ]
    documented = set()
    for package, title in PACKAGES.items():
        module = importlib.import_module(package)
        names = [n for n in module.__all__ if n != "__version__"]
        new = [
            n
            for n in names
            if id(getattr(module, n)) not in documented
            or not hasattr(getattr(module, n), "__module__")
        ]
        shared = [n for n in names if n not in new]
        documented.update(id(getattr(module, n)) for n in new)
        lines += [
            f"``{package}``",
            "-" * (len(package) + 4),
            "",
            title + ".",
            "",
            f".. currentmodule:: {package}",
            "",
        ]
        if new:
            lines += [".. autosummary::", "   :toctree: generated", "   :nosignatures:", ""]
            lines += [f"   {_where(module, n)}" for n in new] + [""]
        if shared:
            lines += ["Also here: " + ", ".join(f"``{n}``" for n in shared) + ".", ""]
    out = Path(__file__).resolve().parent / "api" / "index.rst"
    out.parent.mkdir(exist_ok=True)
    text = "\n".join(lines)
    if not out.exists() or out.read_text() != text:
        out.write_text(text)


_write_api_index()
