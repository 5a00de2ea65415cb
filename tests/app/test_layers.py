"""app/'s packages import one way (docs/architecture.md): rooms, serving, teaching, scenes, recording, drawing,
panel, guards, uploads, language; a package imports only the packages after it in that list."""

from __future__ import annotations

from tests.test_architecture import import_graph, read_modules

ORDER = ("rooms", "serving", "teaching", "scenes", "recording", "drawing", "panel", "guards", "uploads", "language")


def package_of(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if len(parts) > 2 or (len(parts) == 2 and parts[1] in ORDER) else None


def upward_imports(graph: dict[str, set[str]]) -> list[str]:
    found = []
    for importer, imported in sorted((a, b) for a, targets in graph.items() for b in targets):
        low, high = package_of(importer), package_of(imported)
        if low in ORDER and high in ORDER and ORDER.index(high) < ORDER.index(low):
            found.append(f"{importer} -> {imported}")
    return found


def test_every_package_imports_only_the_packages_below_it() -> None:
    assert upward_imports(import_graph(read_modules(("app",)))) == []


def test_every_module_of_app_is_in_a_package_or_one_of_the_doors_at_its_top() -> None:
    """The doors, and the contracts module at the bottom of the imports (app.contracts)."""
    modules = read_modules(("app",))
    outside = sorted(m for m in modules if package_of(m) is None)
    assert outside == ["app", "app.__main__", "app.contracts", "app.controls", "app.draw", "app.server"]


def test_the_check_sees_an_upward_import() -> None:
    """The rule can fail: uploads importing serving is upward, serving importing uploads is not."""
    graph = {"app.uploads.reading": {"app.serving.app"}, "app.serving.app": {"app.uploads.reading"}}
    assert upward_imports(graph) == ["app.uploads.reading -> app.serving.app"]
