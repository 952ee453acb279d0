"""OpenFAST channels that only a blade-element rotor has (names, units and signs of ElastoDyn and AeroDyn).

=====================  ======  =============================================================
channel                unit    definition
=====================  ======  =============================================================
RootMxc<k>, RootMyc<k>  kN-m   blade-root moments about the coned root axes i1 (in-plane moment),
                               i2 (out-of-plane moment): minus the reactions of the locked root
                               rotations (the equations of the same graph: aerodynamic, gravity
                               and inertia loads of the whole blade), as ElastoDyn's ``MomH0B·i``
RootMzc<k>             kN-m    pitching moment about the blade axis i3
RootMxb<k>, RootMyb<k> kN-m    the same moments in the pitched axes j1, j2
RootFxc<k> … RootFzc<k> kN     (``load_channels=True``) the blade's force on the hub at its root along
                               i1, i2, i3: minus the reactions of locked root translations
RootFxb<k>, RootFyb<k> kN      the same forces along j1, j2 (:mod:`mbsym.wind.structure.load_cuts`)
RtAeroFxh … RtAeroFzh  N       aerodynamic force on the rotor in AeroDyn's (rotating) hub axes
                               (:func:`aerodyn_hub_axes`)
RtAeroMxh … RtAeroMzh  N-m     aerodynamic moment about the apex in the hub axes
RtSkew                 deg     skew angle of the disk-averaged relative wind to the shaft
Wind1VelY, Wind1VelZ   m/s     the wind at the hub point (0, 0, hub height), as InflowWind's output point
B1N<j>Alpha …          deg …   AeroDyn node channels of blade 1 (Alpha, Phi [deg], Vrel [m/s],
                               AxInd, TnInd, Cl, Cd [-], Fn, Ft [N/m], Theta [deg]) for the nodes
                               :attr:`OperatingTurbine.output_nodes` lists
=====================  ======  =============================================================
"""

from __future__ import annotations

import math
from typing import Any

import casadi as ca

from ..structure.load_cuts import reaction_rows

__all__ = ["blade_channel_rows", "NODE_CHANNELS", "aerodyn_hub_axes"]

#: AeroDyn node channels: name -> (key of the aero Function's ``node_*`` outputs, unit, scale).
NODE_CHANNELS = {"Alpha": ("alpha", "deg", 180.0 / math.pi), "Phi": ("phi", "deg", 180.0 / math.pi),
                 "Vrel": ("vrel", "m/s", 1.0), "AxInd": ("axial_induction", "-", 1.0),
                 "TnInd": ("tangential_induction", "-", 1.0), "Cl": ("cl", "-", 1.0), "Cd": ("cd", "-", 1.0),
                 "Fn": ("fn", "N/m", 1.0), "Ft": ("ft", "N/m", 1.0), "Theta": ("theta", "deg", 180.0 / math.pi)}


def blade_channel_rows(g) -> list[tuple[str, str, Any]]:
    """``(name, unit, expression)`` of the blade-element channels of the composed graph ``g``."""
    rows = _root_loads(g) + _rotor_loads(g)
    rows.append(("RtSkew", "deg", g.skew * 180.0 / math.pi))
    hub = g.blade_aero["hub_wind"]
    rows += [("Wind1VelY", "m/s", hub[1]), ("Wind1VelZ", "m/s", hub[2])]
    return rows + _node_rows(g)


def _root_loads(g) -> list[tuple[str, str, Any]]:
    """Root moments (and with ``load_channels`` the root forces) of every blade: minus the root reactions."""
    from .channels import reactions

    names = g.model.pitch_names
    pitch = [g.X[names[k] if len(names) > 1 else names[0]] for k in range(g.model.rotor.n_blades)]
    return [r for r in reaction_rows(g.eom.locked, reactions(g), pitch) if r[0].startswith("Root")]


def aerodyn_hub_axes(R: Any) -> Any:
    """AeroDyn's hub axes (columns) from the structure's hub-body frame ``R`` (columns x, y, z).

    AeroDyn writes ``RtAero*h`` (v5: ``RtFld*h``) in its hub motion's orientation, ElastoDyn's ``g1, g2, g3``
    (``ElastoDyn.f90``: ``e2 = cos q c2 + sin q c3`` at the internal azimuth ``q``, without the output azimuth's
    90° offset). That is the hub body's frame turned by −90° about the shaft: ``g2 = z``, ``g3 = −y``.
    Checked on OpenFAST v5 runs: series correlation 1.000 with these axes, 0.00 with the body's own."""
    return ca.horzcat(R[:, 0], R[:, 2], -R[:, 1])


def _rotor_loads(g) -> list[tuple[str, str, Any]]:
    R = aerodyn_hub_axes(g.hub_frame)
    force, moment = g.blade_aero["rotor_force"], g.blade_aero["rotor_moment"]
    rows = [(f"RtAeroF{a}h", "N", ca.dot(force, R[:, i])) for i, a in enumerate("xyz")]
    rows += [(f"RtAeroM{a}h", "N-m", ca.dot(moment, R[:, i])) for i, a in enumerate("xyz")]
    return [r for r in rows if r[0] not in ("RtAeroFxh", "RtAeroMxh")]


def _node_rows(g) -> list[tuple[str, str, Any]]:
    rows = []
    aero = g.blade_aero
    for j, node in enumerate(g.model.output_nodes, start=1):      # B1N<j>: the j-th listed node (BlOutNd)
        for name, (key, unit, scale) in NODE_CHANNELS.items():
            values = aero.get(f"node_{key}")
            if values is not None:
                rows.append((f"B1N{j}{name}", unit, scale * values[node - 1]))
    return rows
