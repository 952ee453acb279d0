"""Paper Sect. 4.3: the NREL 5 MW blade spinning about the rotor axis.

Branlard & Geisler, Wind Energ. Sci. 7 (2022), Sect. 4.3: one blade on a hub turning
at a constant speed Ω, no gravity, cone 0, with its 1st flap, 1st edge and 2nd flap
shape functions treated one at a time. For each shape: generalized mass Me and
stiffness Ke, the Southwell coefficient kΩ (flap: ω² = ω₀² + kΩ Ω²; edge:
ω² = ω₀² + (kΩ − 1) Ω², the −1 being the spin softening), and the frequency at
0, 6 and 12 rpm. The blade is discretized exactly as ElastoDyn does it (BldNodes
midpoint nodes, curvature integrated twice from the root); "one at a time as in the
paper" means each shape in its own plane (flap along the rotor axis, edge in the
rotor plane), without structural twist, and the blade rotating about its root
(the paper's Fig. 2 and Eq. 30: L_B = R, N(r) = ∫_r^R m Ω² r' dr'). A second
table gives the ElastoDyn-equivalent blade (twisted shapes, three shapes coupled,
root 1.5 m off the axis as in the turbine) against OpenFAST.

Blade data: built-in NREL 5 MW (``mbsym.wind.deck.nrel5mw()``); runs without ../shared.
The last printed line is one JSON object.

Run: ``python examples/paper_4_3_rotating_blade.py``
"""

import json

import numpy as np

import mbsym as mb
from mbsym.wind import nrel5mw
from mbsym.wind.structure.elastodyn_bodies import blade_shape_integrals

MODES = ("FlapDOF1", "EdgeDOF", "FlapDOF2")   # the paper's order: 1st flap, 1st edge, 2nd flap
LABELS = ("1st flap", "1st edge", "2nd flap")
# Printed in the paper, Sect. 4.3.
PAPER = {"Me": [9.5e3, 1.5e4, 5.7e3], "Ke": [1.7e4, 6.7e4, 8.7e4], "k_omega": [1.7, 1.4, 5.5]}
# OpenFAST v5.0.0 ElastoDyn linearization of the NREL 5 MW blade (hub held, gravity 0,
# cone 0), blade_campbell case of the project's shared OpenFAST reference data; the same
# numbers are quoted in the project's REFERENCE_NUMBERS notes. [Hz]
OPENFAST_HZ = {0: (0.67174, 1.07913, 1.98069), 3: (0.67510, 1.07967, 1.98427),
               6: (0.68504, 1.08128, 1.99498), 9: (0.70120, 1.08396, 2.01273),
               12: (0.72305, 1.08772, 2.03738), 15: (0.74993, 1.09255, 2.06874)}


def blade_on_hub(sid, hub_radius: float):
    """EquationsOfMotion of a hub (azimuth psi about x) carrying one flexible blade along +z."""
    sys = mb.System()
    psi = sys.coordinates("psi")
    qe = sys.coordinates([f"qe{j}" for j in range(sid.n_e)])
    qe = qe if isinstance(qe, tuple) else (qe,)
    hub = mb.RigidBody("hub", mass=1.0, inertia=[1.0e3, 1.0e3, 1.0e3])
    sys.add_joint(mb.Revolute(sys.ground, hub, axis=[1, 0, 0], coordinate=psi))
    sys.add_joint(mb.Fixed(hub, mb.FlexibleBody("blade", sid, qe), offset=[0.0, 0.0, hub_radius]))
    return sys.equations()


def blade_matrices(eom, rpm: float):
    """Blade block of M, C, K linearized at q = 0 with the hub spinning at ``rpm`` (hub held)."""
    qd0 = np.zeros(eom.n_q)
    qd0[0] = rpm * np.pi / 30.0
    lin = mb.linearize(eom, np.zeros(eom.n_q), qd0)
    return lin.M[1:, 1:], lin.C[1:, 1:], lin.K[1:, 1:]


def single_shapes(turbine):
    """Me, Ke, kΩ and frequencies of each shape alone (paper's treatment)."""
    out = {"Me": [], "Ke": [], "k_omega": [], "freq_hz": {"0": [], "6": [], "12": []}}
    for mode in MODES:
        sid = blade_shape_integrals(turbine, dofs=(mode,), twist=False)
        eom = blade_on_hub(sid, 0.0)          # paper Eq. 30: radius measured from the blade root
        M, _, K0 = blade_matrices(eom, 0.0)
        _, _, K12 = blade_matrices(eom, 12.0)
        om = 12.0 * np.pi / 30.0
        k_omega = (K12[0, 0] - K0[0, 0]) / (M[0, 0] * om**2) + (1.0 if mode == "EdgeDOF" else 0.0)
        out["Me"].append(float(sid.me[0, 0]))
        out["Ke"].append(float(sid.ke[0, 0]))
        out["k_omega"].append(float(k_omega))
        for rpm in (0, 6, 12):
            K = blade_matrices(eom, rpm)[2] if rpm else K0
            out["freq_hz"][str(rpm)].append(float(np.sqrt(K[0, 0] / M[0, 0]) / (2 * np.pi)))
    return out


def coupled_frequencies(turbine):
    """ElastoDyn-equivalent blade (twisted, 3 shapes coupled): frequencies [Hz] per rpm."""
    sid = blade_shape_integrals(turbine, dofs=("FlapDOF1", "FlapDOF2", "EdgeDOF"), twist=True)
    eom = blade_on_hub(sid, turbine.hub_radius)
    result = {}
    for rpm in OPENFAST_HZ:
        M, C, K = blade_matrices(eom, rpm)
        n = M.shape[0]
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
        lam = np.linalg.eigvals(A)
        f = np.sort(np.abs(lam[np.imag(lam) > 0])) / (2 * np.pi)
        result[rpm] = f.tolist()      # ascending: flap1, edge1, flap2
    return result


def main() -> dict:
    turbine = nrel5mw()
    out = single_shapes(turbine)
    coupled = coupled_frequencies(turbine)
    print("Paper Sect. 4.3 - NREL 5 MW blade on a spinning hub, no gravity, cone 0")
    print(f"(ElastoDyn discretization: {turbine.n_blade_nodes} nodes; each shape alone, untwisted, rotating"
          " about the blade root as in the paper)\n")
    print(f"{'shape':<9} {'Me [kg]':>9} {'paper':>8} {'Ke [N/m]':>10} {'paper':>8} {'kΩ':>6} {'paper':>6}"
          f" {'f0 [Hz]':>8} {'OpenFAST':>9} {'diff':>7}")
    for i, lab in enumerate(LABELS):
        f0, of = out["freq_hz"]["0"][i], OPENFAST_HZ[0][i]
        print(f"{lab:<9} {out['Me'][i]:9.4g} {PAPER['Me'][i]:8.2g} {out['Ke'][i]:10.4g} {PAPER['Ke'][i]:8.2g}"
              f" {out['k_omega'][i]:6.3f} {PAPER['k_omega'][i]:6.2g} {f0:8.4f} {of:9.5f} {100 * (f0 / of - 1):6.2f}%")
    print("\nSingle-shape frequencies [Hz] vs rotor speed:")
    for rpm in ("0", "6", "12"):
        print(f"  {rpm:>2} rpm: " + ", ".join(f"{f:.4f}" for f in out["freq_hz"][rpm]))
    print("\nElastoDyn-equivalent blade (twisted shapes, flap1/flap2/edge1 coupled) vs OpenFAST [Hz]:")
    worst = 0.0
    for rpm, f in coupled.items():
        ref = sorted(OPENFAST_HZ[rpm])
        err = max(abs(a / b - 1) for a, b in zip(f, ref))
        worst = max(worst, err)
        print(f"  {rpm:>2} rpm: " + "  ".join(f"{a:.5f} ({b:.5f})" for a, b in zip(f, ref)) + f"   max {err:.1e}")
    print("\nNotes:")
    print(" - The paper's printed Me are about 10x ours, while its Ke agree with ours: with the printed")
    print("   Me, sqrt(Ke/Me)/2π would be 0.21/0.34/0.62 Hz, far from the blade's known 0.67/1.08/1.98 Hz.")
    print("   Our Me give those frequencies within 1 %, so the printed Me carry a factor-10 misprint.")
    print(" - Ke differ from the print by a few % (2nd flap most): the paper used a different")
    print("   discretization of the distributed properties; ours is ElastoDyn's.")
    print(" - kΩ as the paper defines it (Eqs. 30-32, root on the axis); with the real 1.5 m hub radius")
    print("   they rise by 3-4 %, which the coupled table below includes. The paper prints 2 digits;")
    print("   continuous quadrature of the same shapes gives 1.725/1.394/5.510, ElastoDyn's 17 nodes")
    print("   move the 2nd flap value most.")
    print(" - f0 compares one shape alone with OpenFAST's coupled modes; the coupled, twisted model")
    print("   below is the like-for-like comparison.")
    print(f" - Coupled ElastoDyn-equivalent blade: worst difference from OpenFAST {worst:.1e}.")
    out["coupled_freq_hz"] = {str(k): v for k, v in coupled.items()}
    print(json.dumps(out))
    return out


if __name__ == "__main__":
    main()
