"""Euler angles z-x-z of a symmetric top and the attitude they give (docs/conventions.md).

``R = Rz(φ) Rx(θ) Rz(ψ)`` (body to space): θ is the angle of the symmetry axis from +z, φ the precession
(azimuth) and ψ the spin. The symmetry axis in space is ``R[:, 2] = (sin θ sin φ, −sin θ cos φ, cos θ)``
and ``Ṙ = R hat(ω_body)`` with ``ω_body = (φ̇ sin θ sin ψ + θ̇ cos ψ, φ̇ sin θ cos ψ − θ̇ sin ψ, φ̇ cos θ + ψ̇)``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.validation import finite_array

Floats = NDArray[np.float64]

__all__ = ["euler_attitude", "symmetry_axis", "omega_body_from_euler"]


def euler_attitude(phi: ArrayLike, theta: ArrayLike, psi: ArrayLike) -> NDArray[np.float64]:
    """Attitude ``R = Rz(φ) Rx(θ) Rz(ψ)`` (z-x-z Euler angles, body to space).

    Parameters
    ----------
    phi, theta, psi : array_like, shape (n,) or scalars
        Precession, nutation (from +z) and spin angles, rad.

    Returns
    -------
    ndarray, shape (n, 3, 3) (or (3, 3) for scalars)
    """
    phi, theta, psi = _angles(("phi", phi), ("theta", theta), ("psi", psi))
    cf, sf = np.cos(phi), np.sin(phi)
    ct, st = np.cos(theta), np.sin(theta)
    cp, sp = np.cos(psi), np.sin(psi)
    return attitude_from_trig(cf, sf, ct, st, cp, sp)


def attitude_from_trig(cf: Floats, sf: Floats, ct: Floats, st: Floats, cp: Floats, sp: Floats) -> Floats:
    r = np.empty(np.shape(cf) + (3, 3))
    r[..., 0, 0] = cf * cp - sf * ct * sp
    r[..., 0, 1] = -cf * sp - sf * ct * cp
    r[..., 0, 2] = sf * st
    r[..., 1, 0] = sf * cp + cf * ct * sp
    r[..., 1, 1] = -sf * sp + cf * ct * cp
    r[..., 1, 2] = -cf * st
    r[..., 2, 0] = st * sp
    r[..., 2, 1] = st * cp
    r[..., 2, 2] = ct
    return r


def symmetry_axis(phi: ArrayLike, theta: ArrayLike) -> NDArray[np.float64]:
    """Unit symmetry axis in space ``(sin θ sin φ, −sin θ cos φ, cos θ)``, shape (n, 3)."""
    phi, theta = _angles(("phi", phi), ("theta", theta))
    st = np.sin(theta)
    return np.stack([st * np.sin(phi), -st * np.cos(phi), np.cos(theta)], axis=-1)


def omega_body_from_euler(
    theta: ArrayLike, psi: ArrayLike, thetadot: ArrayLike, phidot: ArrayLike, psidot: ArrayLike
) -> NDArray[np.float64]:
    """Body-frame angular velocity of ``R = Rz(φ) Rx(θ) Rz(ψ)``, rad/s, shape (n, 3).

    ``ω_body = (φ̇ sin θ sin ψ + θ̇ cos ψ, φ̇ sin θ cos ψ − θ̇ sin ψ, φ̇ cos θ + ψ̇)``, so that
    ``Ṙ = R hat(ω_body)``.
    """
    theta, psi, td, fd, pd = _angles(
        ("theta", theta), ("psi", psi), ("thetadot", thetadot), ("phidot", phidot), ("psidot", psidot)
    )
    st, ct, sp, cp = np.sin(theta), np.cos(theta), np.sin(psi), np.cos(psi)
    return np.stack([fd * st * sp + td * cp, fd * st * cp - td * sp, fd * ct + pd], axis=-1)


def _angles(*named: tuple[str, ArrayLike]) -> list[Floats]:
    """Finite float arrays broadcast together; ValueError names the argument that is not."""
    arrays = [finite_array(value, name) for name, value in named]
    try:
        return list(np.broadcast_arrays(*arrays))
    except ValueError:
        shapes = ", ".join(f"{name} {a.shape}" for (name, _), a in zip(named, arrays))
        raise ValueError(f"the angles must broadcast together, got shapes {shapes}") from None


def theta_from(one_mu: ArrayLike, one_pu: ArrayLike) -> Any:
    """θ from 1 − cos θ = 2 sin²(θ/2) and 1 + cos θ = 2 cos²(θ/2): accurate at both poles."""
    return 2.0 * np.arctan2(np.sqrt(np.maximum(one_mu, 0.0)), np.sqrt(np.maximum(one_pu, 0.0)))
