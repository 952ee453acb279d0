"""ElastoDyn's initial blade deflection: blade DOF values from OoPDefl and IPDefl (``InitBlDefl``)."""

from __future__ import annotations

import warnings

import numpy as np

from .elastodyn_bodies import BLADE_DOFS

__all__ = ["initial_blade_deflection"]


def initial_blade_deflection(tip_displacement, pitch: float, target, dofs: dict[str, bool], *,
                             blade: int = 1) -> dict[str, float]:
    """Blade DOF values giving the tip deflection ``target`` = (OoPDefl, IPDefl) [m] (notes §5).

    ElastoDyn's rule (``InitBlDefl``): with a flap DOF (FlapDOF1, else FlapDOF2) solve the 2x2
    system of its and the edge mode's coned-frame tip components; the other flap mode is 0.
    Without a flap DOF, least squares on the edge mode. ElastoDyn solves the 2x2 system even
    when EdgeDOF is off and freezes the edge mode at the solved value; a disabled DOF has no
    coordinate here, so the flap mode is then fitted alone (least squares) and a warning says so.

    Parameters
    ----------
    tip_displacement : array (3, 2)
        Tip (j1, j2) components of a unit F1, F2, E1 DOF (``ElastoDynBladeData.tip_displacement``).
    pitch : float
        Blade pitch [rad].
    target : sequence of 2
        (OoPDefl, IPDefl) [m].
    dofs : dict
        ElastoDyn flags -> enabled.

    Returns
    -------
    dict
        ``{"FlapDOF1": q, "FlapDOF2": q, "EdgeDOF": q}`` [m]; disabled DOFs are 0.

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> from mbsym.wind.structure.elastodyn_bodies import blade_elastodyn_data
    >>> ut = blade_elastodyn_data(nrel5mw()).tip_displacement
    >>> q = initial_blade_deflection(ut, 0.0, [1.0, 0.0], {"FlapDOF1": True, "EdgeDOF": True})
    >>> {k: round(v, 4) for k, v in q.items()}
    {'FlapDOF1': 0.9876, 'FlapDOF2': 0.0, 'EdgeDOF': 0.1268}
    """
    ut = np.asarray(tip_displacement, dtype=float)
    c, s = np.cos(pitch), np.sin(pitch)
    A = np.vstack([ut[:, 0] * c + ut[:, 1] * s, -ut[:, 0] * s + ut[:, 1] * c])    # (2, 3): OoP, IP per DOF
    target = np.asarray(target, dtype=float)
    out = {f: 0.0 for f in BLADE_DOFS}
    flap = next((f for f in ("FlapDOF1", "FlapDOF2") if dofs.get(f)), None)
    edge = BLADE_DOFS.index("EdgeDOF")
    if flap is None:
        if dofs.get("EdgeDOF"):
            a = A[:, edge]
            out["EdgeDOF"] = float(a @ target / (a @ a))
        return out
    i = BLADE_DOFS.index(flap)
    pair = A[:, [i, edge]]
    if dofs.get("EdgeDOF") and abs(np.linalg.det(pair)) > 1e-12:
        out[flap], out["EdgeDOF"] = (float(v) for v in np.linalg.solve(pair, target))
        return out
    a = A[:, i]
    out[flap] = float(a @ target / (a @ a))
    if not dofs.get("EdgeDOF") and abs(np.linalg.det(pair)) > 1e-12:
        frozen = np.linalg.solve(pair, target)
        if abs(frozen[1]) > 1e-12:
            warnings.warn(f"blade {blade}: ElastoDyn would freeze the disabled edge mode at q_E1 = {frozen[1]:.6g} m "
                          f"to meet OoPDefl/IPDefl; mbsym keeps it at 0 and fits {flap} alone "
                          f"(q = {out[flap]:.6g} m).", UserWarning, stacklevel=3)
    return out
