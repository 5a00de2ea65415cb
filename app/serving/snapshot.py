"""A simulation's state, to copy into another simulation or to write as a state text and open again.

A snapshot holds the scene, what it was handed, the values of its controls (by label, in order), its own
motion state (:meth:`app.scenes.base.Scene.snapshot`), the time, the speed and whether the clock runs.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from app.guards.handles import is_removed, properties
from app.guards.inputs import check_update
from app.teaching.states import parse_state
from app.teaching.states import state_text as write_state

if TYPE_CHECKING:
    from app.serving.simulation import Simulation

__all__ = ["snapshot", "restore", "state_text", "open_state"]


def snapshot(sim: Simulation) -> dict[str, Any]:
    """Everything needed to start another simulation where ``sim`` is now (ValueError without a scene)."""
    with sim.lock:
        if sim.scene is None:
            raise ValueError("there is no scene to copy (it failed to build)")
        return {
            "scene": sim.scene.name,
            "payload": sim.payload,
            "controls": [(str(h.label), h.value) for h in sim.scene_inputs if not is_removed(h)],
            "motion": sim.scene.snapshot(),
            "time": sim.time,
            "speed": sim.speed,
            "playing": sim.playing,
        }


def restore(sim: Simulation, state: dict[str, Any]) -> None:
    """Put ``sim`` at a state :func:`snapshot` gave (a control whose label differs is left as it is)."""
    with sim.lock:
        if sim.scene is None or sim.scene.name != state["scene"] or state.get("payload") is not None:
            sim.switch_scene(state["scene"], payload=state.get("payload"))
        assert sim.scene is not None
        sim.scene.prepare(state["motion"])
        # Twice: a control that re-applies others (a preset) must not override what followed it.
        for _ in range(2):
            for handle, (label, value) in zip(list(sim.scene_inputs), state["controls"], strict=False):
                if str(handle.label) == label and handle.value != value:
                    handle.value = value  # runs the control's callback: the scene adopts it
        assert sim.scene is not None
        sim.scene.restore(state["motion"])
        sim.set_speed(state["speed"])
        sim.set_time(float(state["time"]))
        sim.set_playing(state["playing"])


def state_text(sim: Simulation, client: Any = None) -> str:
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
            inputs = {str(h.label): h for h in sim.scene_inputs if not is_removed(h)}
            checked = []
            for label, value in state["controls"]:
                handle = inputs.get(label)
                if handle is None:
                    raise ValueError(f"this state sets “{label}”, which the scene does not have")
                checked.append(
                    (label, check_update(handle.value, properties(handle), label, {"value": value})["value"])
                )
            given = dict(checked)
            restore(
                sim, {**state, "controls": [(str(h.label), given.get(str(h.label), h.value)) for h in sim.scene_inputs]}
            )
        except Exception:
            if before is not None:
                restore(sim, before)
            raise
        camera = state.get("camera")
    if camera is not None:
        sim.set_camera(camera["position"], camera["look_at"])
