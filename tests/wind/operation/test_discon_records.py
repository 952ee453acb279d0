"""What mbsym's DISCON loop gives a library: every swap record the plant measures, as OpenFAST's ServoDyn does.

ServoDyn fills record 23 (measured generator torque) and 53 (tower-top fore-aft acceleration) for every library;
ROSCO reads them in some modes and the exported NMPC always (its state and its EKF). Before, ``mbsym simulate
--controller discon`` on a land rotor-effective plant gave the library only the five baseline channels: records 23
and 53 stayed zero, and the exported NMPC, reading a zero torque, ran the built-in NREL 5 MW down to 7.7 rpm in a
14 m/s Kaimal wind (the end-to-end case: tests/wind/control/test_nmpc_export.py, slow).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from mbsym.wind.control import DisconController


class _Probe(DisconController):
    """A stand-in library that records the channels it is wired to (no shared library loaded)."""

    def __init__(self) -> None:             # noqa: D107 - deliberately not DisconController's
        self.dt, self.seen = 0.01, None

    def callable(self, measured, commands):
        self.seen = tuple(measured)
        return lambda t, y: np.zeros(len(commands))


@pytest.fixture(scope="module")
def land():
    from mbsym.wind.operation.deck import builtin_deck

    deck = builtin_deck()
    return deck, deck.model()


def test_the_cli_wires_a_library_to_every_record_a_land_plant_measures(land):
    from mbsym.cli.operate import _for_plant

    deck, model = land
    probe = _Probe()
    ctrl = _for_plant(object(), probe, model, "discon", SimpleNamespace(discon_input=None), deck)
    assert {"GenTq", "YawBrTAxp"} <= set(probe.seen) and tuple(ctrl.measurements) == probe.seen
    assert set(probe.seen) <= set(model.measurement_dynamics().output_names)


def test_a_sweep_worker_names_the_channels(land):
    from mbsym.exceptions import OptionError
    from mbsym.wind.operation.controllers import discon_in_loop

    _, model = land
    probe = _Probe()
    discon_in_loop(probe, measurements=model.measurement_dynamics().output_names)
    assert probe.seen == tuple(model.measurement_dynamics().output_names) and "GenTq" in probe.seen
    with pytest.raises(OptionError, match="no swap record for \\['TTDspFA'\\]"):
        discon_in_loop(_Probe(), measurements=["GenSpeed", "TTDspFA"])
