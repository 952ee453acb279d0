"""The structure driven by its *measured* aerodynamic rotor loads: identification without an aerodynamic model.

An operating turbine's tower fore-aft mode is damped mostly by the rotor: at 14 m/s the NREL 5 MW's
``TwrFADmp(1)`` = 1 % is 0.36 points of about 7 % (docs/identification.md). Fitting the structural
damping through an aerodynamic model therefore asks the model for the aerodynamic damping to a few
hundredths of a point, which no rotor model holds through a wind step. When the record has the rotor's
aerodynamic loads — OpenFAST's AeroDyn channels ``RtAeroFxh``, ``RtAeroFyh``, ``RtAeroFzh``,
``RtAeroMxh``, ``RtAeroMyh``, ``RtAeroMzh`` (a turbine's blade-root gauges give the same) — they
already contain the aerodynamic damping the structure felt, and the structure alone, driven by them,
isolates the structural parameters: :class:`MeasuredLoadTurbine`.

The loads enter as the structure's hub inputs (:class:`~mbsym.wind.structure.turbine.TurbineModel`
with ``hub_moments``): ``RotThrust`` = ``RtAeroFxh``, ``RotTorq`` = ``RtAeroMxh``, and the in-plane force
and moment turned from AeroDyn's hub frame (rotating with the rotor azimuth ψ, ``Azimuth``; at ψ = 0 it
is the shaft frame, and blade 1 turns from the shaft's z axis towards −y) into the shaft frame::

    M_y = M_yh cos ψ − M_zh sin ψ,    M_z = M_yh sin ψ + M_zh cos ψ     (same for the forces)

(on the shared step run the rotating 1.3 MN m of ``RtAeroMyh`` becomes a steady 302 kN m tilt and yaw
moment, ±4.7 kN m of 3P ripple). The collective pitch (``BldPitch1``) and the generator torque
(``GenTq``) are the record's too. Left out, so refused: flexible blades (the aerodynamic loads act
along them, not at the hub), the platform's loads (hydrodynamics, mooring), AeroDyn's tower and nacelle
drag (not part of the rotor loads), teeter.

Measured on the shared ``step_10_14`` deck (docs/identification.md): without the four in-plane
channels the fit puts the disk's tilt damping into the tower (``TwrFADmp(1)`` 5 %); with them
(the same OpenFAST run with those channels recorded) 1.02 % against the deck's 1 %, in 0.1 s.
"""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from ...exceptions import DataError, ModelDefinitionError, SolverError
from .measured import _columns, channel_listing, match_channel

__all__ = ["MeasuredLoadTurbine", "ROTOR_LOAD_CHANNELS", "rotor_loads_recorded"]

#: AeroDyn's rotor-load channels (hub frame) and the azimuth that turns them, with their SI factors by unit.
ROTOR_LOAD_CHANNELS = {
    "RtAeroFxh": {"N": 1.0, "kN": 1e3}, "RtAeroFyh": {"N": 1.0, "kN": 1e3}, "RtAeroFzh": {"N": 1.0, "kN": 1e3},
    "RtAeroMxh": {"N-m": 1.0, "Nm": 1.0, "N m": 1.0, "kN-m": 1e3, "kNm": 1e3, "kN m": 1e3},
    "RtAeroMyh": {"N-m": 1.0, "Nm": 1.0, "N m": 1.0, "kN-m": 1e3, "kNm": 1e3, "kN m": 1e3},
    "RtAeroMzh": {"N-m": 1.0, "Nm": 1.0, "N m": 1.0, "kN-m": 1e3, "kNm": 1e3, "kN m": 1e3},
    "Azimuth": {"deg": np.pi / 180, "rad": 1.0},
    "BldPitch1": {"deg": np.pi / 180, "rad": 1.0},
    "GenTq": {"kN-m": 1e3, "kNm": 1e3, "kN m": 1e3, "N-m": 1.0, "Nm": 1.0, "N m": 1.0},
}
#: The unit of each channel when a record gives none (OpenFAST's).
_DEFAULT_UNIT = {"RtAeroFxh": "N", "RtAeroFyh": "N", "RtAeroFzh": "N", "RtAeroMxh": "N-m", "RtAeroMyh": "N-m",
                 "RtAeroMzh": "N-m", "Azimuth": "deg", "BldPitch1": "deg", "GenTq": "kN-m"}
_FLEXIBLE_BLADES = ("FlapDOF1", "FlapDOF2", "EdgeDOF")
_PLATFORM = ("PtfmSgDOF", "PtfmSwDOF", "PtfmHvDOF", "PtfmRDOF", "PtfmPDOF", "PtfmYDOF")


def rotor_loads_recorded(names) -> list[str]:
    """The channels of :data:`ROTOR_LOAD_CHANNELS` missing from ``names`` (empty: the record drives the model)."""
    return [c for c in ROTOR_LOAD_CHANNELS if match_channel(set(names), c) is None]


class MeasuredLoadTurbine:
    """The structure of an operating turbine driven by the recorded rotor loads, pitch and torque (module docstring).

    Parameters
    ----------
    turbine : OperatingTurbine
        The deck's operating turbine built with ``aero="rotor", disk_moments=True`` (its structure has the hub
        moment and force inputs; its yaw drive is ServoDyn's). Only its structure is used.

    Attributes
    ----------
    structure : TurbineModel
    fixed_states : tuple of str
        ``("GeAz",)``: the azimuth starts from the record and is not estimated.

    Raises
    ------
    TypeError
        ``turbine`` is not an OperatingTurbine.
    ModelDefinitionError
        A load the rotor channels do not hold acts on the model (flexible blades, platform, tower or nacelle
        drag), or the structure has no hub moment inputs.
    """

    fixed_states = ("GeAz",)

    def __init__(self, turbine) -> None:
        from .model import OperatingTurbine

        if not isinstance(turbine, OperatingTurbine):
            raise TypeError(f"turbine must be an OperatingTurbine; got {type(turbine).__name__}.")
        structure = turbine.structure
        dofs = structure.dofs
        problems = [f"{k} (the aerodynamic loads act along the flexible blades, not at the hub)"
                    for k in _FLEXIBLE_BLADES if dofs.get(k)]
        problems += [f"{k} (hydrodynamic and mooring loads are not in the record)" for k in _PLATFORM if dofs.get(k)]
        if dofs.get("TeetDOF"):
            problems.append("TeetDOF (the teeter hinge takes the hub loads)")
        if getattr(turbine, "tower_aero", None) is not None and getattr(turbine.tower_aero, "drag", False):
            problems.append("AeroDyn's tower drag (TwrAero; not part of the rotor loads)")
        if getattr(turbine, "nacelle_drag", None) is not None:
            problems.append("AeroDyn's nacelle drag (NacelleDrag; not part of the rotor loads)")
        if problems:
            raise ModelDefinitionError("the structure driven by the measured rotor loads leaves out "
                                       + "; ".join(problems) + ". Use the operating turbine with its aerodynamics "
                                       "(MeasuredInputTurbine, mbsym identify --model operating) for this deck.")
        if "RotMomY" not in structure.eom.inputs:
            raise ModelDefinitionError("the turbine's structure has no hub moment inputs: build the OperatingTurbine "
                                       "with aero='rotor', disk_moments=True.")
        self.turbine, self.structure = turbine, structure
        self._dynamics = None

    def dynamics(self):
        """The structure as an :class:`mbsym.Dynamics` (its inputs: :meth:`inputs_from`'s columns)."""
        if self._dynamics is None:
            from ...dynamics import as_dynamics

            self._dynamics = as_dynamics(self.structure)
        return self._dynamics

    def resolve_parameter(self, key: str):
        """An ElastoDyn key or descriptive name of the structure (:meth:`TurbineModel.resolve_parameter`)."""
        return self.structure.resolve_parameter(key)

    def inputs_from(self, record: Any) -> np.ndarray:
        """The structure's inputs (N, n_u) in SI units from a record (OpenFAST channel names and units; a dict of
        arrays is taken in OpenFAST's units). Raises :class:`~mbsym.exceptions.DataError` naming missing channels
        or unknown units."""
        names, columns, units = _columns(record)
        missing = rotor_loads_recorded(names)
        if missing:
            raise DataError(f"the structure driven by the rotor loads needs the channels {missing}; the record has "
                            f"{channel_listing(names)}. Record AeroDyn's RtAeroFxh ... RtAeroMzh and ElastoDyn's "
                            "Azimuth, or "
                            "identify through the aerodynamics (mbsym identify --model operating).")
        si = {}
        for ch, factors in ROTOR_LOAD_CHANNELS.items():
            found = match_channel(names, ch)
            unit = units.get(found) or _DEFAULT_UNIT[ch]
            if unit not in factors:
                raise DataError(f"channel {found!r} is in {unit!r}; expected one of {list(factors)}.")
            si[ch] = columns[found] * factors[unit]
        psi = si["Azimuth"]
        c, s = np.cos(psi), np.sin(psi)
        values = {"BlPitch": si["BldPitch1"], "GenTq": si["GenTq"], "RotThrust": si["RtAeroFxh"],
                  "RotTorq": si["RtAeroMxh"],
                  "RotFrcY": si["RtAeroFyh"] * c - si["RtAeroFzh"] * s,
                  "RotFrcZ": si["RtAeroFyh"] * s + si["RtAeroFzh"] * c,
                  "RotMomY": si["RtAeroMyh"] * c - si["RtAeroMzh"] * s,
                  "RotMomZ": si["RtAeroMyh"] * s + si["RtAeroMzh"] * c}
        n = psi.size
        defaults = self.structure.default_inputs()
        out = []
        for name in self.dynamics().inputs:
            if name in values:
                out.append(values[name])
            elif name in ("BlPitch_d", "BlPitch_dd"):
                out.append(np.zeros(n))                       # ElastoDyn: the pitch rate moves no DOF
            elif not callable(defaults.get(name, 0.0)):
                out.append(np.full(n, float(defaults.get(name, 0.0))))
            else:
                raise DataError(f"input {name!r} of the structure is not given by the rotor-load record.")
        U = np.column_stack(out).astype(float)
        if not np.all(np.isfinite(U)):
            raise DataError("the rotor loads, pitch, torque and azimuth must be finite at every sample.")
        return U

    def initial_state_from(self, record: Any, u0: np.ndarray) -> np.ndarray:
        """The static state under the record's first loads, at its first rotor speed (``QD_GeAz``, else
        ``RotSpeed``) and azimuth: where :func:`mbsym.identify` starts (pass ``x0=`` or ``estimate_x0`` for a
        record that does not start steady)."""
        names, columns, _ = _columns(record)
        qd, rpm, q = (match_channel(names, n) for n in ("QD_GeAz", "RotSpeed", "Q_GeAz"))
        if qd is not None:
            speed = float(columns[qd][0])
        elif rpm is not None:
            speed = float(columns[rpm][0]) * np.pi / 30
        else:
            raise DataError("the record needs the rotor speed (QD_GeAz [rad/s] or RotSpeed [rpm]) to start from.")
        azimuth = float(columns[q][0]) if q is not None else \
            float(ROTOR_LOAD_CHANNELS["Azimuth"]["deg"] * columns[match_channel(names, "Azimuth")][0])
        return self.static_state(u0, rotor_speed=speed, azimuth=azimuth)

    def static_state(self, u: np.ndarray, *, rotor_speed: float, azimuth: float = 0.0,
                     p: Mapping[str, float] | None = None) -> np.ndarray:
        """Deflections at rest under the inputs ``u`` (SI) with the rotor turning at ``rotor_speed`` [rad/s]
        about ``azimuth`` [rad]: every rate but the rotor's zero."""
        from scipy.optimize import root

        dyn = self.dynamics()
        u = dyn.input_vector(np.asarray(u, dtype=float))
        pv = dyn.parameter_vector(p)
        x = dyn.x0.copy()
        held = {"GeAz": azimuth, "GeAz_d": rotor_speed}
        for k, v in held.items():
            if k in dyn.states:
                x[dyn.states.index(k)] = v
        free = [i for i, s in enumerate(dyn.states) if s not in held]

        def residual(z):
            xx = x.copy()
            xx[free] = z
            return np.asarray(dyn.rhs(xx, u, pv), dtype=float).reshape(-1)[free]

        sol = root(residual, x[free], method="hybr", options={"xtol": 1e-12})
        x[free] = sol.x
        bad = float(np.max(np.abs(residual(sol.x)))) if free else 0.0
        if not np.isfinite(bad) or bad > 1e-6:
            raise SolverError(f"no static state under the record's first loads (largest rate {bad:.2e}): give the "
                              "initial state (x0=) and estimate it (estimate_x0).")
        return x

    def __repr__(self) -> str:
        return f"MeasuredLoadTurbine({self.structure!r})"
