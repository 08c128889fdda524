"""Series data shipped with the package and the fast evaluators that use them.

The coefficients come from ``src/skydome/data/astro_series.npz``, written by
``tools/build_astro_tables.py`` (VSOP87D truncated, IAU 1980 nutation of Meeus table
22.A); the Moon's series (ELP/MPP02) are in ``moon_elpmpp02.npz``, summed by
:mod:`skydome.astro.moon` with the phasors and the Chebyshev recurrence here. Nothing here
is public API.

Evaluating a trigonometric series costs one cosine per term and per time, which
dominates the cost of the astronomy layer. For long, dense arrays of times the
smooth series are therefore sampled at Chebyshev nodes on fixed-length segments
of the time axis and interpolated (:func:`smooth`), as planetary ephemerides do;
the interpolation error is kept below 1e-4 arcsec (the float64 resolution of a
Julian Date, 40 us, is the floor) and is checked in the tests.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from importlib import resources

import numpy as np

from skydome.physics.constants import J2000_JD

J2000 = J2000_JD  # JD of the epoch J2000.0 (TT)
DAYS_PER_MILLENNIUM = 365250.0


@functools.lru_cache(maxsize=1)
def tables() -> dict[str, np.ndarray]:
    """Load the packaged coefficient tables once."""
    path = resources.files("skydome").joinpath("data/astro_series.npz")
    with path.open("rb") as fh, np.load(fh) as npz:
        return {k: npz[k] for k in npz.files}


class VSOPSeries:
    """One planet's truncated VSOP87D series, grouped by (coordinate, power of tau)."""

    def __init__(self, planet: str) -> None:
        t = tables()
        a = t[f"vsop_{planet}_A"] * 1e-8  # native unit: 1e-8 rad or 1e-8 au
        b = t[f"vsop_{planet}_B"]
        c = t[f"vsop_{planet}_C"]
        coord = t[f"vsop_{planet}_coord"].astype(int)
        power = t[f"vsop_{planet}_power"].astype(int)
        order = np.lexsort((power, coord))
        self.a, self.b, self.c = a[order], b[order], c[order]
        self.coord, self.power = coord[order], power[order]
        self.max_power = int(self.power.max())
        # distinct frequencies; the phasor of each from few cosines (frequency_plan)
        freqs, self.term_freq = np.unique(self.c, return_inverse=True)
        self.plan, self.c_base = frequency_plan(freqs)
        rows = self.coord * (self.max_power + 1) + self.power
        self.lbr_sums = PhasorSums(
            self.plan, self.term_freq, self.a * np.exp(1j * self.b), rows, 3 * (self.max_power + 1)
        )
        self._rate_sums: dict[bytes, PhasorSums] = {}

    def _sums(self, tau: np.ndarray, sums: PhasorSums) -> np.ndarray:
        return sums(lambda blk: self.c_base[:, None] * tau[None, blk], tau.size)

    def lbr(self, jd_tt: np.ndarray) -> np.ndarray:
        """Heliocentric L, B (rad) and R (au), ecliptic and equinox of date; shape (3, N).

        Meeus eq. 32.1-32.2: X = sum_alpha tau^alpha * sum A cos(B + C tau), with
        A cos(B + C tau) = Re(A exp(iB) exp(iC tau)) and the phasors exp(iC tau) of the
        distinct frequencies from :func:`frequency_plan`.
        """
        tau = (np.asarray(jd_tt, dtype=float).ravel() - J2000) / DAYS_PER_MILLENNIUM
        sums = self._sums(tau, self.lbr_sums).reshape(3, self.max_power + 1, tau.size)
        out = sums[:, self.max_power].copy()
        for p in range(self.max_power - 1, -1, -1):  # Horner in tau
            out = out * tau + sums[:, p]
        return out

    def lbr_rates(
        self, jd_tt: np.ndarray, keep_rates: np.ndarray, keep_values: np.ndarray | None = None
    ) -> np.ndarray:
        """L, B, R from the terms ``keep_values`` (default ``keep_rates``) and their rates per
        day from the terms ``keep_rates``; (6, N). One set of phasors serves both.

        d/dtau [tau^a A cos(B + C tau)] = a tau^(a-1) A cos(.) - tau^a A C sin(.), and
        -A C sin(B + C tau) = Re(i A C exp(iB) exp(iC tau)). The rate's first part takes
        the values' sums, so a term kept for the rates must be kept for the values too.
        """
        keep_values = keep_rates if keep_values is None else keep_values
        key = keep_rates.tobytes() + keep_values.tobytes()
        if key not in self._rate_sums:
            if np.any(keep_rates & ~keep_values):
                raise ValueError("every term kept for the rates must be kept for the values")
            n_rows = 3 * (self.max_power + 1)
            rows = self.coord * (self.max_power + 1) + self.power
            w = self.a * np.exp(1j * self.b)
            kv, kr = keep_values, keep_rates
            self._rate_sums[key] = PhasorSums(
                self.plan,
                np.concatenate([self.term_freq[kv], self.term_freq[kr]]),
                np.concatenate([w[kv], 1j * self.c[kr] * w[kr]]),
                np.concatenate([rows[kv], n_rows + rows[kr]]),
                2 * n_rows,
            )
        tau = (np.asarray(jd_tt, dtype=float).ravel() - J2000) / DAYS_PER_MILLENNIUM
        both = self._sums(tau, self._rate_sums[key]).reshape(2, 3, self.max_power + 1, -1)
        val, der = both[0], both[1]
        p_max = self.max_power
        out_val = val[:, p_max].copy()
        out_rate = der[:, p_max].copy()
        for p in range(p_max - 1, -1, -1):  # Horner in tau for both polynomials
            out_val = out_val * tau + val[:, p]
            out_rate = out_rate * tau + der[:, p] + (p + 1) * val[:, p + 1]
        return np.concatenate([out_val, out_rate / DAYS_PER_MILLENNIUM])


@functools.cache
def vsop(planet: str) -> VSOPSeries:
    """The cached series of ``planet`` (lower-case English name)."""
    return VSOPSeries(planet)


# --------------------------------------------------------------------------- phasors

# Times per block in the phasor evaluators: the block's phasor table (a few hundred rows of
# complex128) then stays in the processor's cache between the steps that build it.
PHASOR_BLOCK_TIMES = 1024
# Fewer times than this: one argument per output and time instead of products (the
# products' per-call overhead dominates for short arrays).
PHASOR_DIRECT_BELOW = 64


# 2 pi = _TWO_PI_HI + _TWO_PI_LO: the high part has 30 significant bits, so that k times
# it is exact for |k| < 2^23; 2.4492935982947064e-16 = 2 pi - float(2 pi).
_TWO_PI_HI = round(2.0 * np.pi * 2.0**27) / 2.0**27
_TWO_PI_LO = (2.0 * np.pi - _TWO_PI_HI) + 2.4492935982947064e-16


def unit_phasor(angle_rad: np.ndarray, cos_out: np.ndarray, sin_out: np.ndarray) -> None:
    """cos and sin of ``angle_rad`` into ``cos_out`` and ``sin_out`` from one tangent.

    With r = angle - 2 pi round(angle / 2 pi) in [-pi, pi] and t = tan(r / 2):
    cos = (1 - t^2) / (1 + t^2), sin = 2 t / (1 + t^2) (half-angle formulas; t stays
    finite, |t| < 2e16). NumPy's float64 tangent is SIMD-vectorized where its sine and
    cosine are not (NumPy 2.4, x86-64 with AVX-512: 1 ns against 15-20 ns per value), which
    makes this 3-6 times faster than ``np.cos`` + ``np.sin`` (where the tangent is scalar
    too, one transcendental call instead of two should still not be slower; unmeasured).
    The reduction
    uses 2 pi in two parts (Cody & Waite), exact to 1e-20 rad per turn; the formulas add
    a few ulp.
    """
    if angle_rad.size < 256:  # short arrays: fewer calls win over faster ones
        np.cos(angle_rad, out=cos_out)
        np.sin(angle_rad, out=sin_out)
        return
    k = np.rint(angle_rad * (0.5 / np.pi))
    r = k * -_TWO_PI_HI
    r += angle_rad  # exact for |angle| < 5e7 rad
    k *= _TWO_PI_LO
    r -= k
    r *= 0.5
    t = np.tan(r, out=r)
    t2 = t * t
    inv = np.add(t2, 1.0)
    np.reciprocal(inv, out=inv)
    np.subtract(1.0, t2, out=cos_out)
    cos_out *= inv
    np.multiply(t, 2.0, out=sin_out)
    sin_out *= inv


class PhasorPlan:
    """Recipe for the phasors exp(i phi_u(t)) of many series arguments from few cosines.

    Every argument phi_u is either one of the ``n_base`` base angles supplied at run time
    (its phasor costs one cosine and one sine) or the sum of two arguments already
    computed (one complex multiplication, exp(i(a + b)) = exp(ia) exp(ib)), optionally
    with the second conjugated (exp(i(a - b))). Slots ``0..n_base-1`` hold the base
    phasors; ``steps`` append one slot each; ``outputs`` lists the slots returned.
    """

    def __init__(self, n_base: int, steps: list[tuple[int, int, bool]], outputs: list[int]):
        self.n_base = n_base
        self.steps = steps  # (slot a, slot b, conjugate b); slot -1 is the constant 1
        self.outputs = np.asarray(outputs, dtype=np.intp)
        self.n_slots = n_base + len(steps)
        # each slot's argument as an integer combination of the base angles (last row: 0)
        combos = np.zeros((self.n_slots + 1, n_base))
        combos[:n_base] = np.eye(n_base)
        for k, (a, b, conj) in enumerate(steps, start=n_base):
            combos[k] = combos[a] - combos[b] if conj else combos[a] + combos[b]
        self.output_combos = combos[self.outputs]

    def run(self, base_angles_rad: np.ndarray) -> np.ndarray:
        """Phasors (n_outputs, n) complex of the base angles ``(n_base, n)`` (rad).

        Below ``PHASOR_DIRECT_BELOW`` times the multiplications cost more in call overhead
        than they save, and each output's argument is formed and evaluated directly.
        """
        n = base_angles_rad.shape[1]
        if n < PHASOR_DIRECT_BELOW:
            args = np.einsum("uk,kn->un", self.output_combos, base_angles_rad)
            z = np.empty(args.shape, dtype=complex)
            unit_phasor(args, z.real, z.imag)
            return z
        ws = np.empty((self.n_slots + 1, n), dtype=complex)
        ws[-1] = 1.0  # slot -1: exp(i 0)
        unit_phasor(base_angles_rad, ws.real[: self.n_base], ws.imag[: self.n_base])
        for k, (a, b, conj) in enumerate(self.steps, start=self.n_base):
            if conj:
                np.multiply(ws[a], np.conj(ws[b]), out=ws[k])
            else:
                np.multiply(ws[a], ws[b], out=ws[k])
        return ws[self.outputs]


def integer_combination_plan(multipliers: np.ndarray) -> PhasorPlan:
    """Plan for exp(i sum_j k_tj X_j) of the integer rows ``multipliers`` (T, K).

    The base angles are the K fundamental arguments X_j. Powers exp(i m X_j) come from
    repeated multiplication, and each row is built factor by factor, sharing the partial
    products of rows with the same leading multipliers. Output u belongs to row u.
    """
    mult = np.asarray(multipliers, dtype=int)
    n_base = mult.shape[1]
    steps: list[tuple[int, int, bool]] = []
    power_slot: dict[tuple[int, int], int] = {(j, 1): j for j in range(n_base)}

    def power(j: int, m: int) -> int:  # slot of exp(i m X_j), m >= 1
        if (j, m) not in power_slot:
            steps.append((power(j, m - 1), j, False))
            power_slot[(j, m)] = n_base + len(steps) - 1
        return power_slot[(j, m)]

    prefix_slot: dict[tuple[int, ...], int] = {}
    outputs = []
    for row in mult:
        slot = -1  # the constant 1
        key: tuple[int, ...] = ()
        for j, m in enumerate(row):
            key = key + (int(m),)
            if m == 0:
                continue
            if key not in prefix_slot:
                p = power(j, abs(int(m)))
                if slot == -1 and m > 0:
                    prefix_slot[key] = p
                else:
                    steps.append((slot, p, bool(m < 0)))
                    prefix_slot[key] = n_base + len(steps) - 1
            slot = prefix_slot[key]
        outputs.append(slot)
    return PhasorPlan(n_base, steps, outputs)


def frequency_plan(freqs: np.ndarray, tol: float = 1e-9) -> tuple[PhasorPlan, np.ndarray]:
    """Plan for exp(i C_u tau) of the frequencies ``freqs`` (U,), and the base frequencies.

    Frequencies are visited in increasing order; one equal (to ``tol``, in the unit of
    ``freqs``, so that the phase differs by at most tol * |tau|) to the sum of two already
    available frequencies, or to an integer multiple (3 to 8) of one, is built by
    multiplication; the others are base frequencies (one cosine and one sine each). Zero
    frequencies give the constant 1. The returned base frequencies ``c_base`` give the
    base angles ``c_base[:, None] * tau``.
    """
    freqs = np.asarray(freqs, dtype=float)
    # nodes: ("base", index among the bases) or ("mul", node a, node b); -1 is the constant
    nodes: list[tuple] = []
    base: list[float] = []
    avail_f: list[float] = []  # frequencies computed so far and their nodes
    avail_n: list[int] = []
    out_node = np.full(freqs.size, -1)

    def mul(a: int, b: int) -> int:
        nodes.append(("mul", a, b))
        return len(nodes) - 1

    for u in np.argsort(freqs, kind="stable"):
        x = float(freqs[u])
        if x == 0.0:
            continue
        f = np.asarray(avail_f)
        node = None
        for i in range(f.size):  # x = f_i + f_k
            k = np.flatnonzero(np.abs(x - f[i] - f[i:]) <= tol)
            if k.size:
                node = mul(avail_n[i], avail_n[i + int(k[0])])
                break
        if node is None:  # x = k f_i: f_i^k by repeated multiplication
            for i in range(f.size):
                k = round(x / f[i])
                if 3 <= k <= 8 and abs(x - k * f[i]) <= tol:
                    node = avail_n[i]
                    for _ in range(k - 1):
                        node = mul(node, avail_n[i])
                    break
        if node is None:
            nodes.append(("base", len(base)))
            base.append(x)
            node = len(nodes) - 1
        avail_f.append(x)
        avail_n.append(node)
        out_node[u] = node

    # slots: the bases first, then the products in the order they were made
    slot = {-1: -1}
    n_base = len(base)
    steps: list[tuple[int, int, bool]] = []
    for i, nd in enumerate(nodes):
        if nd[0] == "base":
            slot[i] = nd[1]
        else:
            slot[i] = n_base + len(steps)
            steps.append((slot[nd[1]], slot[nd[2]], False))
    plan = PhasorPlan(n_base, steps, [slot[int(n)] for n in out_node])
    return plan, np.asarray(base)


def _prune(plan: PhasorPlan, outputs: np.ndarray) -> tuple[np.ndarray, PhasorPlan]:
    """The base angles (indices) and steps of ``plan`` that ``outputs`` (slots) need, as a
    plan of its own returning those slots in order."""
    needed = np.zeros(plan.n_slots, dtype=bool)
    stack = [int(o) for o in outputs if o >= 0]
    while stack:
        k = stack.pop()
        if needed[k]:
            continue
        needed[k] = True
        if k >= plan.n_base:
            a, b, _ = plan.steps[k - plan.n_base]
            stack.extend(x for x in (a, b) if x >= 0)
    base_index = np.flatnonzero(needed[: plan.n_base])
    new_slot = np.full(plan.n_slots, -1)
    new_slot[base_index] = np.arange(base_index.size)
    steps = []
    for k in np.flatnonzero(needed[plan.n_base :]) + plan.n_base:
        a, b, conj = plan.steps[k - plan.n_base]
        new_slot[k] = base_index.size + len(steps)
        steps.append((int(new_slot[a]) if a >= 0 else -1, int(new_slot[b]) if b >= 0 else -1, conj))
    outs = [int(new_slot[o]) if o >= 0 else -1 for o in outputs]
    return base_index, PhasorPlan(base_index.size, steps, outs)


class PhasorSums:
    """Sums of series terms Re(w_t exp(i phi_t)) into rows, from a :class:`PhasorPlan`.

    ``term_output`` (T,): the plan output holding each term's phasor; ``term_weight`` (T,)
    complex: w_t (A cos(phi + B) = Re(A exp(iB) exp(i phi)), A sin(phi) =
    Re(-iA exp(i phi))); ``term_row`` (T,): the row the term adds to, of ``n_rows``.
    Times are processed in blocks of ``PHASOR_BLOCK_TIMES``; no BLAS call is made (its
    threads stall on a busy machine for products of this size).
    """

    def __init__(
        self,
        plan: PhasorPlan,
        term_output: np.ndarray,
        term_weight: np.ndarray,
        term_row: np.ndarray,
        n_rows: int,
    ) -> None:
        term_weight = np.asarray(term_weight, dtype=complex)
        nonzero = term_weight != 0.0  # e.g. the few time-dependent nutation coefficients
        term_output = np.asarray(term_output)[nonzero]
        term_weight, term_row = term_weight[nonzero], np.asarray(term_row)[nonzero]
        order = np.argsort(term_row, kind="stable")
        self.plan = plan
        self.slot = plan.outputs[term_output[order]]
        self.weight = term_weight[order][:, None]
        rows = term_row[order]
        used, starts = np.unique(rows, return_index=True)
        stops = np.append(starts[1:], rows.size)
        self.rows, self.starts = used, starts
        self.segments = [
            (int(r), int(a), int(b)) for r, a, b in zip(used, starts, stops, strict=True)
        ]
        self.n_rows = n_rows
        self.base_index, self.term_plan = _prune(plan, self.slot)

    def __call__(self, base_angles: Callable[[slice], np.ndarray], n_times: int) -> np.ndarray:
        """Row sums (n_rows, n_times); ``base_angles(block)`` gives the plan's base angles
        (rad) of the times in ``block``."""
        out = np.zeros((self.n_rows, n_times))
        for start in range(0, n_times, PHASOR_BLOCK_TIMES):
            block = slice(start, min(start + PHASOR_BLOCK_TIMES, n_times))
            terms = self.term_plan.run(base_angles(block)[self.base_index])  # (T, nb)
            terms *= self.weight
            real = np.ascontiguousarray(terms.real)
            if real.shape[1] < PHASOR_DIRECT_BELOW:  # one call for short blocks
                out[self.rows, block] = np.add.reduceat(real, self.starts, axis=0)
                continue
            for row, a, b in self.segments:  # faster than reduceat on long blocks
                np.add.reduce(real[a:b], axis=0, out=out[row, block])
        return out


# --------------------------------------------------------------------------- interpolation


@functools.cache
def cheb_matrix(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev nodes on [-1, 1] and the matrix mapping node values to coefficients."""
    k = np.arange(n)
    theta = np.pi * (k + 0.5) / n
    nodes = np.cos(theta)
    mat = (2.0 / n) * np.cos(np.outer(k, theta))  # c_j = 2/n sum_k f(x_k) cos(j theta_k)
    mat[0] *= 0.5
    return nodes, mat


# The memory one function's segments may hold (SegmentMemo): a span of 150 years of the
# Moon's 8-day segments is 3 MB, of the nutation's 16-day ones 1 MB; 13 functions keep memos.
MEMO_MAX_BYTES = 16 << 20


class SegmentMemo:
    """The Chebyshev coefficients of one function's segments of time, kept once computed.

    A segment ``i`` of a grid of ``step_days`` is ``[J2000 + i step, J2000 + (i + 1) step)``;
    its coefficients depend on nothing else, so a later call on any times in it (not only
    the same times) reuses them, as a precomputed ephemeris would. The memo is a contiguous
    span of segments from ``first`` (coefficients ``coef`` (n, C, S), ``held`` (S,) marks
    those computed), so that a time's segment is found by a subtraction. A span that would
    pass ``max_bytes`` starts again from the call's segments; one call's span beyond it is
    not kept. The three are replaced together (one attribute), so that a call in another
    thread reads either the old span or the new one.
    """

    def __init__(self, max_bytes: int = MEMO_MAX_BYTES) -> None:
        self.max_bytes = max_bytes
        self._span: tuple[float, np.ndarray, np.ndarray] | None = None  # first, coef, held

    @property
    def first(self) -> float:
        return 0.0 if self._span is None else self._span[0]

    @property
    def coef(self) -> np.ndarray | None:
        return None if self._span is None else self._span[1]

    @property
    def held(self) -> np.ndarray:
        return np.zeros(0, dtype=bool) if self._span is None else self._span[2]

    @staticmethod
    def _positions(span, seg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Each segment's position in ``span`` (clipped into it) and whether it is held."""
        if span is None:
            return np.zeros(seg.size, dtype=np.intp), np.zeros(seg.size, dtype=bool)
        first, _, held = span
        offset = seg - first
        pos = np.clip(offset, 0, held.size - 1).astype(np.intp)
        return pos, held[pos] & (pos == offset)  # the clipped ones are outside the span

    def locate(self, seg: np.ndarray) -> tuple:
        """Where the segments ``seg`` (N,) are in the span held now: (the span, each one's
        position in it, whether it is held), for :meth:`missing` and :meth:`coefficients`."""
        span = self._span
        return (span, *self._positions(span, seg))

    def missing(self, seg: np.ndarray, located: tuple | None = None) -> np.ndarray:
        """The distinct segments of ``seg`` (N,) not held, sorted (``located``: :meth:`locate`'s
        answer for ``seg``, if the caller has it)."""
        held = (located or self.locate(seg))[2]
        return np.empty(0) if held.all() else np.unique(seg[~held])

    def coefficients(
        self,
        seg: np.ndarray,
        compute: Callable[[np.ndarray], np.ndarray],
        located: tuple | None = None,
    ) -> tuple[np.ndarray, np.ndarray]:
        """Coefficients (n, C, M) and each time's position in them for the segments ``seg``
        (N,); ``compute(segments)`` gives those (n, C, m) of the distinct segments (m,)
        not held yet; ``located`` as for :meth:`missing`."""
        span, pos, held = located or self.locate(seg)
        if span is not None and held.all():
            return span[1], pos
        if span is not None:
            first, coef_old, held_old = span
            lo = min(seg.min(), first)
            hi = max(seg.max(), first + held_old.size - 1)
            if (hi - lo + 1) * coef_old[:, :, 0].nbytes > self.max_bytes:
                span, held = None, np.zeros(seg.size, dtype=bool)  # start again: every segment
        new = np.unique(seg[~held])
        new_coef = compute(new)
        lo, hi = new[0], new[-1]
        if span is not None:
            lo, hi = min(lo, first), max(hi, first + held_old.size - 1)
        size = int(hi - lo) + 1
        if size * (new_coef.nbytes // new.size) > self.max_bytes:  # this call alone: not kept
            return new_coef, np.searchsorted(new, seg)  # (span is None: new holds every one)
        coef = np.zeros(new_coef.shape[:2] + (size,))
        held_span = np.zeros(size, dtype=bool)
        if span is not None:
            start = int(first - lo)
            coef[:, :, start : start + held_old.size] = coef_old
            held_span[start : start + held_old.size] = held_old
        at = (new - lo).astype(np.intp)
        coef[:, :, at] = new_coef
        held_span[at] = True
        span = (lo, coef, held_span)
        self._span = span
        return coef, self._positions(span, seg)[0]


@functools.cache
def segment_memo(name: str) -> SegmentMemo:
    """The process's memo of the segments of the function called ``name``."""
    return SegmentMemo()


def smooth(
    func: Callable[[np.ndarray], np.ndarray],
    jd: np.ndarray,
    step_days: float,
    degree: int,
    step_cost: float = 0.02,
    memo: SegmentMemo | None = None,
) -> np.ndarray:
    """Evaluate ``func(jd) -> (C, N)`` directly or by piecewise Chebyshev interpolation.

    The time axis is cut into segments ``[J2000 + i*step, J2000 + (i+1)*step)``; ``func``
    is evaluated at ``degree + 1`` Chebyshev nodes of every segment that holds a requested
    time and is not in ``memo`` yet (a :class:`SegmentMemo` of this function and grid), and
    the interpolant is evaluated at the times. Whichever is cheaper is done: M new segments
    cost M (degree + 1) evaluations of ``func`` plus N (degree + 1) Clenshaw steps, against
    N direct evaluations; ``step_cost`` is one Clenshaw step at one time (all components)
    as a fraction of one direct evaluation (measured 0.005 for the Earth's 191 terms and
    0.007 for the nutation's 63; 0.02 leaves a margin for the interpolation's fixed costs).
    Arrays shorter than 12 (degree + 1) are always direct. Both ways agree to far below
    the models' errors (1e-4", tested), so which one a call takes, which can depend on the
    segments an earlier call left in ``memo``, does not matter.
    """
    jd = np.asarray(jd, dtype=float).ravel()
    n = degree + 1
    if jd.size < 12 * n:
        return func(jd)
    memo = SegmentMemo() if memo is None else memo
    seg = np.floor((jd - J2000) / step_days)
    located = memo.locate(seg)
    if memo.missing(seg, located).size * n + jd.size * n * step_cost >= jd.size:
        return func(jd)

    def compute(new: np.ndarray) -> np.ndarray:
        nodes, mat = cheb_matrix(n)
        t_nodes = J2000 + (new[:, None] + 0.5 * (nodes[None, :] + 1.0)) * step_days
        vals = func(t_nodes.ravel())  # (C, M*n)
        coef = vals.reshape(vals.shape[0], new.size, n) @ mat.T  # (C, M, n)
        return np.moveaxis(coef, 2, 0)  # (n, C, M)

    coef, pos = memo.coefficients(seg, compute, located)
    x = 2.0 * ((jd - J2000) / step_days - seg) - 1.0
    return clenshaw(coef, pos, x)


def clenshaw(coef_j: np.ndarray, segment: np.ndarray, x: np.ndarray) -> np.ndarray:
    """sum_j c_j T_j(x) for the coefficients ``coef_j`` (n, C, M) of M segments and C
    components, at the points ``x`` (N,) in [-1, 1] of the segments ``segment`` (N,);
    shape (C, N). Clenshaw's recurrence, gathering one coefficient plane at a time."""
    n = coef_j.shape[0]
    x2 = 2.0 * x
    b1 = np.take(coef_j[n - 1], segment, axis=1)
    b2 = np.zeros_like(b1)
    for j in range(n - 2, 0, -1):
        b1, b2 = x2 * b1 - b2 + np.take(coef_j[j], segment, axis=1), b1
    return 0.5 * x2 * b1 - b2 + np.take(coef_j[0], segment, axis=1)
