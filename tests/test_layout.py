"""The package's layout keeps the data flow (docs/architecture.md): every import goes down the
rooms (model -> scene -> steppers -> periodic driver -> analysis -> figures -> paper -> CLI), no
module imports itself back through others (no import circle, counting the imports inside
functions), no module is longer than 450 lines, and no module reaches into another one's
private names."""

import ast
import re
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "lcpfric"
MAX_LINES = 450

#: the rooms in the order of the data flow: a module may import its own room and those before
RANKS = (
    (
        "lcpfric.errors",
        "lcpfric._checks",
        "lcpfric._optional",
        "lcpfric.memory",
        "lcpfric.methods",
        "lcpfric.linalg",
    ),
    ("lcpfric.model", "lcpfric.results"),
    ("lcpfric.scene", "lcpfric.periodic.measure"),
    ("lcpfric.steppers", "lcpfric.backends", "lcpfric.exact"),
    ("lcpfric.periodic", "lcpfric.harmonic"),
    ("lcpfric.batch", "lcpfric.analysis"),
    ("lcpfric.figures",),
    ("lcpfric.paper",),
    ("lcpfric.cli", "lcpfric.__main__"),
)


def _modules() -> dict:
    out = {}
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        out[name] = path
    return out


MODULES = _modules()


def _rank(module: str) -> int:
    best, length = None, -1
    for rank, rooms in enumerate(RANKS):
        for room in rooms:
            if (module == room or module.startswith(room + ".")) and len(room) > length:
                best, length = rank, len(room)
    if best is None:
        raise AssertionError(f"{module} is in no room of RANKS")
    return best


def _resolve(module: str, level: int, name: str, is_package: bool) -> str:
    if level == 0:
        return module or ""
    base = name.split(".")
    if not is_package:
        base = base[:-1]
    base = base[: len(base) - (level - 1)]
    return ".".join(base + ([module] if module else []))


def _imports(name: str, path: Path):
    """``(target module, imported name or None, line)`` of every import in the module (inside
    functions too), within the package."""
    tree = ast.parse(path.read_text())
    is_package = path.name == "__init__.py"
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            target = _resolve(node.module, node.level, name, is_package)
            if not target.startswith("lcpfric"):
                continue
            for alias in node.names:
                full = f"{target}.{alias.name}"
                if full in MODULES:
                    yield full, None, node.lineno
                else:
                    yield target, alias.name, node.lineno
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("lcpfric"):
                    yield alias.name, None, node.lineno


EDGES = {
    name: {(t, n, line) for t, n, line in _imports(name, path)} for name, path in MODULES.items()
}


def test_no_module_is_longer_than_the_limit():
    long = {
        name: n
        for name, path in MODULES.items()
        if (n := len(path.read_text().splitlines())) > MAX_LINES
    }
    assert not long, f"modules above {MAX_LINES} lines: {long}"


def test_every_import_goes_down_the_rooms():
    """No arrow back up: a module imports only its own room and the rooms before it (the
    package's own ``__init__`` re-exports are not counted: they import nothing but errors at
    load time and the rest on first use)."""
    up = []
    for name, edges in EDGES.items():
        if name == "lcpfric":
            continue
        for target, _, line in edges:
            if target == "lcpfric":
                continue
            if _rank(target) > _rank(name):
                up.append(f"{name}:{line} -> {target}")
    assert not up, "imports back up the data flow:\n" + "\n".join(sorted(up))


def test_no_import_circle():
    """Tarjan's strongly connected components of the import graph (imports inside functions
    included; a package's re-exports of its own children are not edges back)."""
    graph = {
        name: {
            t
            for t, _, _ in edges
            if t in MODULES
            and t != name
            and not (name.startswith(t + ".") and t in MODULES and MODULES[t].name == "__init__.py")
        }
        for name, edges in EDGES.items()
    }
    index, low, stack, on, circles = {}, {}, [], set(), []
    counter = [0]

    def strong(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    for v in graph:
        if v not in index:
            strong(v)
    assert not circles, f"import circles: {circles}"


def _private_uses(name: str, path: Path):
    """Private names of other modules this module imports or reaches by attribute."""
    tree = ast.parse(path.read_text())
    imported = {}  # local name -> the module it came from
    out = []
    for target, alias, line in EDGES[name]:
        if target == name:
            continue
        if alias is not None:
            if alias.startswith("_") and not alias.startswith("__"):
                out.append(f"{name}:{line} imports {target}.{alias}")
            imported[alias] = target
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            for a in node.names:
                imported.setdefault(a.asname or a.name, "")
        if (
            isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name)
            and node.attr.startswith("_")
            and not node.attr.startswith("__")
            and imported.get(node.value.id)
        ):
            out.append(f"{name}:{node.lineno} uses {node.value.id}.{node.attr}")
    return out


def test_no_module_reaches_into_another_ones_private_names():
    found = [use for name, path in MODULES.items() for use in _private_uses(name, path)]
    assert not found, "private names used across modules:\n" + "\n".join(found)


@pytest.mark.parametrize(
    "room", ["model", "scene", "steppers", "backends", "exact", "periodic", "results", "methods"]
)
def test_the_early_rooms_import_no_figures_or_cli(room):
    for name in MODULES:
        if name == f"lcpfric.{room}" or name.startswith(f"lcpfric.{room}."):
            bad = [
                t
                for t, _, _ in EDGES[name]
                if t.startswith(("lcpfric.figures", "lcpfric.cli", "lcpfric.paper"))
            ]
            assert not bad, f"{name} imports {bad}"


TESTS = Path(__file__).resolve().parent
BENCHMARKS = TESTS.parent / "benchmarks"


def test_no_test_imports_a_benchmark_or_another_test():
    """Shared cases and references live in ``tests/support`` (a package of the tests), not in a
    benchmark script or a test file: a test imports neither, nor puts benchmarks/ on its path."""
    scripts = {p.stem for p in BENCHMARKS.rglob("*.py")}
    test_files = {p.stem for p in TESTS.glob("*.py")} - {"conftest"}
    bad = []
    for path in sorted(TESTS.rglob("*.py")):
        text = path.read_text(encoding="utf-8")
        for line in text.splitlines():
            if re.search(r"sys\.path(\.insert|\.append|\[)\S*.*benchmarks", line):
                bad.append(f"{path.name}: {line.strip()}")
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names = [node.module]
            else:
                continue
            for name in names:
                top = name.split(".")[0]
                if (
                    top == "benchmarks"
                    or top in test_files
                    or (top in scripts and top not in ("lcpfric", "support"))
                ):
                    bad.append(f"{path.relative_to(TESTS)}: imports {name}")
    assert not bad, bad
