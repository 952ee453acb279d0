"""A planar five-bar (a closed loop) moved by NMPC: the end effector goes to a new point.

The five-bar is a parallel mechanism: two cranks on motors at the ground pivots A = (0, 0) and
E = (1, 0) m, each carrying a distal link; the two distal links meet at the end effector P. It is
built as a tree with two branches (crank 1 + distal 1 from A, crank 2 + distal 2 from E) and closed
at P with ``add_closure(..., directions="xy")``: four coordinates, two closure rows, two degrees of
freedom — the motor angles ``th1``, ``th2`` (independent); the distal angles ``ph1``, ``ph2`` follow
in the graph. Gravity acts along -y (a vertical plane); the motors' torques ``tau1``, ``tau2``
(|τ| ≤ 8 N m) are the inputs.

NMPC (``mbsym.control``: RTI, horizon 25 × 0.04 s) tracks the motor angles that put P at the target
(closed-form inverse kinematics of each arm, elbows out); the plant is the same closed-loop model
integrated by CVODES between samples, with the input held.

Run: ``python examples/five_bar_nmpc.py``. The last line is one JSON object.
"""

import json
import time

import numpy as np

import mbsym as mb
from mbsym.control import NMPC, OCP

D, CRANK, DISTAL = 1.0, 0.6, 0.8            # ground link, crank and distal lengths [m]
DT, STEPS, HORIZON = 0.04, 60, 25
START, TARGET = (0.5, 0.9), (0.75, 0.7)      # end-effector points [m]


def inverse_kinematics(P):
    """Motor and distal angles (th1, ph1, th2, ph2) [rad] putting the end effector at P, elbows out."""
    P = np.asarray(P, dtype=float)
    out = []
    for base, sign in ((np.zeros(2), 1.0), (np.array([D, 0.0]), -1.0)):
        r = P - base
        dist = np.linalg.norm(r)
        th = np.arctan2(r[1], r[0]) + sign * np.arccos((CRANK**2 + dist**2 - DISTAL**2) / (2 * CRANK * dist))
        elbow = base + CRANK * np.array([np.cos(th), np.sin(th)])
        out += [th, np.arctan2(*(P - elbow)[::-1]) - th]
    return np.array(out)


def five_bar():
    s = mb.System(gravity=[0.0, -9.81, 0.0])
    th1, ph1, th2, ph2 = s.coordinates("th1 ph1 th2 ph2")
    tau1, tau2 = s.inputs("tau1 tau2")
    bodies = {}
    for side, (th, ph, x0) in {"1": (th1, ph1, 0.0), "2": (th2, ph2, D)}.items():
        crank = mb.RigidBody(f"crank{side}", 0.5, com=[CRANK / 2, 0, 0], inertia=np.diag([1e-3, 0.015, 0.015]))
        distal = mb.RigidBody(f"distal{side}", 0.4, com=[DISTAL / 2, 0, 0], inertia=np.diag([1e-3, 0.02, 0.02]))
        s.add_joint(mb.Revolute(s.ground, crank, axis=[0, 0, 1], coordinate=th, offset=[x0, 0, 0]))
        s.add_joint(mb.Revolute(crank, distal, axis=[0, 0, 1], coordinate=ph, offset=[CRANK, 0, 0]))
        bodies[side] = distal
    s.add_torque(s.body("crank1"), [0, 0, tau1])
    s.add_torque(s.body("crank2"), [0, 0, tau2])
    for c in (th1, th2):
        s.add_damper(c, 0.02)                                  # motor bearing friction [N m s/rad]
    s.add_closure(bodies["1"], [DISTAL, 0, 0], bodies["2"], [DISTAL, 0, 0], directions="xy", name="effector")
    q0 = inverse_kinematics(START)
    return s.equations(independent=["th1", "th2"], guess=dict(zip(["th1", "ph1", "th2", "ph2"], q0)))


t0 = time.perf_counter()
eom = five_bar()
derive_s = time.perf_counter() - t0
goal = inverse_kinematics(TARGET)
ocp = (OCP(eom, horizon=HORIZON, dt=DT)
       .track({"th1": 50.0, "th2": 50.0, "th1_d": 0.5, "th2_d": 0.5, "tau1": 1e-6, "tau2": 1e-6},
              reference={"th1": goal[0], "th2": goal[2]})
       .track({"th1": 500.0, "th2": 500.0, "th1_d": 5.0, "th2_d": 5.0}, reference={"th1": goal[0], "th2": goal[2]},
              terminal=True)
       .bound("tau1", -8.0, 8.0)
       .bound("tau2", -8.0, 8.0))
t0 = time.perf_counter()
nmpc = NMPC(ocp, solver="rti", compile=False)
build_s = time.perf_counter() - t0
effector = eom.point_kinematics("distal1", [DISTAL, 0, 0])

q_start = inverse_kinematics(START)
x = np.array([q_start[0], q_start[2], 0.0, 0.0])
log_u, log_res = [], []
for k in range(STEPS):
    u = nmpc.step(x)
    log_u.append(u)
    run = mb.simulate(eom, DT, x0=x, inputs={"tau1": float(u[0]), "tau2": float(u[1])}, method="cvodes",
                      rtol=1e-9, atol=1e-11)
    log_res.append(float(np.max(run.output("closure_residual"))))
    x = run.x[-1]

P = np.asarray(effector(x[:2], x[2:], [0.0, 0.0], log_u[-1], []) [0]).ravel()[:2]
U = np.array(log_u)
walls = np.array([s.wall_s for s in nmpc.stats[1:]])
result = {"effector_m": P.tolist(), "target_m": list(TARGET), "error_m": float(np.linalg.norm(P - TARGET)),
          "max_torque_Nm": float(np.max(np.abs(U))), "max_closure_residual_m": max(log_res),
          "nmpc_failures": nmpc.summary()["failures"], "nmpc_step_median_s": float(np.median(walls)),
          "derivation_s": derive_s, "nmpc_build_s": build_s}
print(f"{eom!r}: derived in {derive_s:.2f} s; NMPC built in {build_s:.2f} s")
print(f"end effector after {STEPS * DT:.1f} s: ({P[0]:.4f}, {P[1]:.4f}) m, target {TARGET}, "
      f"error {1e3 * result['error_m']:.2f} mm; max |tau| {result['max_torque_Nm']:.2f} N m (bound 8)")
print(f"closure residual along the run <= {result['max_closure_residual_m']:.1e} m; NMPC step median "
      f"{1e3 * result['nmpc_step_median_s']:.1f} ms, failures {result['nmpc_failures']}")
print(json.dumps(result))
