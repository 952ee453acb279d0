"""Running a closed loop's generated body over a chunk of controller samples.

:func:`sample_loop` gives, for a body ``(z, U, p, h) -> (z_next, aux)`` (:mod:`.closed_loop`), either one CasADi
``mapaccum`` over the chunk (cheap bodies: :class:`SampleLoop`) or one buffered call per sample (expensive
bodies, e.g. a blade-element turbine: :class:`StepLoop`); both return the carry after the chunk and every
sample's ``aux``. :func:`chunk_length` sizes the chunks for progress reports and Ctrl-C.
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np

from .base import prepared, run_buffered
from .monitor import CHUNK_WALL_S

__all__ = ["sample_loop", "chunk_length", "SampleLoop", "StepLoop"]


def chunk_length(remaining: int, per_sample: float) -> int:
    """All remaining samples if they take about a chunk's time, else a power of two (16..4096) of them."""
    fit = CHUNK_WALL_S / max(per_sample, 1e-9)
    if remaining <= 1.5 * fit:
        return remaining
    return int(min(max(16, 2 ** int(math.log2(max(fit, 1.0)))), 4096, remaining))


def sample_loop(owner, body: ca.Function, n: int, stepwise: bool = False):
    """The loop over ``n`` samples: one ``mapaccum`` (cheap bodies), or the body called sample by sample."""
    if stepwise:
        return prepared(owner, ("closed-loop steps", id(body), n), lambda: StepLoop(body, n))[0]
    return prepared(owner, ("closed-loop samples", id(body), n), lambda: SampleLoop(body, n))[0]


class SampleLoop:
    """``mapaccum`` of the closed-loop body over n samples, each with its own sub-step length h."""

    def __init__(self, body: ca.Function, n: int) -> None:
        self.n = n
        self.body = body
        loop = body.mapaccum(f"{body.name()}_loop{n}", n, [0], [0])
        z, U = ca.MX.sym("z", body.size1_in(0)), ca.MX.sym("U", body.size1_in(1), body.size2_in(1) * n)
        p, H = ca.MX.sym("p", body.size1_in(2)), ca.MX.sym("H", body.size1_in(3), n)
        self.loop = ca.Function(f"{body.name()}_loop{n}", [z, U, p, H], loop(z, U, ca.repmat(p, 1, n), H))

    def run(self, z0, U, p, H):
        args = [np.ascontiguousarray(z0, dtype=float), np.asfortranarray(U, dtype=float).reshape(-1, order="F"),
                np.ascontiguousarray(p, dtype=float), np.asfortranarray(H, dtype=float).reshape(-1, order="F")]
        return run_buffered(self.loop, args, self.n)


class StepLoop:
    """The body called once per sample through one reused buffer (same arithmetic as :class:`SampleLoop`).

    For an expensive body (a blade-element turbine: ~30-200 µs per sample) the Python call, ~2 µs, is cheaper
    than what a ``mapaccum`` of many samples costs to build (~2 ms per sample in CasADi 3.6, rebuilt for every
    chunk length) and to run (its virtual machine's copies of the carried state and outputs). Each sample's
    ``aux`` is copied into a row of an array kept for the next chunk of the same length (no new pages to fault
    in per chunk); of ``z`` only the last is returned (the loop carries nothing else).
    """

    def __init__(self, body: ca.Function, n: int) -> None:
        self.n, self.body = n, body
        self.args = [np.zeros(body.numel_in(i)) for i in range(4)]
        self.z_next = np.zeros(body.numel_out(0))
        self.aux = np.zeros(body.numel_out(1))
        self.A = np.zeros((n, body.numel_out(1)))              # row k: the aux of sample k (contiguous)
        self.buf, self.trigger = body.buffer()
        for i, a in enumerate(self.args):
            self.buf.set_arg(i, memoryview(a))
        self.buf.set_res(0, memoryview(self.z_next))
        # one output buffer, copied into A's row: pointing the buffer at each row (set_res) costs 10-40 µs per call
        # through CasADi's Python binding, the copy of ~1000 values ~1 µs
        self.buf.set_res(1, memoryview(self.aux))

    def run(self, z0, U, p, H):
        z, u, pa, h = self.args
        n_u3 = u.size
        U = np.asfortranarray(U, dtype=float).reshape(-1, order="F")
        H = np.asarray(H, dtype=float).reshape(h.size, self.n)
        z[:] = z0
        pa[:] = p
        trigger, A, z_next, aux = self.trigger, self.A, self.z_next, self.aux
        for k in range(self.n):
            u[:] = U[k * n_u3:(k + 1) * n_u3]
            h[:] = H[:, k]
            trigger()
            A[k] = aux
            z[:] = z_next
        return z_next.copy()[:, None], A.T
