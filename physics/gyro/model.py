"""The model a gyroscope recording is fitted with: the rigid body's Euler equations with air drag, seen in the
phone's axes.

**Drag.** Air drag on a tumbling phone is form drag (tip speed about 2 m/s over 0.15 m: Reynolds number
about 2e4, where a bluff plate's drag grows as the square of the speed; Hoerner, *Fluid-Dynamic Drag*, 1965,
ch. 3), and it is strongly anisotropic: turning about an axis in the screen's plane, the phone sweeps the
air face on; about the screen's normal, edge on. We fit one linear coefficient per principal axis,
``τ_i = −c_i ω_i``: over one toss |ω| changes by less than a third, so a linear law with fitted coefficients
stands in for the quadratic one to within the noise, and it is the drag the project's integrators step
exactly (three :class:`~physics.integrators.SpinFriction` flows), which the fitted result's ``predict`` uses.
Why not a drag along ``L`` (``τ = −γ L``, which has an exact solution by a change of time)? It keeps the
motion's place relative to the separatrix, and that place sets the flip's period: fitted to real tosses
with two flips it left residuals of 30% of |ω|; the anisotropic drag moves the motion towards the
separatrix's other side as the real one does.

**Speed.** Without drag :func:`free_omega` is the textbook closed form (Landau and Lifshitz, *Mechanics*,
§37) on scipy's Jacobi functions, about 50 µs for 100 samples and ~1e-13 of |ω| from
:class:`physics.free_body.FreeBody` (which stays at the round-off floor everywhere); with drag
:func:`physics.gyro.kernel.drag_omega` steps Euler's equations compiled.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray
from scipy.special import ellipj, ellipkinc

from physics.gyro.kernel import drag_omega

Floats = NDArray[np.float64]
DragLaw = Literal["linear", "none"]

__all__ = ["DragLaw", "free_omega", "model_omega", "rotation_from_vector", "euler_ratios"]


def rotation_from_vector(theta: Floats) -> Floats:
    """The rotation ``exp(hat θ)`` (Rodrigues), shape (3, 3), for a rotation vector θ (3,) in rad."""
    angle = float(np.linalg.norm(theta))
    k = np.array([[0.0, -theta[2], theta[1]], [theta[2], 0.0, -theta[0]], [-theta[1], theta[0], 0.0]])
    if angle < 1e-8:
        return np.asarray(np.eye(3) + k + 0.5 * k @ k, dtype=float)
    return np.asarray(np.eye(3) + np.sin(angle) / angle * k + (1.0 - np.cos(angle)) / angle**2 * k @ k, dtype=float)


def _sorting(moments: Floats) -> tuple[Floats, Floats]:
    """The moments ascending (A < B < C, nudged apart by 1e-9 where equal) and the proper rotation whose rows
    are the body axes in that order (a reflection would reverse the sense of Euler's equations)."""
    order = np.argsort(moments, kind="stable")
    perm = np.eye(3)[order]
    if np.linalg.det(perm) < 0.0:
        perm[0] = -perm[0]
    abc = np.array(moments, dtype=float)[order]
    # A symmetric body is the limit of the general closed form; 1e-9 apart it is that limit to 1e-9.
    scale = float(abc[2])
    for i in (1, 2):
        if abc[i] - abc[i - 1] < 1e-9 * scale:
            abc[i] = abc[i - 1] + 1e-9 * scale
    return abc, perm


def free_omega(moments: Floats, omega0: Floats, t: Floats) -> Floats:
    """Torque-free ``ω(t)`` in body axes from ``ω(0) = omega0`` (Euler's equations, Landau and Lifshitz §37).

    Parameters
    ----------
    moments : ndarray (3,)
        Principal moments (any positive scale and order), kg m².
    omega0 : ndarray (3,)
        ω at t = 0 in the same axes, rad/s.
    t : ndarray (n,)
        Times, s.

    Returns
    -------
    ndarray (n, 3)
        ω(t), rad/s.
    """
    (a_, b_, c_), perm = _sorting(moments)
    v = perm @ omega0
    l2 = float((a_ * v[0]) ** 2 + (b_ * v[1]) ** 2 + (c_ * v[2]) ** 2)
    e2 = float(a_ * v[0] ** 2 + b_ * v[1] ** 2 + c_ * v[2] ** 2)
    if e2 <= 0.0:
        return np.zeros((t.shape[0], 3))
    up = max(e2 * c_ - l2, 0.0)  # 2E C − L² ≥ 0
    lo = max(l2 - e2 * a_, 0.0)  # L² − 2E A ≥ 0
    out = np.empty((t.shape[0], 3))
    if l2 >= e2 * b_:
        # Circulating about the largest axis C: ω = (a1 cn, σ a2 sn, σ a3 dn), σ the sign of ω_C.
        a1, a2, a3 = np.sqrt(up / (a_ * (c_ - a_))), np.sqrt(up / (b_ * (c_ - b_))), np.sqrt(lo / (c_ * (c_ - a_)))
        lam = np.sqrt((c_ - b_) * lo / (a_ * b_ * c_))
        m = (b_ - a_) * up / ((c_ - b_) * lo) if lo > 0.0 else 0.0
        sigma = 1.0 if v[2] >= 0.0 else -1.0
        phi0 = np.arctan2(sigma * v[1] / a2 if a2 > 0.0 else 0.0, v[0] / a1 if a1 > 0.0 else 1.0)
        sn, cn, dn, _ = ellipj(lam * t + ellipkinc(phi0, min(m, 1.0)), min(m, 1.0))
        out[:, 0], out[:, 1], out[:, 2] = a1 * cn, sigma * a2 * sn, sigma * a3 * dn
    else:
        # About the smallest axis A (Landau: 1 and 3 exchanged): ω = (σ a1 dn, σ a2 sn, a3 cn), σ the sign of ω_A.
        a1, a2, a3 = np.sqrt(up / (a_ * (c_ - a_))), np.sqrt(lo / (b_ * (b_ - a_))), np.sqrt(lo / (c_ * (c_ - a_)))
        lam = np.sqrt((b_ - a_) * up / (a_ * b_ * c_))
        m = (c_ - b_) * lo / ((b_ - a_) * up)
        sigma = 1.0 if v[0] >= 0.0 else -1.0
        phi0 = np.arctan2(sigma * v[1] / a2 if a2 > 0.0 else 0.0, v[2] / a3 if a3 > 0.0 else 1.0)
        sn, cn, dn, _ = ellipj(lam * t + ellipkinc(phi0, min(m, 1.0)), min(m, 1.0))
        out[:, 0], out[:, 1], out[:, 2] = sigma * a1 * dn, sigma * a2 * sn, a3 * cn
    return out @ perm


def model_omega(moments: Floats, rotation: Floats, drag: Floats | None, omega0_body: Floats, t: Floats) -> Floats:
    """ω in the phone's axes, (n, 3) rad/s: the principal axes are the columns of ``rotation`` (phone axes),
    ``drag`` the coefficients ``c_i`` (moments per s; None: no drag), ``omega0_body`` ω at t = 0 in principal
    axes and ``t`` (n,) the times from then, s (either sign)."""
    if drag is None or not np.any(drag > 0.0):
        body = free_omega(moments, omega0_body, t)
    else:
        body = np.empty((t.shape[0], 3))
        ahead = t >= 0.0
        body[ahead] = drag_omega(moments, drag, omega0_body, t[ahead])
        if not np.all(ahead):
            behind = np.nonzero(~ahead)[0][::-1]
            body[behind] = drag_omega(moments, drag, omega0_body, t[behind])
    return np.asarray(body @ rotation.T, dtype=float)


def euler_ratios(pieces: list[tuple[Floats, Floats]]) -> Floats:
    """Moments (3,) with the largest 1 from Euler's equations read as a linear system in ``I``.

    ``I_x ω̇_x − (I_y − I_z) ω_y ω_z = 0`` and its cyclic versions are linear and homogeneous in the moments;
    with ω̇ from central differences over each piece ``(times (n,), omega (n, 3))`` the least-squares
    solution is the right singular vector of the smallest singular value. A starting guess for the fit
    (noise and drag bias it a little), not a result.
    """
    blocks = []
    for times, omega in pieces:
        if times.shape[0] < 3:
            continue
        w = 0.5 * (omega[2:] + omega[:-2])
        dw = (omega[2:] - omega[:-2]) / (times[2:] - times[:-2])[:, None]
        x, y, z = w[:, 0], w[:, 1], w[:, 2]
        blocks += [
            np.stack([dw[:, 0], -y * z, y * z], axis=1),
            np.stack([z * x, dw[:, 1], -z * x], axis=1),
            np.stack([-x * y, x * y, dw[:, 2]], axis=1),
        ]
    rows = np.concatenate(blocks) if blocks else np.zeros((0, 3))
    rows = rows[np.all(np.isfinite(rows), axis=1)]
    if rows.shape[0] < 3:
        return np.ones(3)
    try:
        vec = np.linalg.svd(rows, full_matrices=False)[2][-1]
    except np.linalg.LinAlgError:
        return np.ones(3)
    vec = vec if vec[np.argmax(np.abs(vec))] > 0.0 else -vec
    vec = np.clip(vec, 1e-3 * np.max(vec), None)
    return np.asarray(vec / np.max(vec), dtype=float)
