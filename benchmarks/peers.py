"""The peers of the benchmark: scipy ``solve_ivp`` and MuJoCo, on the same rigid-body problems.

scipy: the state is (unit quaternion q in scipy order x, y, z, w; body angular velocity ω); Euler's
equations ``I ω̇ = (I ω) × ω + τ`` and ``q̇ = ½ q ⊗ (ω, 0)`` (body-frame ω multiplies on the right,
``Ṙ = R hat(ω)``). The quaternion is normalised only when it is read out at the end.

MuJoCo: a free joint (gravity 0) for the torque-free body, a ball joint ``j`` at the pivot for a body with
any torque, the body's inertia set by ``diaginertia`` about its centre of mass (the pivot moments minus
``M ℓ²``). Both joints' ``qvel`` angular velocity is in the body's local frame (MuJoCo's convention for free
and ball joints; checked by the benchmark itself, whose MuJoCo errors converge to our exact solutions).
Spin friction and air drag are actuators on ``j`` with an affine velocity bias (no control): friction a
``general`` actuator with gear ``(a, 0, 0, 0)``, force ``−c (a · ω)`` along ``a``; drag two, along body x and y,
force ``−c_air ω_i`` (tests/benchmarks checks that ``qfrc_actuator`` is the project's torque). Stepping uses
``mujoco.rollout`` (C loop, no Python per step) in chunks.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from physics import G


class PeerTimeout(Exception):
    """A peer run exceeded its CPU cap (recorded as 'not reached')."""


def scipy_run(case, method: str, rtol: float, cpu_cap: float = float("inf")):
    """Integrate ``case`` with ``solve_ivp``; returns (R (3,3), ω (3,), number of RHS evaluations).

    Raises :class:`PeerTimeout` once the run has used more than ``cpu_cap`` seconds of CPU (checked every
    1000 right-hand-side evaluations), so that a hopeless setting (RK45 or LSODA over 10^4 periods) cannot
    stall the benchmark.
    """
    import time

    I = case.moments
    start = time.process_time()
    calls = [0]
    inv = np.where(I > 0, 1.0 / np.where(I > 0, I, 1.0), 0.0)
    mgc = case.mass * G * case.com
    fc, dc = case.friction, case.drag
    a0, a1, a2 = np.asarray(case.friction_axis, dtype=float) / np.linalg.norm(case.friction_axis)

    def rhs(t, y):
        calls[0] += 1
        if calls[0] % 1000 == 0 and time.process_time() - start > cpu_cap:
            raise PeerTimeout(f"{method} rtol {rtol} over {cpu_cap} s")
        x, yq, z, w = y[0], y[1], y[2], y[3]
        o0, o1, o2 = y[4], y[5], y[6]
        l0, l1, l2 = I[0] * o0, I[1] * o1, I[2] * o2
        t0, t1, t2 = l1 * o2 - l2 * o1, l2 * o0 - l0 * o2, l0 * o1 - l1 * o0
        if case.mass:
            # τ = c × (Rᵀ(−M g ẑ)); the third row of R from the quaternion
            u0 = 2.0 * (x * z - w * yq)
            u1 = 2.0 * (yq * z + w * x)
            u2 = 1.0 - 2.0 * (x * x + yq * yq)
            t0 -= mgc[1] * u2 - mgc[2] * u1
            t1 -= mgc[2] * u0 - mgc[0] * u2
            t2 -= mgc[0] * u1 - mgc[1] * u0
        if fc:  # spin friction −c (ω · a) a
            wa = fc * (o0 * a0 + o1 * a1 + o2 * a2)
            t0, t1, t2 = t0 - wa * a0, t1 - wa * a1, t2 - wa * a2
        if dc:  # transverse air drag −c_air (ω1, ω2, 0)
            t0, t1 = t0 - dc * o0, t1 - dc * o1
        # q ⊗ (ω, 0), scalar last
        return [
            0.5 * (w * o0 + yq * o2 - z * o1),
            0.5 * (w * o1 + z * o0 - x * o2),
            0.5 * (w * o2 + x * o1 - yq * o0),
            0.5 * (-x * o0 - yq * o1 - z * o2),
            t0 * inv[0],
            t1 * inv[1],
            t2 * inv[2],
        ]

    q0 = Rotation.from_matrix(case.R0).as_quat()
    y0 = np.concatenate([q0, case.L0 * inv])
    scale = max(np.max(np.abs(y0[4:])), 1.0)
    atol = np.concatenate([np.full(4, rtol), np.full(3, rtol * scale)])
    sol = solve_ivp(rhs, (0.0, case.t_end), y0, method=method, rtol=rtol, atol=atol)
    y = sol.y[:, -1]
    R = Rotation.from_quat(y[:4] / np.linalg.norm(y[:4])).as_matrix()
    return R, y[4:], sol.nfev


def scipy_energy_series(case, method: str, rtol: float, t_eval):
    """Energy along a solve_ivp run sampled at t_eval (for the long-run plot)."""
    I = case.moments

    def rhs(t, y):
        w = y[4:]
        l = I * w
        q = y[:4]
        x, yq, z, s = q
        o0, o1, o2 = w
        return np.array(
            [
                0.5 * (s * o0 + yq * o2 - z * o1),
                0.5 * (s * o1 + z * o0 - x * o2),
                0.5 * (s * o2 + x * o1 - yq * o0),
                0.5 * (-x * o0 - yq * o1 - z * o2),
                *(np.cross(l, w) / I),
            ]
        )

    y0 = np.concatenate([Rotation.from_matrix(case.R0).as_quat(), case.L0 / I])
    sol = solve_ivp(rhs, (0.0, t_eval[-1]), y0, method=method, rtol=rtol, atol=rtol, t_eval=t_eval)
    w = sol.y[4:].T
    return 0.5 * np.sum(I * w * w, axis=1), sol.t.size, sol.nfev


# --------------------------------------------------------------------------------------------------
# MuJoCo
# --------------------------------------------------------------------------------------------------

_INTEGRATORS = {"Euler": "Euler", "implicitfast": "implicitfast", "RK4": "RK4"}


def _quiet_mujoco():
    """Unstable coarse steps make MuJoCo warn (to stdout and MUJOCO_LOG.TXT); the benchmark records the
    resulting NaN as an infinite error instead."""
    import mujoco

    mujoco.set_mju_user_warning(lambda msg: None)


def _pivoted(case) -> bool:
    """A ball joint at the pivot (any torque) rather than a free joint (the torque-free body)."""
    return bool(case.mass or case.friction or case.drag)


def mujoco_model(case, integrator: str, dt: float):
    """An MjModel of the case; returns (model, data)."""
    import mujoco

    _quiet_mujoco()

    I = [float(x) for x in case.moments]
    actuators = ""
    if _pivoted(case):
        ell = np.asarray(case.com, dtype=float)
        m = case.mass or 1.0  # without gravity: any mass at the pivot (ℓ = 0), the moments are the inertia
        # inertia about the centre of mass: pivot moments minus the parallel-axis terms (com on z)
        d2 = ell @ ell
        icm = [float(v) for v in np.asarray(I) - m * (d2 - ell * ell)]
        ell = [float(v) for v in ell]
        body = (
            f'<body name="b" pos="0 0 0"><joint name="j" type="ball" damping="0" armature="0"/>'
            f'<inertial pos="{ell[0]!r} {ell[1]!r} {ell[2]!r}" mass="{m!r}" '
            f'diaginertia="{icm[0]!r} {icm[1]!r} {icm[2]!r}"/></body>'
        )
        gravity = f"0 0 {-G if case.mass else 0.0!r}"
        gears = []
        if case.friction:
            a = [float(v) for v in np.asarray(case.friction_axis, dtype=float) / np.linalg.norm(case.friction_axis)]
            gears.append((f"{a[0]!r} {a[1]!r} {a[2]!r}", float(case.friction)))
        if case.drag:
            gears += [("1 0 0", float(case.drag)), ("0 1 0", float(case.drag))]
        actuators = "".join(
            f'<general joint="j" gear="{g} 0 0 0" gainprm="0" biastype="affine" biasprm="0 0 {-c!r}"/>'
            for g, c in gears
        )
        actuators = f"<actuator>{actuators}</actuator>" if actuators else ""
    else:
        body = (
            f'<body name="b" pos="0 0 0"><freejoint/>'
            f'<inertial pos="0 0 0" mass="1" diaginertia="{I[0]!r} {I[1]!r} {I[2]!r}"/></body>'
        )
        gravity = "0 0 0"
    xml = (
        f'<mujoco><option timestep="{dt!r}" integrator="{_INTEGRATORS[integrator]}" gravity="{gravity}">'
        f'<flag contact="disable" constraint="disable" energy="enable"/></option>'
        f"<worldbody>{body}</worldbody>{actuators}</mujoco>"
    )
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    q = Rotation.from_matrix(case.R0).as_quat()  # x y z w
    wq = np.array([q[3], q[0], q[1], q[2]])
    omega = case.L0 / case.moments
    if _pivoted(case):
        data.qpos[:] = wq
        data.qvel[:] = omega
    else:
        data.qpos[3:7] = wq
        data.qvel[3:6] = omega
    mujoco.mj_forward(model, data)
    return model, data


def mujoco_run(case, integrator: str, dt: float, chunk: int = 20000):
    """Step the MuJoCo model to ``t_end`` (n = round(t_end/dt) steps); returns (R, ω, n)."""
    import mujoco
    from mujoco import rollout

    n = max(1, int(round(case.t_end / dt)))
    model, data = mujoco_model(case, integrator, case.t_end / n)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    size = mujoco.mj_stateSize(model, spec)
    state = np.empty(size)
    mujoco.mj_getState(model, data, state, spec)
    done = 0
    while done < n:
        k = min(chunk, n - done)
        out, _ = rollout.rollout(model, data, state[None, :], nstep=k)
        state = out[0, -1].copy()
        done += k
    mujoco.mj_setState(model, data, state, spec)
    if _pivoted(case):
        wq, w = data.qpos[0:4], data.qvel[0:3]
    else:
        wq, w = data.qpos[3:7], data.qvel[3:6]
    R = Rotation.from_quat([wq[1], wq[2], wq[3], wq[0]]).as_matrix()
    return R, np.array(w), n
