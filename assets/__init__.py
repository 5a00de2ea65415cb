"""The body meshes the scenes use, made by ``python -m assets.build`` and committed beside it.

Each asset is a watertight binary PLY in metres, in the modelling frame its builder documents
(long bodies along +z from their handle end or tip). Uniform density is assumed; the catalogue
gives a realistic total mass so inertia readouts come out in familiar magnitudes.

Examples
--------
>>> from assets import ASSETS, load_mesh, mass_properties
>>> props = mass_properties("tennis_racket")   # physics.inertia.MassProperties, kg and m
>>> props.moments                                # I1 >= I2 >= I3, kg m²
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from pathlib import Path

import trimesh

from physics.inertia import MassProperties, from_mesh

ASSET_DIR = Path(__file__).resolve().parent

__all__ = ["Asset", "ASSETS", "asset_path", "load_mesh", "mass_properties"]


@dataclass(frozen=True)
class Asset:
    """One catalogued body: its label in the GUI, its nominal mass (kg) and what it is for."""

    label: str
    mass: float
    description: str


ASSETS: dict[str, Asset] = {
    "tennis_racket": Asset("Tennis racket", 0.31, "open oval head, solid throat; the intermediate-axis flip"),
    "t_handle": Asset("T-handle (Dzhanibekov nut)", 0.146, "steel T of square bars; flips in orbit"),
    "spinning_top": Asset("Spinning top", 0.095, "wooden top on its tip, axis +z"),
    "baseball_bat": Asset("Baseball bat", 0.90, "0.84 m bat, knob at the origin; the sweet spot"),
    "book": Asset("Book", 1.0, "hardback 240 x 170 x 35 mm; tumbles about its middle axis"),
}
"""Asset name -> catalogue entry; the mesh is ``assets/<name>.ply``."""


def asset_path(name: str) -> Path:
    """Path of an asset's mesh file.

    Raises
    ------
    ValueError
        If ``name`` is not in :data:`ASSETS`.
    """
    if name not in ASSETS:
        raise ValueError(f"unknown asset {name!r}; the assets are {', '.join(ASSETS)}")
    return ASSET_DIR / f"{name}.ply"


@cache
def _load(name: str) -> trimesh.Trimesh:
    mesh = trimesh.load_mesh(asset_path(name), process=True)
    mesh.merge_vertices()
    return mesh


def load_mesh(name: str) -> trimesh.Trimesh:
    """A fresh copy of an asset's mesh (vertices in m, modelling frame)."""
    return _load(name).copy()


@cache
def mass_properties(name: str) -> MassProperties:
    """Mass, centre of mass and inertia tensor of an asset at its catalogue mass (uniform density)."""
    return from_mesh(_load(name), mass=ASSETS[name].mass)
