"""The house rules, read from the code's own imports.

- no import loop in ``physics/``, ``app/`` or ``assets/`` (module level and inside functions alike);
- no private name (one leading underscore) imported from another project module;
- no project module imported inside a function, except in a command-line entry (``__main__``);
- no module over 600 lines;
- ``physics/`` never imports ``app/``, viser or anything above it;
- outside ``app/guards/``, no private part of another object or of viser reached: no ``x._name`` (nor
  ``getattr(x, "_name")``) on anything but ``self``/``cls``, no import of viser's private modules or names
  (``app/guards/handles.py`` and its neighbours are the one door; docs/viser-internals.md lists them);
- no scene imports ``app.guards`` (it is composed from the kit, ``app.draw`` and ``app.controls``);
- docs/architecture.md names every package of ``app/`` and every module in it, and nothing that is not there;
- no ``Any`` for a context, app, client, server, simulation, scene or session anywhere in ``app/``; no class
  outside ``app/guards/`` forwards unknown attributes (``__getattr__``); mypy checks ``app/`` as strictly as
  ``physics/``;
- no comment or docstring cites an issue by number (it says why in words);
- tests/app/ mirrors app/'s packages;
- no two modules of ``app/`` share a name (a door at app/'s top named as the module it opens onto, or the
  same name in two packages, makes a reader ask which one does the job).

``python -m tests.test_architecture`` prints the figures (loops, private imports, lazy imports, largest
modules) for a closing note.
"""

from __future__ import annotations

import ast
import functools
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("physics", "app", "assets")
PROJECT = ("physics", "app", "assets", "benchmarks", "lectures")
MAX_LINES = 600
# Command-line entries may import lazily: `rigid-body-lab export` should not pay for viser's start-up.
LAZY_ALLOWED = {"app.__main__"}


@dataclass
class Module:
    name: str
    path: Path
    lines: int
    imports: set[str] = field(default_factory=set)  # project modules imported anywhere
    private: list[str] = field(default_factory=list)  # "module.name" of private names imported
    lazy: list[str] = field(default_factory=list)  # project modules imported inside a function


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _resolve(module: str, node: ast.ImportFrom, is_package: bool) -> str:
    if node.level == 0:
        return node.module or ""
    base = module.split(".")
    if not is_package:
        base = base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def read_modules(packages: tuple[str, ...] = PACKAGES) -> dict[str, Module]:
    modules: dict[str, Module] = {}
    for package in packages:
        for path in sorted((ROOT / package).rglob("*.py")):
            name = module_name(path)
            source = path.read_text(encoding="utf-8")
            modules[name] = Module(name, path, source.count("\n") + (not source.endswith("\n")))
    for module in modules.values():
        tree = ast.parse(module.path.read_text(encoding="utf-8"))
        is_package = module.path.name == "__init__.py"
        _collect(module, tree, modules, is_package, inside_function=False)
    return modules


def _target(name: str, modules: dict[str, Module]) -> str | None:
    """The project module that ``name`` (a dotted import path) refers to, or None outside the project."""
    while name:
        if name in modules:
            return name
        name = name.rpartition(".")[0]
    return None


def _collect(
    module: Module, node: ast.AST, modules: dict[str, Module], is_package: bool, inside_function: bool
) -> None:
    for child in ast.iter_child_nodes(node):
        if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            _collect(module, child, modules, is_package, inside_function=True)
            continue
        if isinstance(child, ast.If) and _is_type_checking(child.test):
            continue  # annotations only: never executed, never a loop at run time
        targets: list[tuple[str, str | None]] = []
        if isinstance(child, ast.Import):
            targets = [(alias.name, None) for alias in child.names]
        elif isinstance(child, ast.ImportFrom):
            base = _resolve(module.name, child, is_package)
            for alias in child.names:
                sub = f"{base}.{alias.name}"
                targets.append((sub, None) if sub in modules else (base, alias.name))
        for name, imported in targets:
            target = _target(name, modules)
            if target is None or name.split(".")[0] not in PROJECT:
                continue
            if target != module.name:
                module.imports.add(target)
            if inside_function:
                module.lazy.append(target)
            if imported and imported.startswith("_") and not imported.startswith("__") and target != module.name:
                module.private.append(f"{target}.{imported}")
        _collect(module, child, modules, is_package, inside_function)


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def import_graph(modules: dict[str, Module]) -> dict[str, set[str]]:
    """Who imports whom. A package's ``__init__`` re-exporting its own sub-modules is not an edge: that is
    how a package shows its public names. A module importing a package above it is one (running back up).
    """
    return {
        name: {t for t in m.imports if t in modules and t != name and not (is_package(m) and t.startswith(name + "."))}
        for name, m in modules.items()
    }


def is_package(m: Module) -> bool:
    return m.path.name == "__init__.py"


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan's algorithm), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


_ATTRIBUTE_CALLS = ("getattr", "setattr", "hasattr", "delattr")


def private_reaches(source: str) -> list[str]:
    """Where ``source`` reaches into a private part of another object or of viser: "line: code" each."""
    found = []
    for node in ast.walk(ast.parse(source)):
        reach = None
        if isinstance(node, ast.Attribute) and node.attr.startswith("_") and not node.attr.startswith("__"):
            if not (isinstance(node.value, ast.Name) and node.value.id in ("self", "cls")):
                reach = node
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in _ATTRIBUTE_CALLS:
            owner, name = (node.args + [None, None])[:2]
            private = isinstance(name, ast.Constant) and isinstance(name.value, str) and name.value.startswith("_")
            if private and not name.value.startswith("__"):  # type: ignore[union-attr]
                if not (isinstance(owner, ast.Name) and owner.id in ("self", "cls")):
                    reach = node
        elif isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] == "viser":
            if any(p.startswith("_") for p in (node.module or "").split(".")) or any(
                a.name.startswith("_") for a in node.names
            ):
                reach = node
        elif isinstance(node, ast.Import) and any(
            a.name.split(".")[0] == "viser" and any(p.startswith("_") for p in a.name.split(".")) for a in node.names
        ):
            reach = node
        if reach is not None:
            found.append(f"{reach.lineno}: {ast.unparse(reach)}")
    return sorted(set(found), key=lambda line: int(line.split(":")[0]))


def viser_reaches_outside_guards() -> dict[str, list[str]]:
    """Every private reach (:func:`private_reaches`) in app/ outside app/guards/, by file."""
    out = {}
    for path in sorted((ROOT / "app").rglob("*.py")):
        if path.relative_to(ROOT / "app").parts[0] == "guards":
            continue
        reaches = private_reaches(path.read_text(encoding="utf-8"))
        if reaches:
            out[str(path.relative_to(ROOT))] = reaches
    return out


@functools.cache
def figures() -> dict[str, object]:
    modules = read_modules()
    graph = import_graph(modules)
    loops = cycles(graph)
    back_up = [f"{a} -> {b}" for a, targets in graph.items() for b in targets if a.startswith(b + ".")]
    private = [f"{m.name} <- {p}" for m in modules.values() for p in m.private]
    lazy = [f"{m.name} -> {t}" for m in modules.values() if m.name not in LAZY_ALLOWED for t in m.lazy]
    long = sorted(((m.lines, m.name) for m in modules.values()), reverse=True)
    physics_up = [
        f"{m.name} -> {t}"
        for m in modules.values()
        if m.name.startswith("physics")
        for t in m.imports
        if not t.startswith("physics")
    ]
    return {
        "loops": loops,
        "back_up": back_up,
        "private": private,
        "lazy": lazy,
        "over_limit": [(n, name) for n, name in long if n > MAX_LINES],
        "largest": long[:6],
        "physics_up": physics_up,
        "app_top_level_files": sorted(p.name for p in (ROOT / "app").glob("*.py")),
        "private_reaches": viser_reaches_outside_guards(),
        "scenes_on_guards": [
            f"{m.name} -> {t}"
            for m in modules.values()
            if m.name.startswith("app.scenes")
            for t in m.imports
            if t.startswith("app.guards")
        ],
    }


def test_no_import_loop() -> None:
    assert figures()["loops"] == []


def test_no_import_runs_back_up_into_its_own_package() -> None:
    assert figures()["back_up"] == []


def test_no_private_name_crosses_a_module() -> None:
    assert figures()["private"] == []


def test_no_project_import_inside_a_function() -> None:
    assert figures()["lazy"] == []


def test_every_module_at_most_600_lines() -> None:
    assert figures()["over_limit"] == []


def test_physics_imports_nothing_above_it() -> None:
    assert figures()["physics_up"] == []


def test_app_has_at_most_8_files_at_its_top() -> None:
    assert len(figures()["app_top_level_files"]) <= 8  # type: ignore[arg-type]


def test_no_private_part_of_viser_or_another_object_reached_outside_guards() -> None:
    assert figures()["private_reaches"] == {}


def test_a_scene_is_composed_from_the_kit_never_from_guards() -> None:
    """A scene uses ``app.draw`` and ``app.controls`` (``draw.move``, ``controls.markdown_text``), not the
    guards beneath them."""
    assert figures()["scenes_on_guards"] == []


def test_the_checker_sees_each_kind_of_private_reach() -> None:
    """The rule can fail: each way of reaching into viser's insides is found; our own privates are not."""
    source = """
from viser import _messages
import viser._gui_api
from viser.infra import _async_message_buffer
handle._impl.uuid
getattr(client, "_rbl_view", None)
setattr(folder, "_rbl_choices", {})
self._mine
getattr(self, "_stepper", None)
obj.__class__
"""
    assert [line.split(":")[0] for line in private_reaches(source)] == ["2", "3", "4", "5", "6", "7"]


def documented_packages(text: str) -> dict[str, set[str]]:
    """The packages of app/ that docs/architecture.md's "app/ in sub-packages" table names, each with the
    modules its row names (``name.py``)."""
    section = text.split("## app/ in sub-packages", 1)[1].split("\n## ", 1)[0]
    rows = re.findall(r"^\| `(\w+)/` \| (.*) \|$", section, re.M)
    return {name: set(re.findall(r"`(\w+)\.py`", row)) for name, row in rows}


def architecture_drift(text: str, app: Path) -> list[str]:
    """Where the document ``text`` and the packages under ``app`` disagree (empty when they match): a package
    named but missing or there but not named, a module named but missing or there but not named (a scene's
    own module excepted: its row says "one module per scene")."""
    from app.scenes import scene_names

    named = documented_packages(text)
    there = {p.name: p for p in app.iterdir() if (p / "__init__.py").exists()}
    drift = [f"package {n}/ named, not there" for n in sorted(set(named) - set(there))]
    drift += [f"package {n}/ there, not named" for n in sorted(set(there) - set(named))]
    for name in sorted(set(named) & set(there)):
        modules = {p.stem for p in there[name].glob("*.py")} - {"__init__"}
        unnamed = modules - named[name] - (set(scene_names()) if name == "scenes" else set())
        drift += [f"{name}/{m}.py named, not there" for m in sorted(named[name] - modules)]
        drift += [f"{name}/{m}.py there, not named" for m in sorted(unnamed)]
    return drift


def test_the_architecture_document_names_every_package_and_module_and_only_those() -> None:
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    assert architecture_drift(text, ROOT / "app") == []


def test_the_document_check_sees_drift(tmp_path: Path) -> None:
    """The check can fail: a missing package, an unnamed one, a missing module and an unnamed one."""
    for package, modules in {"serving": ("app", "clock"), "extra": ("thing",)}.items():
        (tmp_path / package).mkdir()
        for m in ("__init__", *modules):
            (tmp_path / package / f"{m}.py").write_text("")
    text = "## app/ in sub-packages\n\n| `serving/` | `app.py`, `gone.py` |\n| `ghost/` | `x.py` |\n"
    assert architecture_drift(text, tmp_path) == [
        "package ghost/ named, not there",
        "package extra/ there, not named",
        "serving/gone.py named, not there",
        "serving/clock.py there, not named",
    ]


def test_the_checker_sees_a_loop_and_a_private_import(tmp_path: Path) -> None:
    """The rules can fail: two modules that import each other and a private name are found."""
    (tmp_path / "a.py").write_text("from physics.b import _x\n")
    (tmp_path / "b.py").write_text("def f():\n    import physics.a\n")
    modules = {n: Module(n, tmp_path / f"{n[-1]}.py", 2) for n in ("physics.a", "physics.b")}
    for m in modules.values():
        _collect(m, ast.parse(m.path.read_text()), modules, False, inside_function=False)
    assert cycles(import_graph(modules)) == [["physics.a", "physics.b"]]
    assert modules["physics.a"].private == ["physics.b._x"]
    assert modules["physics.b"].lazy == ["physics.a"]


CONTRACT_NAMES = frozenset(
    {"ctx", "context", "app", "client", "client_id", "clients", "server", "simulation", "sim", "scene", "session"}
)
"""Names that stand for one of app/'s contracts: their annotations must say which (app.contracts, viser)."""


def _is_any(annotation: ast.expr) -> bool:
    """``Any``, ``typing.Any``, ``Any | None`` or ``Optional[Any]``: an annotation that declares nothing."""
    parts = ast.unparse(annotation).removeprefix("Optional[").removesuffix("]").split("|")
    return any(part.strip() in ("Any", "typing.Any") for part in parts)


def untyped_contracts(source: str) -> list[str]:
    """``line: name`` for every parameter or annotated variable named for a contract (:data:`CONTRACT_NAMES`,
    also as ``self.name``) whose annotation is ``Any``."""
    found: list[tuple[int, int, str]] = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.arg) and node.annotation is not None:
            name, annotation = node.arg, node.annotation
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, (ast.Name, ast.Attribute)):
            name = node.target.id if isinstance(node.target, ast.Name) else node.target.attr
            annotation = node.annotation
        else:
            continue
        if name in CONTRACT_NAMES and _is_any(annotation):
            found.append((node.lineno, node.col_offset, name))
    return [f"{line}: {name}" for line, _, name in sorted(found)]


def forwarding_classes(source: str) -> list[str]:
    """The classes that define ``__getattr__`` (every unknown attribute handed on to something else)."""
    return [
        node.name
        for node in ast.walk(ast.parse(source))
        if isinstance(node, ast.ClassDef)
        and any(isinstance(f, ast.FunctionDef) and f.name == "__getattr__" for f in node.body)
    ]


def _app_sources(*, outside_guards: bool = False) -> dict[str, str]:
    return {
        str(path.relative_to(ROOT)): path.read_text(encoding="utf-8")
        for path in sorted((ROOT / "app").rglob("*.py"))
        if not (outside_guards and path.parent.name == "guards")
    }


def test_no_contract_is_typed_any_in_app() -> None:
    found = {path: hits for path, source in _app_sources().items() if (hits := untyped_contracts(source))}
    assert found == {}


def test_no_class_outside_guards_forwards_unknown_attributes() -> None:
    """The App declares what it answers for its shared simulation; viser's stand-ins in guards/ may forward."""
    found = {
        path: names
        for path, source in _app_sources(outside_guards=True).items()
        if (names := forwarding_classes(source))
    }
    assert found == {}


def test_the_contract_checks_can_fail() -> None:
    source = """
def f(ctx: Any, client: Any = None, scene: Any | None = None, value: Any = 0, server: viser.ViserServer = s): ...
class App:
    session: Optional[Any] = None
    def __init__(self, app: Any) -> None:
        self.simulation: Any = None
        self.other: Any = None
    def __getattr__(self, name: str) -> Any: ...
"""
    assert untyped_contracts(source) == ["2: ctx", "2: client", "2: scene", "4: session", "5: app", "6: simulation"]
    assert forwarding_classes(source) == ["App"]


def strict_flags(pyproject: str, module: str) -> dict[str, object]:
    """The mypy flags pyproject's ``[[tool.mypy.overrides]]`` set for ``module`` (a later override wins)."""
    import tomllib

    flags: dict[str, object] = {}
    for override in tomllib.loads(pyproject).get("tool", {}).get("mypy", {}).get("overrides", []):
        patterns = override["module"] if isinstance(override["module"], list) else [override["module"]]
        if module in patterns:
            flags.update({k: v for k, v in override.items() if k != "module"})
    return flags


def test_mypy_checks_app_as_strictly_as_physics() -> None:
    pyproject = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    physics, app = strict_flags(pyproject, "physics.*"), strict_flags(pyproject, "app.*")
    assert physics.get("disallow_untyped_defs") is True and physics.get("warn_return_any") is True
    assert app == physics


def test_the_strictness_check_can_fail() -> None:
    pyproject = """
[[tool.mypy.overrides]]
module = ["physics.*", "app.*"]
disallow_untyped_defs = true
[[tool.mypy.overrides]]
module = "app.*"
disallow_untyped_defs = false
"""
    assert strict_flags(pyproject, "physics.*") == {"disallow_untyped_defs": True}
    assert strict_flags(pyproject, "app.*") == {"disallow_untyped_defs": False}


ISSUE_NUMBER = re.compile(r"\b[Ii]ssues? ?#?\d+")
"""A comment or docstring citing an issue by number: the code says why in words, the tracker keeps the history."""


def issue_citations(source: str) -> list[int]:
    """The lines of ``source`` that cite an issue by number."""
    return [n for n, line in enumerate(source.splitlines(), 1) if ISSUE_NUMBER.search(line)]


def test_no_comment_cites_an_issue_number() -> None:
    folders = ("app", "physics", "tests", "benchmarks", "examples", "lectures")
    sources = [p for d in folders for p in (ROOT / d).rglob("*.py") if "node_modules" not in p.parts]
    found = {
        str(p.relative_to(ROOT)): lines
        for p in sources
        if p != Path(__file__) and (lines := issue_citations(p.read_text(encoding="utf-8")))
    }
    assert found == {}


def test_the_issue_check_can_fail() -> None:
    source = 'x = 1\n# as issue 15 asked\n"""(Issue #3, item 2)"""\n# an issue with 2 parts\n'
    assert issue_citations(source) == [2, 3]


def unmirrored(tests: Path, source: Path) -> list[str]:
    """The sub-folders of ``tests`` (tests/app) that name no package of ``source`` (app/)."""
    packages = {p.name for p in source.iterdir() if (p / "__init__.py").exists()}
    return sorted(p.name for p in tests.iterdir() if p.is_dir() and p.name != "__pycache__" and p.name not in packages)


def test_tests_of_app_mirror_its_packages() -> None:
    """tests/app/<package>/ holds the tests of app/<package>/; a test of the whole app stays at tests/app/."""
    assert unmirrored(ROOT / "tests" / "app", ROOT / "app") == []


def test_the_mirror_check_can_fail(tmp_path: Path) -> None:
    for folder in ("source/serving", "tests/serving", "tests/servng"):
        (tmp_path / folder).mkdir(parents=True)
    (tmp_path / "source" / "serving" / "__init__.py").write_text("")
    assert unmirrored(tmp_path / "tests", tmp_path / "source") == ["servng"]


def shared_module_names(source: Path) -> dict[str, list[str]]:
    """Module names (``__init__`` and ``__main__`` aside) found more than once under ``source``, with where."""
    where: dict[str, list[str]] = {}
    for path in sorted(source.rglob("*.py")):
        if path.stem not in ("__init__", "__main__"):
            where.setdefault(path.stem, []).append(path.relative_to(source).as_posix())
    return {name: paths for name, paths in where.items() if len(paths) > 1}


def test_no_two_modules_of_app_share_a_name() -> None:
    assert shared_module_names(ROOT / "app") == {}


def test_the_shared_name_check_can_fail(tmp_path: Path) -> None:
    for path in ("controls.py", "panel/controls.py", "panel/__init__.py", "serving/__init__.py", "__main__.py"):
        (tmp_path / path).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / path).write_text("")
    assert shared_module_names(tmp_path) == {"controls": ["controls.py", "panel/controls.py"]}


if __name__ == "__main__":
    f = figures()
    print(f"loops: {len(f['loops'])} ({sum(len(c) for c in f['loops'])} modules)")  # type: ignore[arg-type]
    for c in f["loops"]:  # type: ignore[attr-defined]
        print("   ", " ".join(c))
    print(f"imports running back up into their own package: {len(f['back_up'])}")  # type: ignore[arg-type]
    print(f"private imports: {len(f['private'])}")  # type: ignore[arg-type]
    print(f"lazy project imports: {len(f['lazy'])}")  # type: ignore[arg-type]
    print(f"modules over {MAX_LINES} lines: {f['over_limit']}")
    print(f"largest: {f['largest']}")
    print(f"physics importing above it: {f['physics_up']}")
    print(f"files directly in app/: {len(f['app_top_level_files'])}")  # type: ignore[arg-type]
    reaches = f["private_reaches"]
    print(f"private reaches outside app/guards/: {sum(len(v) for v in reaches.values())}")  # type: ignore[attr-defined]
    if "-v" in sys.argv:
        for key in ("back_up", "private", "lazy"):
            print(f"--- {key}")
            for line in f[key]:  # type: ignore[attr-defined]
                print("   ", line)
