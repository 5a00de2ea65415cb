"""The component state of one body or a batch, and the exact sub-flows every method is built from.

A state is a tuple of 12 scalars (or (n,) arrays): ``R`` row-major r00..r22, then ``L0, L1, L2``. The rotations
``rot_x/rot_y/rot_z`` are the exact flows of ``L_i²/(2 I_i)`` (lecture, Euler's equations); ``right_exp`` is
``R ← R exp(hat u)``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.validation import finite_array, finite_result, rotation_array, vector_array

# A state is a tuple of 12 scalars (or (n,) arrays): R row-major r00..r22, then L0, L1, L2.
State = tuple


def vec3(value: ArrayLike, name: str) -> NDArray[np.float64]:
    v = np.asarray(value, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be 3 finite numbers, got {np.asarray(value).tolist()}")
    return v


def check_moments(moments: ArrayLike) -> NDArray[np.float64]:
    m = finite_array(moments, "moments")
    if m.shape != (3,):
        raise ValueError(f"moments must be 3 finite principal moments in kg m², got shape {m.shape}")
    if np.any(m < 0.0) or np.all(m == 0.0):
        raise ValueError(f"no rigid body has these moments: {m.tolist()} (negative, or all zero)")
    with np.errstate(divide="ignore", over="ignore"):
        if np.any((m > 0.0) & ~np.isfinite(1.0 / m)):
            raise ValueError(
                f"moments {m.tolist()} kg m²: each must be 0 or at least {1.0 / np.finfo(float).max:.2g} (the steps "
                "divide by them); the motion is the same with the moments and L_body scaled up together"
            )
    tol = 1e-12 * float(np.max(m))
    for i in range(3):
        if m[i] > m[(i + 1) % 3] + m[(i + 2) % 3] + tol:
            raise ValueError(
                f"no rigid body has these moments: {m.tolist()} (each moment must be at most the sum of the other two)"
            )
    return m


def inverse_moments(m: NDArray[np.float64]) -> NDArray[np.float64]:
    """1/I, with 0 on a zero moment (a rod: no angular velocity component is carried there)."""
    return np.where(m > 0.0, 1.0 / np.where(m > 0.0, m, 1.0), 0.0)


def kinetic_energy(moments: ArrayLike, L_body: ArrayLike) -> NDArray[np.float64]:
    """``T = Σ L_i² / (2 I_i)``, J (zero moments contribute 0): ``L_body`` (n,3) or (3,) -> (n,) or ()."""
    inv = inverse_moments(finite_array(moments, "moments", (3,)))
    L = vector_array(L_body, "L_body")
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused by name just below
        energy: NDArray[np.float64] = 0.5 * np.sum(L * L * inv, axis=-1)
    finite_result(energy, "the kinetic energy", "values of L_body and the moments")
    return energy


def to_state(R, L) -> State:
    """Arrays to the component tuple; floats for one body, (n,) arrays for a batch."""
    if R.ndim == 2:
        r = R.ravel().tolist()
        return tuple(r) + tuple(L.tolist())
    return tuple(R[:, i, j].copy() for i in range(3) for j in range(3)) + tuple(L[:, i].copy() for i in range(3))


def from_state(s: State, batched: bool):
    if not batched:
        return np.array(s[:9], dtype=float).reshape(3, 3), np.array(s[9:], dtype=float)
    n = np.broadcast(*s).shape[0]
    R = np.empty((n, 3, 3))
    L = np.empty((n, 3))
    for k in range(9):
        R[:, k // 3, k % 3] = s[k]
    for k in range(3):
        L[:, k] = s[9 + k]
    return R, L


def rot_x(s: State, th, xp) -> State:
    """R ← R exp(θ ê_x), L ← exp(−θ ê_x) L (the exact flow of L_x²/(2 I_x) for θ = h L_x / I_x)."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22, l0, l1, l2 = s
    c, sn = xp.cos(th), xp.sin(th)
    return (
        r00,
        c * r01 + sn * r02,
        c * r02 - sn * r01,
        r10,
        c * r11 + sn * r12,
        c * r12 - sn * r11,
        r20,
        c * r21 + sn * r22,
        c * r22 - sn * r21,
        l0,
        c * l1 + sn * l2,
        c * l2 - sn * l1,
    )


def rot_y(s: State, th, xp) -> State:
    r00, r01, r02, r10, r11, r12, r20, r21, r22, l0, l1, l2 = s
    c, sn = xp.cos(th), xp.sin(th)
    return (
        c * r00 - sn * r02,
        r01,
        c * r02 + sn * r00,
        c * r10 - sn * r12,
        r11,
        c * r12 + sn * r10,
        c * r20 - sn * r22,
        r21,
        c * r22 + sn * r20,
        c * l0 - sn * l2,
        l1,
        c * l2 + sn * l0,
    )


def rot_z(s: State, th, xp) -> State:
    r00, r01, r02, r10, r11, r12, r20, r21, r22, l0, l1, l2 = s
    c, sn = xp.cos(th), xp.sin(th)
    return (
        c * r00 + sn * r01,
        c * r01 - sn * r00,
        r02,
        c * r10 + sn * r11,
        c * r11 - sn * r10,
        r12,
        c * r20 + sn * r21,
        c * r21 - sn * r20,
        r22,
        c * l0 + sn * l1,
        c * l1 - sn * l0,
        l2,
    )


ROT = (rot_x, rot_y, rot_z)


def expm_coeffs(u0, u1, u2, xp):
    """Rodrigues coefficients sin(a)/a and (1 − cos a)/a² (Taylor below a = 1e-4 rad)."""
    a2 = u0 * u0 + u1 * u1 + u2 * u2
    if xp is math:
        if a2 < 1e-8:
            return 1.0 - a2 / 6.0 + a2 * a2 / 120.0, 0.5 - a2 / 24.0 + a2 * a2 / 720.0
        a = math.sqrt(a2)
        return math.sin(a) / a, (1.0 - math.cos(a)) / a2
    small = a2 < 1e-8
    angle = np.sqrt(np.where(small, 1.0, a2))
    sa = np.where(small, 1.0 - a2 / 6.0 + a2 * a2 / 120.0, np.sin(angle) / angle)
    # 2 sin²(a/2) avoids the cancellation of 1 − cos a.
    ca = np.where(small, 0.5 - a2 / 24.0 + a2 * a2 / 720.0, 2.0 * np.sin(0.5 * angle) ** 2 / (angle * angle))
    return sa, ca


def right_exp(s: State, u0, u1, u2, xp) -> tuple:
    """The attitude part ``R exp(hat u)`` of a state (9 components), by Rodrigues' formula."""
    sa, ca = expm_coeffs(u0, u1, u2, xp)
    # E = I + sa K + ca K², K = hat(u)
    e00 = 1.0 - ca * (u1 * u1 + u2 * u2)
    e11 = 1.0 - ca * (u0 * u0 + u2 * u2)
    e22 = 1.0 - ca * (u0 * u0 + u1 * u1)
    p01, p02, p12 = ca * u0 * u1, ca * u0 * u2, ca * u1 * u2
    q0, q1, q2 = sa * u0, sa * u1, sa * u2
    e01, e10 = p01 - q2, p01 + q2
    e02, e20 = p02 + q1, p02 - q1
    e12, e21 = p12 - q0, p12 + q0
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = s[:9]
    return (
        r00 * e00 + r01 * e10 + r02 * e20,
        r00 * e01 + r01 * e11 + r02 * e21,
        r00 * e02 + r01 * e12 + r02 * e22,
        r10 * e00 + r11 * e10 + r12 * e20,
        r10 * e01 + r11 * e11 + r12 * e21,
        r10 * e02 + r11 * e12 + r12 * e22,
        r20 * e00 + r21 * e10 + r22 * e20,
        r20 * e01 + r21 * e11 + r22 * e21,
        r20 * e02 + r21 * e12 + r22 * e22,
    )


def check_shapes(R, L_body, names):
    """Finite ``R`` and ``L_body`` of one body ((3, 3), (3,)) or a batch ((n, 3, 3), (n, 3)), ``R`` not
    necessarily a rotation; ``names`` are the caller's argument names, used in the messages."""
    r_name, l_name = names
    R = finite_array(R, r_name)
    L = vector_array(L_body, l_name)
    if not (R.shape == (3, 3) or (R.ndim == 3 and R.shape[1:] == (3, 3))):
        raise ValueError(f"{r_name} must have shape (3, 3) or (n, 3, 3), got shape {R.shape}")
    if (R.ndim == 2) != (L.ndim == 1) or (R.ndim == 3 and R.shape[0] != L.shape[0]):
        raise ValueError(
            f"{r_name} must have shape (3, 3) or (n, 3, 3) and {l_name} (3,) or (n, 3) with the same n; "
            f"got {r_name} {R.shape}, {l_name} {L.shape}"
        )
    return R, L


def check_state(R, L_body, names=("R0", "L0_body")):
    """Attitudes (rotations) and momenta of one body ((3, 3), (3,)) or a batch ((n, 3, 3), (n, 3)); ``names``
    are the caller's argument names, used in the messages."""
    r_name, l_name = names
    R = rotation_array(R, r_name)
    R, L = check_shapes(R, L_body, names)
    return R, L, R.ndim == 3


def check_dt(dt) -> float:
    if isinstance(dt, bool) or not isinstance(dt, (int, float, np.integer, np.floating)):
        raise ValueError(f"the time step dt must be one number of seconds, got {dt!r}")
    try:
        dt = float(dt)
    except OverflowError:  # an int beyond the float range
        dt = math.inf
    if not math.isfinite(dt):
        raise ValueError(f"the time step dt must be a finite number of seconds, got {dt}")
    return dt
