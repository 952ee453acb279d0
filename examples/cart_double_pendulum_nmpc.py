"""Swing-up and stabilization of a double pendulum on a cart: NMPC with an MHE on noisy measurements.

The model is built with :class:`mbsym.System` (:func:`mbsym.control.models.cart_double_pendulum`:
a cart on a rail, two links with point masses, upright at zero angles). The pendulum starts
hanging (a1 = π) and must be swung up and held upright by pushing the cart (|F| ≤ 30 N, the
cart within ±2 m). The controller never sees the true state: an MHE estimates it from noisy
encoder readings of the cart position and of both link angles (σ = 5 mm / 5 mrad). The plant is
integrated accurately between samples (scipy DOP853), with the input held (zero-order hold).

Run: ``python examples/cart_double_pendulum_nmpc.py``. The last line is one JSON object.
"""

import json
import time

import numpy as np
from scipy.integrate import solve_ivp

from mbsym.control import MHE, NMPC, OCP
from mbsym.control.models import cart_double_pendulum

DT, STEPS, HORIZON = 0.05, 120, 40
NOISE = {"cart": 0.005, "a1": 0.005, "angle2": 0.005}

dyn = cart_double_pendulum()                 # states s, a1, a2, s_d, a1_d, a2_d; input F; outputs cart, angle2, ...
p = dyn.parameter_vector()

ocp = (OCP(dyn, horizon=HORIZON, dt=DT, substeps=2)
       .track({"s": 1.0, "a1": 10.0, "a2": 10.0, "s_d": 0.1, "a1_d": 0.1, "a2_d": 0.1, "F": 1e-3})
       .track({"s": 10.0, "a1": 100.0, "a2": 100.0, "s_d": 1.0, "a1_d": 1.0, "a2_d": 1.0}, terminal=True)
       .penalize_rates({"F": 1e-5})
       .bound("F", -30.0, 30.0)
       .bound("s", -2.0, 2.0))
t0 = time.perf_counter()
nmpc = NMPC(ocp, solver="rti", qp_solver="hpipm")                  # real-time iterations, compiled
mhe = MHE(dyn, dt=DT, window=20, measurements=["cart", "a1", "angle2"],
          process_noise={"s_d": 0.05, "a1_d": 0.1, "a2_d": 0.1}, measurement_noise=NOISE,
          x0=[0.0, np.pi, 0.0, 0.0, 0.0, 0.0], P0={"s": 0.1, "a1": 0.1, "a2": 0.1, "s_d": 0.5, "a1_d": 0.5,
                                                   "a2_d": 0.5})
build_s = time.perf_counter() - t0


def plant(x, u):
    """One sample of the true system: accurate integration with the input held."""
    sol = solve_ivp(lambda t, z: np.asarray(dyn.rhs(z, u, p)).ravel(), (0.0, DT), x, method="DOP853",
                    rtol=1e-8, atol=1e-10)
    return sol.y[:, -1]


rng = np.random.default_rng(0)
x = np.array([0.0, np.pi, 0.0, 0.0, 0.0, 0.0])
u = np.zeros(1)
log = {"x": [], "x_hat": [], "u": []}
for k in range(STEPS):
    y_true = dyn.output_value(x, u)
    y = np.array([y_true[0], x[1], y_true[3]]) + rng.normal(0.0, [NOISE[n] for n in NOISE])
    x_hat = mhe.step(y, u)                       # u: the input held over the last interval
    u = nmpc.step(x_hat)
    log["x"].append(x)
    log["x_hat"].append(x_hat)
    log["u"].append(u[0])
    x = plant(x, u)

X, X_hat, U = np.array(log["x"]), np.array(log["x_hat"]), np.array(log["u"])
wrap = lambda a: (a + np.pi) % (2 * np.pi) - np.pi          # noqa: E731
final = {"cart_m": float(x[0]), "a1_rad": float(wrap(x[1])), "angle2_rad": float(wrap(x[1] + x[2]))}
input_violation = max(float(np.max(np.abs(U)) - 30.0), 0.0)                  # |F| ≤ 30 N (hard)
cart_excess = max(float(np.max(np.abs(X[:, 0])) - 2.0), 0.0)                 # |s| ≤ 2 m, on the true plant
after = slice(STEPS // 2, None)                              # estimation error once upright
est_rms = np.sqrt(np.mean((X_hat[after, :3] - X[after, :3]) ** 2, axis=0))
nm, me = nmpc.summary(), mhe.summary()
walls = np.array([s.wall_s for s in nmpc.stats[1:]])        # the first step converges a full SQP
print(f"built NMPC + MHE in {build_s:.2f} s (compiled: {nmpc.compiled}); {STEPS} steps of {DT} s")
print(f"final state: cart {final['cart_m']:+.4f} m, a1 {final['a1_rad']:+.4f} rad, "
      f"link 2 {final['angle2_rad']:+.4f} rad")
print(f"NMPC step: median {1e3 * np.median(walls):.2f} ms, max {1e3 * walls.max():.2f} ms "
      f"(first step {1e3 * nmpc.stats[0].wall_s:.0f} ms); failures {nm['failures']}")
print(f"MHE step:  median {1e3 * me['step_median_s']:.2f} ms, max {1e3 * me['step_max_s']:.2f} ms "
      f"(window full, after the first solve: {1e3 * me['first_solve_s']:.0f} ms); "
      f"failures {me['failures']}; RMS error (s, a1, a2) once upright {est_rms.round(4).tolist()}")
print(json.dumps({**final, "max_input_violation_N": input_violation, "max_cart_excess_m": cart_excess,
                  "nmpc_step_median_s": float(np.median(walls)),
                  "nmpc_step_max_s": float(walls.max()), "nmpc_first_step_s": nmpc.stats[0].wall_s,
                  "nmpc_failures": nm["failures"], "mhe_step_median_s": me["step_median_s"],
                  "mhe_step_max_s": me["step_max_s"], "mhe_first_solve_s": me["first_solve_s"],
                  "mhe_failures": me["failures"],
                  "estimation_rms": est_rms.tolist(), "build_s": build_s}))
