"""Linear models of the NREL 5 MW with blade-element aerodynamics, in multi-blade coordinates (as OpenFAST + MBC3).

1. trim the rotor-effective model of the same deck at 14 m/s (pitch, torque, rotor speed);
2. hold those commands and find the periodic steady state of the blade-element turbine (flexible blades);
3. linearize at 12 azimuths, transform to multi-blade coordinates, average: a named control.StateSpace;
4. the Campbell diagram with aerodynamic damping over a few wind speeds.

Needs the shared OpenFAST decks (shared/openfast/aero): ``python examples/blade_linear_mbc.py [path/to/steady_14.fst]``.
"""

import sys
import time
from pathlib import Path

import numpy as np

import mbsym as mb
from mbsym.wind.analysis.blade_linear import blade_aero_campbell, blade_statespace, blade_linear_model, labelled_modes
from mbsym.wind.analysis.blade_periodic import periodic_point
from mbsym.wind.analysis.operating_points import operating_points
from mbsym.wind.operation import trim

DECK = "shared/openfast/aero/openfast_inputs/steady_14/steady_14.fst"
FST = Path(sys.argv[1]) if len(sys.argv) > 1 else \
    next((p / DECK for p in Path(__file__).resolve().parents if (p / DECK).exists()), Path(DECK))
DOFS = ["GenDOF", "TwFADOF1", "TwSSDOF1", "FlapDOF1", "EdgeDOF"]

rotor = mb.wind.OperatingTurbine.from_openfast(FST, aero="rotor", dofs=["GenDOF", "TwFADOF1", "TwSSDOF1"])
blade = mb.wind.OperatingTurbine.from_openfast(FST, aero="blade", dofs=DOFS, pitch="individual")

t0 = time.perf_counter()
point = periodic_point(blade, 14.0, start=trim(rotor, 14.0))
print(point, f"[{time.perf_counter() - t0:.1f} s]")

t0 = time.perf_counter()
ss = blade_statespace(blade, point)
print(f"StateSpace: {ss.nstates} states, inputs {ss.input_labels}, outputs {ss.output_labels} "
      f"[{time.perf_counter() - t0:.1f} s]")
k = ss.input_labels.index("BlPitchCom_coll")
print("static RotSpeed / collective pitch [rad/s per rad]:", float(np.real(ss.dcgain()[ss.output_labels.index("RotSpeed"), k])))

lin = blade_linear_model(blade, point, outputs=(), keep_azimuth=True)
for label, f, z in zip(*labelled_modes(lin)):
    print(f"  {label:28s} {f:7.4f} Hz  damping {100 * z:6.2f} %")

speeds = [8.0, 11.0, 14.0, 18.0, 22.0]
t0 = time.perf_counter()
diagram = blade_aero_campbell(blade, operating_points(rotor, speeds), progress=print)
print(f"Campbell diagram over {speeds} m/s [{time.perf_counter() - t0:.0f} s]")
diagram.plot("blade_aero_campbell.png", title="NREL 5 MW, blade-element aerodynamics, MBC average of 12 azimuths")
