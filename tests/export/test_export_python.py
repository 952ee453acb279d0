"""eom.export_python: the numpy-only module agrees with the CasADi Functions.

Reference: ``eom.functions`` evaluated by CasADi's virtual machine; the rhs Jacobians by
CasADi's automatic differentiation of ``eom.functions.rhs``. Tolerance 1e-12 relative to
the largest entry (see _models.close). Models: pendulum with an input and damping, double
pendulum (symbolic parameters), a rotating two-mode flexible beam, a 9-link chain (rhs as
an MX Function with a numeric solve), NREL 5 MW turbines (3 DOFs; and 4 DOFs with a
prescribed azimuth, whose mass matrix takes u).
"""

import importlib.util
import re

import numpy as np
import pytest

from mbsym.exceptions import ExportError
from mbsym.export import FUNCTION_NAMES

from . import _models


def load(path):
    spec = importlib.util.spec_from_file_location(f"exported_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


#: The rhs Jacobians of the 9-link chain are ~70k SX instructions (slow to write and import); they go through
#: the same residual-form code as every other model's, so the chain exports the rest only.
NO_JACOBIANS = ("chain9",)
MODELS = {"pendulum": _models.pendulum, "double_pendulum": _models.double_pendulum,
          "beam": _models.flexible_beam, "chain9": _models.chain, "turbine": _models.turbine,
          "turbine_prescribed": lambda: _models.turbine(prescribed=True), "four_bar": _models.four_bar}


@pytest.fixture(scope="module", params=list(MODELS))
def exported(request, tmp_path_factory):
    eom = MODELS[request.param]()
    names = [n for n in FUNCTION_NAMES if request.param not in NO_JACOBIANS or not n.startswith("rhs_jacobian")]
    path = eom.export_python(tmp_path_factory.mktemp("py") / f"{request.param}.py", functions=names)
    return eom, load(path), path, names


def test_every_function_agrees_with_casadi(exported):
    eom, mod, _, names = exported
    for seed in range(3):
        pt = _models.random_point(eom, seed)
        ref = _models.references(eom, pt)
        for name in names:
            got = getattr(mod, name)(*_models.arguments(eom, pt, name))
            want = ref[name]
            if name in ("forcing", "residual", "rhs"):          # documented kinds: vectors are 1-D,
                want = want.reshape(-1)
            elif name in ("kinetic_energy", "potential_energy", "power"):
                assert isinstance(got, float)                    # scalars float, matrices 2-D
                want = float(want.reshape(-1)[0])
            _models.close(got, want, f"{eom.name}.{name} (seed {seed})")


def test_metadata_and_parameter_vector(exported):
    eom, mod = exported[:2]
    assert mod.COORDINATES == eom.coordinates and mod.STATES == eom.states
    assert mod.INPUTS == eom.inputs and mod.PARAMETERS == eom.parameters
    if all(n in eom.defaults for n in eom.parameters):
        np.testing.assert_array_equal(mod.parameter_vector(), eom.parameter_vector())


def test_module_imports_only_numpy_and_math(exported):
    text = exported[2].read_text()
    lines = [ln for ln in text.splitlines() if re.match(r"\s*(import|from)\s", ln)]
    imported = {re.match(r"\s*(?:import|from)\s+([\w]+)", ln).group(1) for ln in lines}
    assert imported == {"math", "numpy"}, imported
    compile(text, "exported", "exec")           # valid Python (also checked by the import)


def test_sx_functions_repeat_casadis_operations_bit_for_bit(tmp_path):
    """Same instruction sequence on IEEE doubles and the same C library: identical numbers."""
    eom = _models.double_pendulum()
    mod = load(eom.export_python(tmp_path / "dp.py"))
    pt = _models.random_point(eom, 7)
    f = eom.functions
    np.testing.assert_array_equal(mod.mass_matrix(pt["q"], pt["p"]), np.array(f.mass_matrix(pt["q"], pt["p"])))
    np.testing.assert_array_equal(mod.forcing(pt["q"], pt["qd"], [], pt["p"]),
                                  np.array(f.forcing(pt["q"], pt["qd"], [], pt["p"])).reshape(-1))


def test_ieee_results_where_python_floats_raise(tmp_path):
    """Zero masses: CasADi's symbolic solve divides by zero (inf/nan); Python floats would raise."""
    eom = _models.double_pendulum()
    mod = load(eom.export_python(tmp_path / "dp.py"))
    x, p = [0.1, 0.2, 0.3, 0.4], [0.0, 0.0, 1.0, 1.0]
    want = np.array(eom.functions.rhs(x, [], p)).reshape(-1)
    got = mod.rhs(x, [], p)
    np.testing.assert_array_equal(np.isfinite(got), np.isfinite(want))
    assert not np.all(np.isfinite(got))


def test_bad_calls_and_bad_exports(tmp_path):
    eom = _models.pendulum()
    mod = load(eom.export_python(tmp_path / "p.py", functions=["rhs", "mass_matrix"]))
    assert not hasattr(mod, "forcing")
    with pytest.raises(ValueError, match="x has 3 entries; expected 2"):
        mod.rhs([0.0, 0.0, 0.0], [0.0], [1.0, 1.0])
    with pytest.raises(KeyError, match="unknown parameters"):
        mod.parameter_vector({"mass": 1.0})
    with pytest.raises(ExportError, match="unknown functions"):
        eom.export_python(tmp_path / "q.py", functions=["jacobian"])
    with pytest.raises(ExportError, match="does not exist"):
        eom.export_python(tmp_path / "missing" / "q.py")
    with pytest.raises(TypeError):
        eom.export_python(tmp_path / "q.py", fast=True)
