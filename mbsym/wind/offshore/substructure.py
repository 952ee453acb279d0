"""A bottom-fixed SubDyn substructure: Guyan and Craig–Bampton reduction to the transition piece (TP).

:class:`Substructure` builds the frame of a SubDyn input file (:mod:`.frame_fem`), locks all six DOFs
of the reaction joints, ties the interface joints rigidly to the TP reference point and reduces the
model as OpenFAST v5's SubDyn does at initialization (``SD_Init``, ``SD_Craig_Bampton``,
``SetParameters``); :class:`ReducedSubstructure` holds the result and evaluates SubDyn's output
equation (``SD_CalcOutput``).

**The TP reference point** is ElastoDyn's platform reference point (``PtfmRefxt``, ``PtfmRefyt``,
``PtfmRefzt``): the glue code passes ElastoDyn's ``PlatformPtMesh`` position to SubDyn as
``TP_RefPoint`` (``FAST_Subs.f90``), SubDyn's TP input and output meshes sit there, and the glue code
maps them to and from ``PlatformPtMesh`` point to point at the same place (``FAST_Mapping.f90``), so
loads and motions pass unchanged. It need not coincide with an interface joint: the joints follow
the TP as a rigid body (``TI``).

**Partition and reduction.** DOFs are C (reaction joints, all locked: removed), R (the interface
joints, 6 each, file order) and L (all other nodes). With Φ_R = −K_LL⁻¹ K_LR (Guyan modes), the
interface-level M̄_BB = M_RR + M_RL Φ_R + (M_RL Φ_R)ᵀ + Φ_Rᵀ M_LL Φ_R, K̄_BB = K_RR + K_RL Φ_R and
M̄_Bm = M_RL Φ_m + Φ_Rᵀ M_LL Φ_m, where Φ_m are the first ``n`` mass-normalized eigenvectors of
(K_LL, M_LL) (frequencies ω_m). With T_I the rigid transformation from the TP point to the interface
DOFs (u_joint = u_TP + θ_TP × (x_joint − x_TP)): K_BB = T_Iᵀ K̄_BB T_I, M_BB = T_Iᵀ M̄_BB T_I,
M_Bm = T_Iᵀ M̄_Bm, M_mB = M_Bmᵀ. Guyan damping C_BB: 0 (``GuyanDampMod`` 0), α M_BB + β K_BB (1,
``RayleighDamp``), or the file's 6×6 matrix (2). Modal damping C_mm = diag(2 ζ_m ω_m) (``JDampings``),
K_mm = diag(ω_m²).

**The output equation** (fixed bottom, ``SD_SolveEOM`` then ``SD_CalcOutput``). Inputs: the TP
displacement u = (x, y, z, θx, θy, θz) [m, rad] (θ: SubDyn's small angles of the TP orientation,
``GetSmllRotAngs``; to first order ElastoDyn's roll, pitch, yaw), the TP velocity u̇ = (v, ω) and
acceleration ü = (a, ω̇) [m/s, rad/s, m/s², rad/s²] in global axes, the CB states q, q̇, and the
external nodal loads F_ext,k (force, moment at node k, global; HydroDyn's ``LMesh``). All loads act
at the TP reference point in global axes (ElastoDyn's ``PlatformPtMesh``), in ElastoDyn's platform DOF
order (surge, sway, heave, roll, pitch, yaw):

1. Nodal loads: F_k = F_ext,k + F_g,k (gravity, :attr:`.FrameModel.gravity_load`) plus, at every node,
   the lever-arm moment Δu_k × f_k of its force f_k (external + gravity), with Δu = Φ_TP u the nodes'
   Guyan displacements (``LeverArm``: no CB part); at a concentrated mass of weight W and offset r
   also (R(Δθ_k)ᵀ r − r) × (0, 0, −W) (R = ``SmllRotTrans`` of the node's Guyan rotation).
2. q̈ = Φ_CBᵀ F − M_mB ü − C_mm q̇ − K_mm q   (Φ_CBᵀ F = Φ_mᵀ F_L, the modal load).
3. F_TP = M_BB ü + C_BB u̇ + K_BB u + M_Bm q̈.
4. Y1 = Φ_TPᵀ F − F_TP   (Φ_TPᵀ F = T_Iᵀ (F_R + Φ_Rᵀ F_L): the Guyan-reduced nodal loads).
5. Y1_moment += −(x, y, z) × Y1_force   (the "Guyan load correction" of the TP translation).

Y1 is the load SubDyn applies to ElastoDyn's platform (SubDyn's ``Intf1F*ss`` channels print −Y1).
At static equilibrium under gravity alone (u = 0, q = q₀ = K_mm⁻¹ Φ_mᵀ F_g, q̇ = q̈ = 0)
Y1 = Φ_TPᵀ F_g (:attr:`ReducedSubstructure.gravity_load`): the part of the substructure's weight the TP
carries in a clamped–clamped static solution; the base carries the rest. SubDyn starts the CB states
at q = q̇ = 0, where q̈ = Φ_mᵀ F_g and Y1 = Φ_TPᵀ F_g − M_Bm Φ_mᵀ F_g: gravity starts a modal transient
(:meth:`ReducedSubstructure.static_modal_coordinates` gives q₀). ``SttcSolve`` (the static
improvement) adds (K_LL⁻¹ − Φ_m ω_m⁻² Φ_mᵀ) F_L to the interior displacements used only for SubDyn's own
member-load channels: it changes neither Y1 nor the node motion SubDyn gives HydroDyn (``Y2Mesh``:
u_nodes = Φ_TP u + Φ_CB q, likewise for velocities and accelerations).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from ...exceptions import DimensionError, ModelWarning, ParameterError
from ..deck.subdyn import SubDynSettings, _format_error
from .frame_fem import FrameModel, build_frame, rigid_transform, small_rotation_matrix

__all__ = ["Substructure", "ReducedSubstructure"]


def _cross_matrix(v) -> np.ndarray:
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def _node_dofs(nodes) -> np.ndarray:
    """The six DOF indices of each node, in order."""
    return (6 * np.asarray(nodes, dtype=int)[:, None] + np.arange(6)).reshape(-1)


def _vector(value, n: int, name: str) -> np.ndarray:
    arr = np.zeros(n) if value is None else np.asarray(value, dtype=float).reshape(-1)
    if arr.shape != (n,):
        raise DimensionError(f"`{name}` has {arr.size} entries; expected {n}.")
    return arr


@dataclass(frozen=True, eq=False)
class ReducedSubstructure:
    """SubDyn's TP-level model (module docstring), SI units, ElastoDyn's platform DOF order.

    Attributes
    ----------
    reference_point : ndarray, shape (3,)
        The TP reference point [m] (ElastoDyn's platform reference point).
    stiffness, mass, damping : ndarray, shape (6, 6)
        K_BB [N/m, N/rad, N m/rad], M_BB [kg, kg m, kg m²], C_BB [N s/m, …] at the TP.
    frequencies : ndarray, shape (n,)
        CB mode frequencies ω_m [rad/s] (n = 0 for a Guyan reduction).
    damping_ratios : ndarray, shape (n,)
        ζ_m [-].
    mass_coupling : ndarray, shape (6, n)
        M_Bm [√kg, √kg m] (SubDyn's ``MBM`` at the TP; M_mB is its transpose). The CB coordinates q [√kg m]
        are those of mass-normalized modes (unit modal mass), as SubDyn's.
    gravity_load : ndarray, shape (6,)
        Φ_TPᵀ F_g [N, N m]: Y1 on ElastoDyn's platform at static equilibrium (u = 0, q = q₀).
    modal_gravity_load : ndarray, shape (n,)
        Φ_CBᵀ F_g [√kg m/s²].
    tp_shapes : ndarray, shape (6 N, 6)
        Φ_TP: displacements of the N nodes' six DOFs (node k: rows 6k…6k+5) per unit TP DOF.
    modal_shapes : ndarray, shape (6 N, n)
        Φ_CB: the same per unit CB coordinate [1/√kg, rad/(√kg m)] (zero at the interface and reaction
        nodes).
    frame : FrameModel
        The full model (node positions, gravity loads, concentrated masses).
    """

    reference_point: np.ndarray
    stiffness: np.ndarray
    mass: np.ndarray
    damping: np.ndarray
    frequencies: np.ndarray
    damping_ratios: np.ndarray
    mass_coupling: np.ndarray
    gravity_load: np.ndarray
    modal_gravity_load: np.ndarray
    tp_shapes: np.ndarray
    modal_shapes: np.ndarray
    frame: FrameModel
    _static_dofs: np.ndarray
    _static_flexibility: np.ndarray

    @property
    def n_modes(self) -> int:
        """Number of CB modes kept."""
        return len(self.frequencies)

    @property
    def modal_stiffness(self) -> np.ndarray:
        """K_mm = diag(ω_m²) [1/s²] (unit modal mass)."""
        return np.diag(self.frequencies ** 2)

    @property
    def modal_damping(self) -> np.ndarray:
        """C_mm = diag(2 ζ_m ω_m) [1/s]."""
        return np.diag(2.0 * self.damping_ratios * self.frequencies)

    def guyan_frequencies(self) -> np.ndarray:
        """Frequencies [Hz] of (K_BB, M_BB), ascending (SubDyn's summary ``GY_frequencies``)."""
        values = scipy.linalg.eigh(self.stiffness, self.mass, eigvals_only=True)
        return np.sqrt(np.maximum(values, 0.0)) / (2.0 * math.pi)

    def static_modal_coordinates(self) -> np.ndarray:
        """q₀ = K_mm⁻¹ Φ_CBᵀ F_g [√kg m]: the CB coordinates at rest under gravity (SubDyn starts at 0)."""
        return self.modal_gravity_load / self.frequencies ** 2

    def _nodal_loads(self, u: np.ndarray, nodal_loads) -> np.ndarray:
        """Step 1 of the output equation: the (6N,) nodal loads with gravity and lever arms."""
        n = self.frame.n_nodes
        loads = self.frame.gravity_load.reshape(n, 6).copy()
        if nodal_loads is not None:
            ext = np.asarray(nodal_loads, dtype=float)
            if ext.size != 6 * n:
                raise DimensionError(f"`nodal_loads` has {ext.size} entries; expected {6 * n} (6 per node).")
            loads += ext.reshape(n, 6)
        guyan = (self.tp_shapes @ u).reshape(n, 6)
        loads[:, 3:] += np.cross(guyan[:, :3], loads[:, :3])
        for node, weight, offset in self.frame.point_masses:
            turned = small_rotation_matrix(guyan[node, 3:]).T @ offset
            loads[node, 3:] += np.cross(turned - offset, (0.0, 0.0, -weight))
        return loads.reshape(-1)

    def tp_loads(self, u, udot, uddot, q=None, qdot=None, nodal_loads=None) -> tuple[np.ndarray, np.ndarray]:
        """SubDyn's output equation: the TP load on ElastoDyn's platform and the CB accelerations.

        Parameters
        ----------
        u, udot, uddot : array_like, shape (6,)
            TP displacement [m, rad], velocity [m/s, rad/s], acceleration [m/s², rad/s²] (module docstring).
        q, qdot : array_like, shape (n,), optional
            CB coordinates [√kg m] and rates [√kg m/s] (default 0).
        nodal_loads : array_like, shape (N, 6) or (6 N,), optional
            External forces [N] and moments [N m] at the nodes, global axes.

        Returns
        -------
        load : ndarray, shape (6,)
            Y1: force [N] and moment [N m] at the TP reference point, global axes.
        qddot : ndarray, shape (n,)
            CB accelerations [√kg m/s²].
        """
        u, udot, uddot = (_vector(v, 6, name) for v, name in ((u, "u"), (udot, "udot"), (uddot, "uddot")))
        q, qdot = _vector(q, self.n_modes, "q"), _vector(qdot, self.n_modes, "qdot")
        loads = self._nodal_loads(u, nodal_loads)
        qddot = (self.modal_shapes.T @ loads - self.mass_coupling.T @ uddot
                 - 2.0 * self.damping_ratios * self.frequencies * qdot - self.frequencies ** 2 * q)
        y1 = self.tp_shapes.T @ loads - (self.mass @ uddot + self.damping @ udot + self.stiffness @ u
                                         + self.mass_coupling @ qddot)
        y1[3:] -= np.cross(u[:3], y1[:3])
        return y1, qddot

    def lever_arm_stiffness(self) -> tuple[np.ndarray, np.ndarray]:
        """The gravity lever-arm terms of the output equation (steps 1 and 5), linearized at rest.

        Linearized at the static equilibrium (u = 0, q = q₀) with gravity as the only load:
        Y1 ≈ Φ_TPᵀ F_g + (G − K_BB) u − C_BB u̇ − M_BB ü − M_Bm q̈ and
        q̈ ≈ G_m u − M_mB ü − C_mm q̇ − K_mm (q − q₀). (Step 5 also holds −(x, y, z) × (−K_BB u …): a
        second-order term.)

        Returns
        -------
        tp : ndarray, shape (6, 6)
            G [N/m, N/rad, N m/m, N m/rad]: lever arms of the nodal weights, rotated concentrated-mass offsets
            and −(x, y, z) × the gravity force at the TP.
        modal : ndarray, shape (n, 6)
            G_m: q̈ [√kg m/s²] per unit TP DOF [m, rad].
        """
        n = self.frame.n_nodes
        weights = self.frame.gravity_load.reshape(n, 6)[:, :3]
        shapes = self.tp_shapes.reshape(n, 6, 6)
        change = np.zeros((n, 6, 6))
        for k in range(n):
            change[k, 3:] = -_cross_matrix(weights[k]) @ shapes[k, :3]
        for node, weight, offset in self.frame.point_masses:
            change[node, 3:] += _cross_matrix((0.0, 0.0, -weight)) @ _cross_matrix(offset) @ shapes[node, 3:]
        change = change.reshape(6 * n, 6)
        tp = self.tp_shapes.T @ change
        tp[3:, :3] += _cross_matrix(self.gravity_load[:3])
        return tp, self.modal_shapes.T @ change

    def node_displacements(self, u, q=None, static_loads=None) -> np.ndarray:
        """Node displacements and small rotations (N, 6) [m, rad]: Φ_TP u + Φ_CB q (SubDyn's ``Y2Mesh``).

        The same map gives velocities and accelerations from (u̇, q̇) and (ü, q̈). ``static_loads`` (6 N,)
        adds SubDyn's static improvement (K_LL⁻¹ − Φ_m ω_m⁻² Φ_mᵀ) F_L of those loads, which SubDyn uses
        only for its member-load channels.
        """
        disp = self.tp_shapes @ _vector(u, 6, "u") + self.modal_shapes @ _vector(q, self.n_modes, "q")
        if static_loads is not None:
            loads = _vector(static_loads, 6 * self.frame.n_nodes, "static_loads")
            disp[self._static_dofs] += self._static_flexibility @ loads[self._static_dofs]
        return disp.reshape(-1, 6)


class Substructure:
    """A bottom-fixed SubDyn substructure (module docstring): frame, partition, reductions.

    Parameters
    ----------
    settings : SubDynSettings
        From :func:`~mbsym.wind.deck.subdyn.read_subdyn`.
    reference_point : array_like, shape (3,)
        ElastoDyn's platform reference point (``PtfmRefxt``, ``PtfmRefyt``, ``PtfmRefzt``) [m]: the TP.
    gravity : float
        [m/s²] (the ``.fst``'s ``Gravity``).
    water_depth : float
        [m]; SubDyn uses it only to place its base-reaction channels at (0, 0, −depth): see
        :attr:`base_point`.

    Attributes
    ----------
    frame : FrameModel
        Nodes (``frame.positions``), elements, K, M, nodal gravity loads.
    fixed_dofs, interface_dofs, interior_dofs : ndarray of int
        The C, R and L DOF indices into the 6 N frame DOFs.
    interface_transform : ndarray, shape (6 n_I, 6)
        T_I (SubDyn's ``TI``).
    guyan_modes : ndarray, shape (n_L, 6 n_I)
        Φ_R.
    interface_stiffness, interface_mass : ndarray, shape (6 n_I, 6 n_I)
        K̄_BB, M̄_BB at the interface joints (before T_I).

    Examples
    --------
    >>> from mbsym.wind.deck.subdyn import read_subdyn
    >>> sub = Substructure.from_subdyn(read_subdyn("IEA-15-240-RWT-Monopile_SubDyn.dat"),
    ...                                reference_point=(0, 0, 15), gravity=9.81)  # doctest: +SKIP
    >>> red = sub.guyan()  # doctest: +SKIP
    >>> red.guyan_frequencies()[:2]  # doctest: +SKIP
    array([3.73599..., 3.73599...])
    """

    def __init__(self, settings: SubDynSettings, reference_point, gravity: float = 9.80665,
                 water_depth: float = 0.0) -> None:
        point = np.asarray(reference_point, dtype=float).reshape(-1)
        if point.shape != (3,) or not np.all(np.isfinite(point)):
            raise DimensionError(f"`reference_point` must be 3 finite numbers [m]; got {reference_point!r}.")
        if not (math.isfinite(gravity) and gravity > 0):
            raise ParameterError(f"`gravity` must be a positive number [m/s²]; got {gravity!r}.")
        if any(settings.rigid_body_position):
            warnings.warn(f"{settings.path}: the initial rigid-body position {settings.rigid_body_position} is used by "
                          "SubDyn only for floating structures with several transition pieces; it has no effect on a "
                          "bottom-fixed one (nor here).", ModelWarning, stacklevel=2)
        self.settings = settings
        self.reference_point = point
        self.gravity = float(gravity)
        self.base_point = np.array([0.0, 0.0, -float(water_depth)])
        self.frame = build_frame(settings, self.gravity)
        n = self.frame.n_nodes
        boundary = set(self.frame.reaction_nodes) | set(self.frame.interface_nodes)
        self.fixed_dofs = _node_dofs(self.frame.reaction_nodes)
        self.interface_dofs = _node_dofs(self.frame.interface_nodes)
        self.interior_dofs = _node_dofs([k for k in range(n) if k not in boundary])
        blocks = [rigid_transform(self.frame.positions[k] - point) for k in self.frame.interface_nodes]
        self.interface_transform = np.vstack(blocks)  # T_I, (6 n_I, 6)
        k, m = self.frame.stiffness, self.frame.mass
        r, l_ = self.interface_dofs, self.interior_dofs
        self._lu = scipy.linalg.lu_factor(k[np.ix_(l_, l_)]) if len(l_) else None
        self._check_conditioning(k[np.ix_(l_, l_)])
        self.guyan_modes = -self._solve_interior(k[np.ix_(l_, r)])  # Φ_R, (n_L, n_R)
        coupling = m[np.ix_(r, l_)] @ self.guyan_modes
        mbb = m[np.ix_(r, r)] + coupling + coupling.T + self.guyan_modes.T @ m[np.ix_(l_, l_)] @ self.guyan_modes
        kbb = k[np.ix_(r, r)] + k[np.ix_(r, l_)] @ self.guyan_modes
        t = self.interface_transform
        self.interface_stiffness, self.interface_mass = 0.5 * (kbb + kbb.T), 0.5 * (mbb + mbb.T)
        self._kbb, self._mbb = t.T @ self.interface_stiffness @ t, t.T @ self.interface_mass @ t
        self._modes: tuple[np.ndarray, np.ndarray] | None = None

    @classmethod
    def from_subdyn(cls, settings: SubDynSettings, reference_point, gravity: float = 9.80665,
                    water_depth: float = 0.0) -> "Substructure":
        """Build from read settings (same arguments as the class)."""
        return cls(settings, reference_point, gravity, water_depth)

    def _check_conditioning(self, kll: np.ndarray) -> None:
        """Warn when K_LL is so ill-conditioned that the reduction is round-off (e.g. Euler–Bernoulli
        elements 1 mm long: 12 E I / L³ dwarfs the rest of the matrix)."""
        if self._lu is None:
            return
        rcond, _ = scipy.linalg.lapack.dgecon(self._lu[0], np.abs(kll).sum(axis=0).max(), norm="1")
        if rcond < 1e-12:
            shortest = float(self.frame.element_length.min())
            digits = math.log10(1.0 / max(rcond, 1e-300))
            warnings.warn(f"{self.settings.path}: the interior stiffness matrix has a condition number of about "
                          f"1e{digits:.0f}: the reduction loses about {digits:.0f} of its 16 digits to round-off "
                          f"(SubDyn's LAPACK solve too). The shortest element is {shortest:.3g} m long: merge joints "
                          "that close, or use Timoshenko elements (FEMMod 3).", ModelWarning, stacklevel=3)

    def _solve_interior(self, rhs: np.ndarray) -> np.ndarray:
        """K_LL⁻¹ rhs (empty when every node is a reaction or interface node)."""
        return scipy.linalg.lu_solve(self._lu, rhs) if self._lu is not None else np.zeros(rhs.shape)

    # ------------------------------------------------------------------ modes
    def _interior_modes(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """The first ``n`` (or all) eigenpairs of (K_LL, M_LL), mass-normalized, largest entry positive."""
        n_l = len(self.interior_dofs)
        if n_l == 0:
            return np.zeros(0), np.zeros((0, 0))
        if self._modes is None or self._modes[0].size < n:
            l_ = self.interior_dofs
            kll, mll = self.frame.stiffness[np.ix_(l_, l_)], self.frame.mass[np.ix_(l_, l_)]
            count = min(max(n + 1, 12), n_l)
            values, vectors = scipy.linalg.eigh(kll, mll, subset_by_index=[0, count - 1])
            vectors = vectors / np.sqrt(np.einsum("ij,ij->j", vectors, mll @ vectors))
            big = np.argmax(np.abs(vectors), axis=0)
            vectors *= np.sign(vectors[big, np.arange(count)])
            self._modes = (np.sqrt(np.maximum(values, 0.0)), vectors)
        return self._modes[0][:n], self._modes[1][:, :n]

    def full_frequencies(self, n: int = 12) -> np.ndarray:
        """The first ``n`` frequencies [Hz] of the whole frame with the reaction DOFs locked (SubDyn's
        summary ``Full_frequencies``)."""
        free = np.setdiff1d(np.arange(6 * self.frame.n_nodes), self.fixed_dofs)
        k, m = self.frame.stiffness[np.ix_(free, free)], self.frame.mass[np.ix_(free, free)]
        values = scipy.linalg.eigh(k, m, eigvals_only=True, subset_by_index=[0, min(n, len(free)) - 1])
        return np.sqrt(np.maximum(values, 0.0)) / (2.0 * math.pi)

    def rigid_body_mass(self, point=None) -> np.ndarray:
        """6×6 rigid-body mass of the whole frame about ``point`` [m] (default: the TP reference point)
        (SubDyn's summary ``M_P``; ``MRB`` for the origin)."""
        origin = self.reference_point if point is None else np.asarray(point, dtype=float)
        t = np.vstack([rigid_transform(p - origin) for p in self.frame.positions])
        return t.T @ self.frame.mass @ t

    # ------------------------------------------------------------------ reductions
    def guyan(self) -> ReducedSubstructure:
        """The Guyan reduction (no CB mode), with the deck's Guyan damping."""
        return self.craig_bampton(0)

    def reduce(self) -> ReducedSubstructure:
        """The reduction the deck asks for: ``Nmodes`` CB modes (0: Guyan; < 0: all interior modes)."""
        n = self.settings.n_modes
        return self.craig_bampton(len(self.interior_dofs) if n < 0 else n)

    def craig_bampton(self, n_modes: int | None = None, damping_ratios=None) -> ReducedSubstructure:
        """The Craig–Bampton reduction with ``n_modes`` interior modes (module docstring).

        Parameters
        ----------
        n_modes : int, optional
            Number of CB modes (default: the deck's ``Nmodes``; all interior modes if it is < 0).
        damping_ratios : float or sequence of float, optional
            ζ_m [-]; a shorter sequence repeats its last value (SubDyn's rule). Default: the deck's
            ``JDampings``.

        Raises
        ------
        OpenFASTFormatError
            More modes than interior DOFs (names the file, line and key ``Nmodes``).
        ParameterError
            Modes asked for without damping ratios (the deck gives none when ``Nmodes`` is 0).
        """
        s = self.settings
        n_l = len(self.interior_dofs)
        if n_modes is None:
            n_modes = n_l if s.n_modes < 0 else s.n_modes
        if not 0 <= n_modes <= n_l:
            raise _format_error(s, "Nmodes", f"{n_modes} CB modes asked for, but the frame has {n_l} interior DOFs "
                                f"(6 per node that is neither a reaction nor an interface node). Use 0 to {n_l}.")
        zeta = np.atleast_1d(np.asarray(s.mode_damping if damping_ratios is None else damping_ratios, dtype=float))
        if zeta.ndim != 1 or not np.all(np.isfinite(zeta)) or np.any(zeta < 0):
            raise ParameterError(f"`damping_ratios` must be non-negative numbers; got {damping_ratios!r}.")
        if n_modes and zeta.size == 0:
            raise ParameterError("Craig-Bampton modes need damping ratios: give `damping_ratios` (the deck's Nmodes "
                                 "is 0, so its JDampings line is a comment).")
        zeta = np.concatenate([zeta, np.repeat(zeta[-1:], max(n_modes - zeta.size, 0))])[:n_modes]
        omega, phi = self._interior_modes(n_modes)
        if 0 < n_modes < n_l:
            following = self._interior_modes(n_modes + 1)[0][-1]
            if following - omega[-1] <= 1e-6 * following:
                warnings.warn(f"{s.path}: CB modes {n_modes} and {n_modes + 1} have the same frequency "
                              f"({omega[-1] / (2 * math.pi):.6g} Hz): keeping {n_modes} modes keeps one direction of a "
                              "degenerate pair, chosen arbitrarily (so does SubDyn's LAPACK). Keep both modes.",
                              ModelWarning, stacklevel=2)
        m, r, l_ = self.frame.mass, self.interface_dofs, self.interior_dofs
        t = self.interface_transform
        mbm = t.T @ (m[np.ix_(r, l_)] @ phi + self.guyan_modes.T @ m[np.ix_(l_, l_)] @ phi)
        n_dof = 6 * self.frame.n_nodes
        tp_shapes = np.zeros((n_dof, 6))
        tp_shapes[r] = t
        tp_shapes[l_] = self.guyan_modes @ t
        modal = np.zeros((n_dof, n_modes))
        modal[l_] = phi
        fg = self.frame.gravity_load
        # SttcSolve: K_LL^-1 - Φ_m ω_m^-2 Φ_mᵀ, for the interior displacements of SubDyn's member outputs
        flexibility = self._solve_interior(np.eye(n_l)) - (phi / omega ** 2) @ phi.T
        return ReducedSubstructure(self.reference_point.copy(), self._kbb.copy(), self._mbb.copy(),
                                   self._guyan_damping(), omega, zeta, mbm, tp_shapes.T @ fg, modal.T @ fg,
                                   tp_shapes, modal, self.frame, l_.copy(), 0.5 * (flexibility + flexibility.T))

    def _guyan_damping(self) -> np.ndarray:
        s = self.settings
        if s.guyan_damping_model == 1:
            alpha, beta = s.rayleigh_damping
            return alpha * self._mbb + beta * self._kbb
        if s.guyan_damping_model == 2:
            return np.array(s.guyan_damping_matrix, dtype=float)
        return np.zeros((6, 6))
