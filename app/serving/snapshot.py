"""A simulation's state, to copy into another simulation or to write as a state text and open again.

A snapshot holds the scene, what it was handed, the values of its controls (in order, each by its stable
name: a parameter slider's key, any other control's label; :meth:`app.scenes.base.Scene.control_key`), its own
motion state (:meth:`app.scenes.base.Scene.snapshot`), the time, the speed and whether the clock runs.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import viser

from app.guards.handles import is_removed, properties
from app.guards.inputs import check_update
from app.teaching.states import parse_state
from app.teaching.states import state_text as write_state

if TYPE_CHECKING:
    from app.serving.simulation import Simulation

__all__ = ["snapshot", "restore", "state_text", "open_state", "named_controls"]


def snapshot(sim: Simulation) -> dict[str, Any]:
    """Everything needed to start another simulation where ``sim`` is now (ValueError without a scene)."""
    with sim.lock:
        if sim.scene is None:
            raise ValueError("there is no scene to copy (it failed to build)")
        return {
            "scene": sim.scene.name,
            "payload": sim.payload,
            "controls": [(sim.scene.control_key(h), h.value) for h in sim.scene_inputs if not is_removed(h)],
            "motion": sim.scene.snapshot(),
            "time": sim.time,
            "speed": sim.speed,
            "playing": sim.playing,
        }


def named_controls(sim: Simulation) -> dict[str, Any]:
    """The scene's controls by the names a state text may give them: each one's stable name
    (:meth:`app.scenes.base.Scene.control_key`) and, for the states written before sliders had keys, a
    slider's label too."""
    scene = sim.scene
    if scene is None:
        return {}
    handles = [h for h in sim.scene_inputs if not is_removed(h)]
    names = {scene.control_key(h): h for h in handles}
    for h in handles:
        names.setdefault(str(h.label), h)
    return names


def restore(sim: Simulation, state: dict[str, Any]) -> None:
    """Put ``sim`` at a state :func:`snapshot` gave (a control the scene does not have is passed over)."""
    with sim.lock:
        if sim.scene is None or sim.scene.name != state["scene"] or state.get("payload") is not None:
            sim.switch_scene(state["scene"], payload=state.get("payload"))
        assert sim.scene is not None
        sim.scene.prepare(state["motion"])
        # Twice: a control that re-applies others (a preset) must not override what followed it.
        for _ in range(2):
            controls = named_controls(sim)
            for name, value in state["controls"]:
                handle = controls.get(name)
                if handle is not None and handle.value != value:
                    handle.value = value  # runs the control's callback: the scene adopts it
        assert sim.scene is not None
        sim.scene.restore(state["motion"])
        sim.set_speed(state["speed"])
        sim.set_time(float(state["time"]))
        sim.set_playing(state["playing"])


def state_text(sim: Simulation, client: viser.ClientHandle | None = None) -> str:
    """``sim``'s state as a short text (:mod:`app.teaching.states`), with ``client``'s camera if given."""
    camera = None
    if client is not None:
        camera = {"position": list(client.camera.position), "look_at": list(client.camera.look_at)}
    return write_state(snapshot(sim), camera)


def open_state(sim: Simulation, text: str) -> None:
    """Put ``sim`` at the state a text describes: all of it or, if any part is refused, none of it.

    Raises
    ------
    ValueError
        What is wrong with the text, or which control refused its value (the previous state stays).
    """
    state = parse_state(text)
    with sim.lock:
        before = snapshot(sim) if sim.scene is not None else None
        try:
            if sim.scene is None or sim.scene.name != state["scene"]:
                sim.switch_scene(state["scene"])
            controls = named_controls(sim)
            given: dict[int, Any] = {}  # by the control's id: a state may name it by key or by label
            for name, value in state["controls"]:
                handle = controls.get(name)
                if handle is None:
                    raise ValueError(f"this state sets “{name}”, which the scene does not have")
                given[id(handle)] = check_update(handle.value, properties(handle), name, {"value": value})["value"]
            scene = sim.scene
            assert scene is not None
            restore(
                sim,
                {
                    **state,
                    "controls": [
                        (scene.control_key(h), given.get(id(h), h.value)) for h in sim.scene_inputs if not is_removed(h)
                    ],
                },
            )
        except Exception:
            if before is not None:
                restore(sim, before)
            raise
        camera = state.get("camera")
    if camera is not None:
        sim.set_camera(camera["position"], camera["look_at"])
