"""How OpenFAST v5's AeroDyn filters the induction through a wind step (DBEMT_Mod 2): the evidence behind the
model-form gap of issue 22 item 2's identification check (docs/identification.md).

One isolated OpenFAST v5.0.0 run of the shared ``step_10_14`` deck (wind 10 -> 14 m/s over t = 30.0-30.1 s) with
everything but the induction dynamics taken out: no ServoDyn (``CompServo = 0``: no controller library needed), no
DOFs (``GenDOF``, ``TwFADOF1``, ``TwSSDOF1`` off: rotor speed 11.48 rpm and pitch 0.43 deg fixed), no shaft tilt
(``ShftTilt = 0``: no skewed-wake redistribution), ``TMax = 50`` s, and AeroDyn's all-node outputs ``AxInd``,
``AxInd_qs``, ``Vx`` of blade 1 plus ``DBEMTau1``. After the ramp the quasi-steady induced velocity
``v_s = a_qs Vx`` of every node is constant, so Øye's filter (AeroDyn's DBEMT, ``mbsym.wind.aero.blade.dbemt``)
must take the induced velocity ``v = a Vx`` monotonically from its old to its new value.

The script replays two filters node by node on OpenFAST's own ``a_qs``, ``Vx`` and ``tau1`` (outputs every
0.05 s, linear in between, AeroDyn's exact per-step update on 8 sub-steps):

* ``ode``: the Øye ODE as AeroDyn's DBEMT.f90 writes it, ``v_s(t) = a_qs(t) Vx(t)`` at both ends of each step
  (what mbsym integrates);
* ``newest wind``: both ends of each step built with the wind of the newer end, ``a_qs(t) Vx(t + dt)`` and
  ``a_qs(t + dt) Vx(t + dt)``. In OpenFAST v5's ``AD_UpdateStates`` (AeroDyn.f90) the BEMT inputs at ``t`` and
  ``t + dt`` are both set from one copy of the inflow taken before the loop over the two times, so a change of
  the wind drops out of the ``k tau1 dv_s/dt`` term of the filter (a change of the induction factor or of the
  structure's velocity does not).

Run: ``python benchmarks/dbemt_wind_step.py [--workdir DIR]`` (about 1-3 min of OpenFAST). Prints a Markdown
table; benchmarks/README.md, section "DBEMT through a wind step", holds the measured one.
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from _report import shared_aero

OYE_K = 0.6
NODES = (9, 13, 17)            # AeroDyn blade nodes compared (r/R 0.45, 0.71, 0.94)
NODE_CHANNELS = ("AxInd", "AxInd_qs", "Vx")


def _set(text: str, key: str, value: str) -> str:
    """Replace the value in front of ``key`` (OpenFAST's ``value  key  - comment`` layout)."""
    new, n = re.subn(rf"^(\s*)(\S+)(\s+{re.escape(key)}\s)", lambda m: f"{m.group(1)}{value}{m.group(3)}", text,
                     count=1, flags=re.MULTILINE)
    if n != 1:
        raise SystemExit(f"key {key} not found")
    return new


def make_case(work: Path) -> Path:
    """The isolated case under ``work`` (module docstring); returns its .fst."""
    src = shared_aero() / "openfast_inputs"
    shutil.copytree(src / "deck", work / "deck", dirs_exist_ok=True)
    case = work / "iso"
    case.mkdir(parents=True, exist_ok=True)
    for f in (src / "step_10_14").iterdir():
        shutil.copy(f, case / f.name)
    fst = case / "step_10_14.fst"
    text = _set(_set(fst.read_text(), "TMax", "50"), "CompServo", "0")
    fst.write_text(text)
    ed = case / "step_10_14_ED.dat"
    text = ed.read_text()
    for key in ("GenDOF", "TwFADOF1", "TwSSDOF1"):
        text = _set(text, key, "False")
    ed.write_text(_set(text, "ShftTilt", "0"))
    ad = work / "deck" / "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat"
    text = ad.read_text()
    end = text.index("END of input file")
    text = text[:end] + '"DBEMTau1"\n' + text[end:]
    nodal = ("====== Outputs for all blade stations (same ending as above for B1N1....) ======\n"
             "          1   BldNd_BladesOut     - Number of blades to output all node information at (-)\n"
             '"All"         BldNd_BlOutNd       - Nodes (-)\n'
             "              OutList             - Nodal outputs (-)\n"
             + "".join(f'"{c}"\n' for c in NODE_CHANNELS)
             + 'END of input file (the word "END" must appear in the first 3 columns of this last OutList line)\n'
             "---------------------------------------------------------------------------------------\n")
    last = text.index("\n", text.index("END of input file")) + 1
    ad.write_text(text[:last] + nodal)
    return fst


def read_outb(path: Path) -> tuple[list[str], np.ndarray, np.ndarray]:
    """(channel names, time, data) of an OpenFAST binary output (FileFmtID 1-4, OutFileFmt 2 or 4)."""
    with open(path, "rb") as f:
        fid = int(np.fromfile(f, np.int16, 1)[0])
        name_len = int(np.fromfile(f, np.int16, 1)[0]) if fid == 4 else 10
        n_ch, n_t = (int(v) for v in np.fromfile(f, np.int32, 2))
        t_a, t_b = np.fromfile(f, np.float64, 2)
        if fid != 3:
            scale, offset = np.fromfile(f, np.float32, n_ch), np.fromfile(f, np.float32, n_ch)
        f.read(int(np.fromfile(f, np.int32, 1)[0]))
        names = [f.read(name_len).decode().strip() for _ in range(n_ch + 1)]
        f.read(name_len * (n_ch + 1))                                    # units
        packed_time = np.fromfile(f, np.int32, n_t) if fid == 1 else None
        if fid == 3:
            data = np.fromfile(f, np.float64, n_t * n_ch).reshape(n_t, n_ch)
        else:
            data = (np.fromfile(f, np.int16, n_t * n_ch).reshape(n_t, n_ch) - offset) / scale
    time = (packed_time - t_b) / t_a if fid == 1 else t_a + t_b * np.arange(n_t)
    return names[1:], time, data


def replay(t: np.ndarray, a_qs: np.ndarray, vx: np.ndarray, tau1: np.ndarray, span_ratio: float, v0: float, *,
           newest_wind: bool, substeps: int = 8) -> np.ndarray:
    """Induced velocity ``v`` [m/s] of one node from ``v0`` at ``t[0]``, AeroDyn's exact DBEMT update per sub-step."""
    v1, v, out = a_qs[0] * vx[0], v0, [v0]
    k_tau = 0.39 - 0.26 * span_ratio**2
    for k in range(t.size - 1):
        h = (t[k + 1] - t[k]) / substeps
        for m in range(substeps):
            s0, s1 = m / substeps, (m + 1) / substeps
            a0, a1 = (a_qs[k] + s * (a_qs[k + 1] - a_qs[k]) for s in (s0, s1))
            x0, x1 = (vx[k] + s * (vx[k + 1] - vx[k]) for s in (s0, s1))
            vs0, vs1 = (a0 * x1, a1 * x1) if newest_wind else (a0 * x0, a1 * x1)
            ta = tau1[k] + s0 * (tau1[k + 1] - tau1[k])
            tb = k_tau * ta
            slope = (vs1 - vs0) / h
            A = vs0 + slope * OYE_K * ta
            c0 = v1 - A + slope * ta
            v1 = c0 * np.exp(-h / ta) + A + slope * (h - ta)
            c2 = v - c0 / (1 - k_tau) - A + slope * (ta + tb)
            v = c2 * np.exp(-h / tb) + A + slope * (h - ta - tb) + c0 / (1 - k_tau) * np.exp(-h / ta)
        out.append(v)
    return np.array(out)


def table(outb: Path, blade_file: Path, hub_radius: float = 1.5) -> list[str]:
    names, t, d = read_outb(outb)
    col = {n: i for i, n in enumerate(names)}
    nodal = [i for i, n in enumerate(names) if n.startswith("AB1N")]
    n_nodes = len(nodal) // len(NODE_CHANNELS)
    ax, ax_qs, vx = (d[:, nodal[j * n_nodes:(j + 1) * n_nodes]] for j in range(len(NODE_CHANNELS)))
    tau1 = d[:, col["DBEMTau1"]]
    lines = blade_file.read_text().splitlines()
    span = np.array([float(s.split()[0]) for s in lines[6:6 + n_nodes]])
    r = span + hub_radius
    k0 = int(np.searchsorted(t, 29.0 - 1e-9))
    tt = t[k0:]
    rows = [("| node | r/R | v before [m/s] | v_s after [m/s] | OpenFAST min v [m/s] (t) | ode min v | newest-wind min v "
             "| max abs(ode - OpenFAST) [m/s] | max abs(newest wind - OpenFAST) [m/s] |"),
            "|---|---|---|---|---|---|---|---|---|"]
    for n in NODES:
        j = n - 1
        v_of = (ax[:, j] * vx[:, j])[k0:]
        runs = {w: replay(tt, ax_qs[k0:, j], vx[k0:, j], tau1[k0:], r[j] / r.max(), v_of[0], newest_wind=w)
                for w in (False, True)}
        after = tt > 30.1
        i_min = int(np.argmin(v_of))
        rows.append(f"| {n} | {r[j] / r.max():.2f} | {v_of[0]:.3f} | {(ax_qs[:, j] * vx[:, j])[-1]:.3f} | "
                    f"{v_of[i_min]:.3f} ({tt[i_min]:.1f} s) | {runs[False].min():.3f} | {runs[True].min():.3f} | "
                    f"{np.max(np.abs(runs[False] - v_of)[after]):.3f} | "
                    f"{np.max(np.abs(runs[True] - v_of)[after]):.3f} |")
    return rows


def write_csv(outb: Path, path: Path, t_from: float = 29.0) -> None:
    """Time, hub wind, tau1 and, per node of :data:`NODES`, AxInd, AxInd_qs, Vx from ``t_from`` on (12 digits)."""
    names, t, d = read_outb(outb)
    nodal = [i for i, n in enumerate(names) if n.startswith("AB1N")]
    n_nodes = len(nodal) // len(NODE_CHANNELS)
    cols, header = [t, d[:, names.index("Wind1VelX")], d[:, names.index("DBEMTau1")]], ["Time_[s]", "Wind1VelX_[m/s]",
                                                                                       "DBEMTau1_[s]"]
    for n in NODES:
        for j, (c, unit) in enumerate(zip(NODE_CHANNELS, ("-", "-", "m/s"))):
            cols.append(d[:, nodal[j * n_nodes + n - 1]])
            header.append(f"AB1N{n:03d}{c}_[{unit}]")
    keep = t >= t_from - 1e-9
    data = np.column_stack(cols)[keep]
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savetxt(path, data, delimiter=",", header=",".join(header), comments="", fmt="%.12g")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--workdir", type=Path, help="where the case is written and run (default: a temporary dir)")
    ap.add_argument("--outb", type=Path, help="use this output of an earlier run instead of running OpenFAST")
    ap.add_argument("--csv", type=Path, help="also write the reference series of the test (tests/data/openfast_dbemt_step)")
    args = ap.parse_args(argv)
    work = args.workdir or Path(tempfile.mkdtemp(prefix="dbemt_step_"))
    outb = args.outb
    if outb is None:
        fst = make_case(work)
        exe = shared_aero().parents[1] / "tools" / "openfast" / "openfast"
        subprocess.run([str(exe), fst.name], cwd=fst.parent, check=True, stdout=subprocess.DEVNULL)
        outb = fst.with_suffix(".outb")
    blade = shared_aero() / "openfast_inputs" / "deck" / "NRELOffshrBsline5MW_AeroDyn_blade.dat"
    print("\n".join(table(outb, blade)))
    if args.csv is not None:
        write_csv(outb, args.csv)
    return 0


if __name__ == "__main__":
    sys.exit(main())
