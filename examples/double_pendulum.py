"""Quick start: the double pendulum of README.md, checked against its closed form.

Run: ``python examples/double_pendulum.py``. The last line is one JSON object.
"""

import json

import numpy as np

import mbsym as mb
from mbsym.demo import double_pendulum_closed_form

sys = mb.System(gravity=[0.0, 0.0, -9.81])
q1, q2 = sys.coordinates("q1 q2")
m1, m2, l1, l2 = sys.parameters("m1 m2 l1 l2")
b1 = mb.RigidBody("b1", mass=m1, com=[0, 0, -l1])      # point mass at the end of a massless link
b2 = mb.RigidBody("b2", mass=m2, com=[0, 0, -l2])
sys.add_joint(mb.Revolute(sys.ground, b1, axis=[0, 1, 0], coordinate=q1))
sys.add_joint(mb.Revolute(b1, b2, axis=[0, 1, 0], coordinate=q2, offset=[0, 0, -l1]))
eom = sys.equations()
p = {"m1": 2.0, "m2": 1.0, "l1": 1.0, "l2": 0.5}
M = eom.mass_matrix([0.3, -0.2], p)            # numpy array (2, 2)
F = eom.forcing([0.3, -0.2], [0.1, 0.4], p)    # numpy array (2,)  (no inputs declared)

M_ref, F_ref = double_pendulum_closed_form([0.3, -0.2], [0.1, 0.4], **p)
print(eom)
print("M =\n", M, "\nclosed form:\n", M_ref)
print("F =", F, " closed form:", F_ref)
print(json.dumps({"M": M.tolist(), "F": F.tolist(),
                  "max_error": float(max(np.abs(M - M_ref).max(), np.abs(F - F_ref).max()))}))
