"""Closed-loop linear models of the NREL 5 MW with our baseline controller: margins and poles over wind speed.

Run: ``python examples/closed_loop_margins.py`` (about 15 s; writes closed_loop_margins.png). The same from the
command line: ``mbsym linearize --wind 4:25:1 --closed-loop --plot closed_loop_margins.png``.
"""

from mbsym.wind.analysis.closed_loop import closed_loop_sweep
from mbsym.wind.operation import OperatingTurbine

model = OperatingTurbine.nrel5mw()                 # rotor-effective aerodynamics, GenDOF + tower fore-aft/side-side
sweep = closed_loop_sweep(model, [6.0, 9.0, 13.0, 16.0, 20.0, 25.0])
print(sweep.table())

cl = sweep[3]                                      # 16 m/s, region 3: both loops active
print(cl)
for pole in cl.poles:
    if pole.freq_hz < 2.0:
        print(f"  {pole.label:<40} {pole.freq_hz:7.3f} Hz  zeta {pole.damping_ratio:6.3f}")
step = cl.step_response("Wind1VelX", 0.1, 20.0)    # deviations after a 0.1 m/s wind step (SI units)
print(f"peak rotor-speed deviation after +0.1 m/s: {max(abs(step['RotSpeed'])):.2e} rad/s, "
      f"pitch settles at +{step['BldPitch1'][-1]:.2e} rad")
sweep.plot("closed_loop_margins.png")
