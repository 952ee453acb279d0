"""The result of :func:`mbsym.simulate`: named time series and statistics."""

from __future__ import annotations

from dataclasses import InitVar, dataclass, field

import numpy as np

from ..exceptions import OptionError

__all__ = ["SimulationResult"]


@dataclass(frozen=True, eq=False)
class SimulationResult:
    """Time series of a simulation (immutable; arrays are read-only).

    Attributes
    ----------
    t : ndarray (N,)
        Output times [s].
    x : ndarray (N, n_x)
        States ``[q; qd]`` [m, rad; m/s, rad/s] at ``t``.
    states : tuple of str
        Names of the columns of ``x`` (coordinates, then speeds ``<name>_d``).
    u : ndarray (N, n_u)
        Inputs at ``t``, as used by the integration.
    inputs : tuple of str
        Names of the columns of ``u``.
    y : ndarray (N, n_y)
        Model outputs at ``t`` (``n_y = 0`` if the model defines none).
    output_names : tuple of str
        Names of the columns of ``y``.
    statistics : dict
        ``method``, ``steps``, ``n_rhs`` (rhs evaluations), ``n_jac`` (Jacobian
        evaluations), ``integration_wall_s`` (integration alone, inputs sampling
        included), ``prepare_wall_s`` (building or fetching the CasADi
        Functions, including code generation and compilation with
        ``compile=True``), ``cache_hit`` (the prepared Functions came from the
        in-process cache), ``disk_cache_hit`` (with ``compile=True``, whether
        the libraries loaded by this preparation came from the disk cache; None
        when none was loaded), ``compiled`` (whether the method ran compiled C),
        ``outputs_wall_s`` (evaluating the model outputs), ``dt`` (fixed step
        actually used [s]), ``success`` (the integrator reached the last output
        time; failures raise IntegrationError), ``message``, and per method
        extras (``rtol``, ``atol``, ``n_lu``; ``input_samples`` of the SUNDIALS
        methods: samples per callable input). Counters a method does not know
        are ``None``.
    output_units : tuple of str
        Units of the columns of ``y`` ("" when the model gives none), e.g. OpenFAST's.
    structural : int or None
        Number of coordinates ``q`` when ``x`` starts with ``[q; qd]`` (equations of
        motion, or dynamics composed around them); None for other first-order dynamics,
        where :attr:`q` and :attr:`qd` are not defined.
    state_units : dict of str to str
        Units of the states the model knows (:attr:`mbsym.Dynamics.state_units`; the joints'
        :attr:`EquationsOfMotion.units`); see :meth:`unit`.
    input_units : dict of str to str
        Units of the inputs the model knows (:attr:`mbsym.Dynamics.input_units`).

    Units follow docs/units.md: states and inputs in SI, outputs in the model's units (an operating
    turbine's OpenFAST channels in OpenFAST's units).
    """

    t: np.ndarray
    x: np.ndarray
    states: tuple[str, ...]
    u: np.ndarray
    inputs: tuple[str, ...]
    y: np.ndarray
    output_names: tuple[str, ...]
    statistics: dict = field(default_factory=dict)
    output_units: tuple[str, ...] = ()
    structural: int | None = -1
    state_units: dict = field(default_factory=dict)
    input_units: dict = field(default_factory=dict)
    #: Internal: the arrays are fresh float arrays of the library's own (no private copy needed).
    _owned: InitVar[bool] = False

    def __post_init__(self, _owned: bool) -> None:
        for name in ("t", "x", "u", "y"):
            value = getattr(self, name)
            adopt = _owned and isinstance(value, np.ndarray) and value.dtype == float and value.flags.owndata
            arr = value if adopt else np.array(value, dtype=float)   # a private copy, then read-only
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)
        units = tuple(self.output_units) or ("",) * len(self.output_names)
        if len(units) != len(self.output_names):
            raise ValueError(f"output_units has {len(units)} entries for {len(self.output_names)} outputs.")
        object.__setattr__(self, "output_units", units)
        if self.structural == -1:                       # not given: x = [q; qd]
            object.__setattr__(self, "structural", len(self.states) // 2)

    @property
    def units(self) -> dict[str, str]:
        """Units of the outputs by name (e.g. ``res.units["RotSpeed"] == "rpm"``)."""
        return dict(zip(self.output_names, self.output_units))

    @property
    def n_q(self) -> int:
        """Number of coordinates (see :attr:`structural`)."""
        if self.structural is None:
            raise AttributeError("this result is of first-order dynamics without coordinates q (structural is "
                                 "None): use x, states and state(name).")
        return self.structural

    @property
    def coordinates(self) -> tuple[str, ...]:
        return self.states[: self.n_q]

    @property
    def q(self) -> np.ndarray:
        """Coordinates, shape (N, n_q) (a view of ``x``)."""
        return self.x[:, : self.n_q]

    @property
    def qd(self) -> np.ndarray:
        """Speeds, shape (N, n_q) (a view of ``x``)."""
        return self.x[:, self.n_q: 2 * self.n_q]

    @property
    def success(self) -> bool:
        return bool(self.statistics.get("success", False))

    @property
    def message(self) -> str:
        return str(self.statistics.get("message", ""))

    def state(self, name: str) -> np.ndarray:
        """Time series of one state (a coordinate ``q`` or a speed ``q_d``), shape (N,)."""
        return self.x[:, _index(self.states, name, "state")]

    def output(self, name: str) -> np.ndarray:
        """Time series of one model output, shape (N,)."""
        return self.y[:, _index(self.output_names, name, "output")]

    def to_dict(self) -> dict[str, np.ndarray]:
        """Columns by name: ``t``, then states, inputs and outputs (e.g. for ``pandas.DataFrame``).

        Raises
        ------
        ValueError
            If a name is used twice (say, an output named like a state).
        """
        cols: dict[str, np.ndarray] = {"t": self.t}
        for names, arr in ((self.states, self.x), (self.inputs, self.u), (self.output_names, self.y)):
            for j, name in enumerate(names):
                if name in cols:
                    raise ValueError(f"the name {name!r} appears twice among t, states, inputs and outputs; "
                                     "use the arrays x, u, y instead.")
                cols[name] = arr[:, j]
        return cols

    def unit(self, name: str, kind: str | None = None) -> str:
        """Unit of an output, a state or an input (``"-"`` if the model does not say).

        ``kind`` (``"output"``, ``"state"`` or ``"input"``) picks among names used twice with
        different units: an operating turbine's generator-torque state ``GenTq`` is in N m (SI, as
        every state) and its OpenFAST channel ``GenTq`` in kN-m. Without ``kind``: outputs, then
        states, then inputs.

        Raises
        ------
        OptionError
            An unknown ``kind``.
        """
        tables = {"output": self.units, "state": self.state_units, "input": self.input_units}
        if kind is not None and kind not in tables:
            raise OptionError(f"kind must be one of {list(tables)} or None; got {kind!r}.")
        for k in ((kind,) if kind is not None else tuple(tables)):
            if tables[k].get(name):
                return tables[k][name]
        return "-"

    def __repr__(self) -> str:
        s = self.statistics

        def named(names, kind, limit=8):
            shown = [f"{n} [{self.unit(n, kind)}]" for n in names[:limit]]
            return ", ".join(shown) + (f", … ({len(names)} in all)" if len(names) > limit else "") or "none"

        return (f"SimulationResult(method={s.get('method')!r}, t = {self.t[0]:g} .. {self.t[-1]:g} s "
                f"({self.t.size} points, {s.get('steps')} steps); states: {named(self.states, 'state')}; "
                f"inputs: {named(self.inputs, 'input', 4)}; outputs: {named(self.output_names, 'output', 4)})")


def _index(names: tuple[str, ...], name: str, what: str) -> int:
    try:
        return names.index(name)
    except ValueError:
        raise KeyError(f"no {what} named {name!r}; the {what}s are {list(names)}.") from None
