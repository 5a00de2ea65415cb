"""physics/ imports one way (docs/architecture.md): validation, double-double and constants →
elliptic, rotations, Euler angles → inertia → the free body → integrators → the heavy top and the pendulum
→ the events of their motions and the history of stepped ones; a module imports only modules of its own layer's package or of the layers before it."""

from __future__ import annotations

from tests.test_architecture import import_graph, read_modules

LAYERS: tuple[tuple[str, ...], ...] = (
    ("physics.validation", "physics.double_double", "physics.constants"),
    ("physics.elliptic", "physics.rotations", "physics.euler_angles"),
    ("physics.inertia",),
    ("physics.free_body", "physics.free_body_motion", "physics.free_body_trajectory"),
    ("physics.integrators",),
    ("physics.heavy_top", "physics.heavy_body", "physics.pendulum", "physics.gyro"),
    ("physics.events", "physics.history"),
)


def layer_of(module: str) -> int | None:
    for index, layer in enumerate(LAYERS):
        if any(module == name or module.startswith(name + ".") for name in layer):
            return index
    return None


def upward_imports(graph: dict[str, set[str]]) -> list[str]:
    """Imports that run from a layer to a later one."""
    found = []
    for importer, imported in sorted((a, b) for a, targets in graph.items() for b in targets):
        low, high = layer_of(importer), layer_of(imported)
        if low is not None and high is not None and high > low:
            found.append(f"{importer} -> {imported}")
    return found


def test_physics_imports_down_its_layers() -> None:
    assert upward_imports(import_graph(read_modules(("physics",)))) == []


def test_every_physics_module_has_a_layer() -> None:
    modules = read_modules(("physics",))
    assert sorted(m for m in modules if m != "physics" and layer_of(m) is None) == []


def test_the_check_sees_an_upward_import() -> None:
    """The rule can fail: inertia importing the free body runs up, the free body importing inertia does not."""
    graph = {"physics.inertia": {"physics.free_body"}, "physics.free_body": {"physics.inertia"}}
    assert upward_imports(graph) == ["physics.inertia -> physics.free_body"]
