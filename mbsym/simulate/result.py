"""The result of :func:`mbsym.simulate`: named time series and statistics."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

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
    units : dict of str to str
        Unit of each state, input and output by name (``"m"``, ``"rad/s"`` …; ``"-"`` where
        the model does not say): states from the joints (:attr:`EquationsOfMotion.units`),
        outputs from the model's output channels when they carry units.
    """

    t: np.ndarray
    x: np.ndarray
    states: tuple[str, ...]
    u: np.ndarray
    inputs: tuple[str, ...]
    y: np.ndarray
    output_names: tuple[str, ...]
    statistics: dict = field(default_factory=dict)
    units: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        for name in ("t", "x", "u", "y"):
            arr = np.array(getattr(self, name), dtype=float)   # a private copy, then read-only
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)

    @property
    def n_q(self) -> int:
        return len(self.states) // 2

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
        return self.x[:, self.n_q:]

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

    def unit(self, name: str) -> str:
        """Unit of a state, input or output (``"-"`` if unknown)."""
        return self.units.get(name, "-")

    def __repr__(self) -> str:
        s = self.statistics

        def named(names, limit=8):
            shown = [f"{n} [{self.unit(n)}]" for n in names[:limit]]
            return ", ".join(shown) + (f", … ({len(names)} in all)" if len(names) > limit else "") or "none"

        return (f"SimulationResult(method={s.get('method')!r}, t = {self.t[0]:g} .. {self.t[-1]:g} s "
                f"({self.t.size} points, {s.get('steps')} steps); states: {named(self.states)}; "
                f"inputs: {named(self.inputs, 4)}; outputs: {named(self.output_names, 4)})")


def result_units(model, eom, output_names) -> dict[str, str]:
    """Units by name for a :class:`SimulationResult`: states from ``eom.units``, outputs from the
    model's output channels (an ``output_function()`` result with ``names`` and ``units``)."""
    units = dict(getattr(eom, "units", {}) or {})
    channels = None
    if model is not eom and callable(getattr(model, "output_function", None)):
        channels = model.output_function()
    names, values = getattr(channels, "names", None), getattr(channels, "units", None)
    if names is not None and values is not None:
        units.update({n: u for n, u in zip(names, values) if n in output_names})
    return units


def _index(names: tuple[str, ...], name: str, what: str) -> int:
    try:
        return names.index(name)
    except ValueError:
        raise KeyError(f"no {what} named {name!r}; the {what}s are {list(names)}.") from None
