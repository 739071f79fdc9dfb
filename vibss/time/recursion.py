"""The modal recursion ``x[i+1] = E[hk[i]] x[i] + d[i]`` for every mode and every step at once.

Modes are independent blocks (``b = 1`` complex modes, ``b = 2`` real 2x2 blocks), so the work is
``steps x modes`` and what costs is Python: a loop over steps runs 10,000 times. :func:`scan` cuts
the steps into ``B`` blocks of ``L`` (``L ~ sqrt(steps)``) and runs three short loops instead:

1. every block from a zero state at once (``L`` iterations over arrays of ``B x modes``), its
   outputs ``Y x`` taken as it goes (a small GEMM per iteration, so the states are never stored);
2. the state at each block's start, block after block (``B`` iterations over the modes), with the
   block's transition ``E^L`` (a product of the step matrices where a block holds other steps);
3. the start state carried into the block, ``Y E^(j+1) x_start``, added to the outputs by one GEMM
   against the ``L`` powers ``Y E^(j+1)``; blocks with other steps (inserted breakpoints) carry
   their start state step by step instead.

The arithmetic is the recursion's own (products of the same ``E``), regrouped: the round-off is of
the order of ``L eps`` per block, the same as the step-by-step loop over ``L`` steps.

With one step length and the forcing in factors, step 1 is two GEMMs (:func:`_factored_blocks`):
the blocks' outputs from zero through the (Lb p, Lb c) block-Toeplitz matrix of the step's impulse
response, and their end states through the stacked ``E^k F``; the per-step Python loop is gone and
the whole scan is three GEMMs and a loop over the ``B`` blocks.

The forcing of a step is a fixed map of a few input samples (a first-order hold of ``m`` inputs:
``d[i] = V[i] F`` with ``V`` (L, c), ``c`` ~ 2 m): :class:`LowRank` passes it so, and step 1 forms
each iteration's ``B`` forcings by one small GEMM where they are used, instead of reading an
``L x modes`` array written beforehand (at 600 DOF and 10,000 steps, 96 MB written and read back).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["scan", "LowRank", "RealProduct"]


@dataclass(frozen=True)
class LowRank:
    """The forcing of every step as ``d[i] = V[i] @ F``: V (L, c) real, F (c, b, nb) real or complex."""

    V: np.ndarray
    F: np.ndarray

    def __len__(self) -> int:
        return int(self.V.shape[0])

    def rows(self, V: np.ndarray) -> np.ndarray:
        """``V @ F`` for rows ``V`` (..., c): (..., b, nb), as one real GEMM when F is complex."""
        c, b, nb = self.F.shape
        if np.iscomplexobj(self.F):
            Fr = np.ascontiguousarray(self.F).reshape(c, b * nb).view(float)
            return np.asarray(np.ascontiguousarray(V @ Fr).view(complex)).reshape(V.shape[:-1] + (b, nb))
        return np.asarray(V @ self.F.reshape(c, b * nb)).reshape(V.shape[:-1] + (b, nb))


def _apply(E: np.ndarray, x: np.ndarray, d: np.ndarray, out: np.ndarray) -> None:
    """``out = E x + d`` for component-major states: E (..., b, b, nb), x, d, out (..., b, nb)."""
    b = x.shape[-2]
    for i in range(b):
        o = out[..., i, :]
        np.multiply(E[..., i, 0, :], x[..., 0, :], out=o)
        for j in range(1, b):
            o += E[..., i, j, :] * x[..., j, :]
        o += d[..., i, :]


def _matmul(P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Per-mode products of component-major blocks: P (..., b, b, nb) times Q (..., b, k, nb)."""
    if P.shape[-3] == 1:
        return P * Q
    return np.einsum("...ikm,...kjm->...ijm", P, Q)


class RealProduct:
    """``Re(S @ Y.T)`` for rows S (r, N) and a fixed Y (p, N): one real GEMM even when S is complex."""

    def __init__(self, Y: np.ndarray, dtype: np.dtype) -> None:
        self.cplx = np.issubdtype(dtype, np.complexfloating)
        if self.cplx:
            Yc = np.asarray(Y, complex)
            self.op = np.empty((2 * Yc.shape[1], Yc.shape[0]))       # re, im interleaved rows
            self.op[0::2], self.op[1::2] = Yc.real.T, -Yc.imag.T
        else:
            self.op = np.ascontiguousarray(np.real(Y).T)

    def __call__(self, S: np.ndarray) -> np.ndarray:
        if self.cplx:
            S = np.ascontiguousarray(S, complex).view(float)
        return S @ self.op


def scan(E: np.ndarray, hk: np.ndarray, x0: np.ndarray, drive: "np.ndarray | LowRank",
         Y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Outputs ``Re(Y x[i+1])`` of ``x[i+1] = E[hk[i]] x[i] + drive[i]``, vectorised over steps.

    Parameters
    ----------
    E : (nh, nb, b, b) ndarray
        Transition matrix of each distinct step (``b`` = 1 or 2).
    hk : (L,) int ndarray
        Step key (index into ``E``) of each step.
    x0 : (b, nb) ndarray
        State before the first step (component-major).
    drive : (L, b, nb) ndarray or LowRank
        Forced part of each step (or its factors ``V (L, c)``, ``F (c, b, nb)``).
    Y : (p, b, nb) ndarray
        Output map (complex for complex modes: the real part of ``Y x`` is taken).

    Returns
    -------
    y : (L, p) ndarray
        Outputs after each step.
    x : (b, nb) ndarray
        State after the last step.

    Examples
    --------
    >>> E = np.full((1, 1, 1, 1), 0.5)
    >>> y, x = scan(E, np.zeros(4, int), np.ones((1, 1)), np.zeros((4, 1, 1)), np.ones((1, 1, 1)))
    >>> y[:, 0].tolist()
    [0.5, 0.25, 0.125, 0.0625]
    """
    L = len(hk)
    b, nb = x0.shape
    dtype = np.result_type(E, x0, drive.F if isinstance(drive, LowRank) else drive)
    Yf = Y.reshape(Y.shape[0], b * nb)
    y = np.zeros((L, Y.shape[0]))
    x = x0.astype(dtype)
    Lb = int(min(max(np.sqrt(L), 1), 128))
    B = L // Lb

    def part(lo: int, nblk: int, lb: int) -> "np.ndarray | LowRank":
        if isinstance(drive, LowRank):
            return LowRank(drive.V[lo:lo + nblk * lb].reshape(nblk, lb, -1), drive.F)
        return drive[lo:lo + nblk * lb].reshape(nblk, lb, b, nb)

    if B:
        n = B * Lb
        y[:n], x = _blocks(E, hk[:n].reshape(B, Lb), x, part(0, B, Lb), Yf, dtype)
    if L > B * Lb:
        r = L - B * Lb
        y[B * Lb:], x = _blocks(E, hk[B * Lb:].reshape(1, r), x, part(B * Lb, 1, r), Yf, dtype)
    return y, x


def _blocks(E: np.ndarray, H: np.ndarray, x0: np.ndarray, D: "np.ndarray | LowRank", Yf: np.ndarray,
            dtype: np.dtype) -> tuple[np.ndarray, np.ndarray]:
    """:func:`scan` on ``B`` blocks of ``Lb`` steps: H (B, Lb) keys, D (B, Lb, b, nb) drives (or their
    factors: ``V`` (B, Lb, c))."""
    B, Lb = H.shape
    b, nb = x0.shape
    drive = (lambda j: D.rows(D.V[:, j])) if isinstance(D, LowRank) else (lambda j: D[:, j])
    p = Yf.shape[0]
    key0 = int(np.bincount(H.ravel()).argmax())
    regular = np.all(H == key0, axis=1)
    irr = np.flatnonzero(~regular)
    same = np.all(H == H[:1], axis=0)             # step j has one key in every block
    Et = np.ascontiguousarray(np.moveaxis(E, 1, -1))   # (nh, b, b, nb): components then modes
    # powers E^(j+1) of the common step, and the outputs they carry: W[j] = Y E^(j+1)
    Ek = Et[key0]
    pw = np.empty((Lb, b, b, nb), dtype)
    if b == 1:
        pw[:, 0, 0] = np.cumprod(np.broadcast_to(Ek[0, 0], (Lb, nb)), axis=0)
        W = (Yf[None, :, :] * pw[:, 0, 0][:, None, :]).reshape(Lb * p, nb)
    else:
        pw[0] = Ek
        for j in range(1, Lb):
            pw[j] = _matmul(Ek, pw[j - 1])
        W = np.einsum("pim,jicm->jpcm", Yf.reshape(p, b, nb), pw).reshape(Lb * p, b * nb)
    Pirr = np.broadcast_to(np.eye(b, dtype=dtype)[:, :, None], (len(irr), b, b, nb)).copy()
    if isinstance(D, LowRank) and not irr.size and _factored_fits(Lb, p, D.F.shape[0], b * nb):
        # 1. every block from zero, as GEMMs: the outputs through the block's impulse response
        y, last = _factored_blocks(D, pw, Yf.reshape(p, b, nb), dtype)
    else:
        # 1. every block from zero; its outputs as it goes (the states are not kept)
        out = RealProduct(Yf, dtype)
        y = np.empty((B, Lb, p))
        x = np.zeros((B, b, nb), dtype)
        for j in range(Lb):
            Ej = Et[H[0, j]] if same[j] else Et[H[:, j]]
            Dj = drive(j)
            if b == 1:
                x[:, 0] *= Ej[..., 0, 0, :]
                x[:, 0] += Dj[:, 0]
            else:
                xn = np.empty_like(x)
                _apply(Ej, x, Dj, xn)
                x = xn
            y[:, j] = out(x.reshape(B, b * nb))
            if irr.size:
                Pirr = _matmul(Ej if same[j] else Ej[irr], Pirr)
        last = x
    # 2. block start states
    C = np.empty((B, b, nb), dtype)
    x = x0
    where = {int(k): i for i, k in enumerate(irr)}
    for k in range(B):
        C[k] = x
        P = pw[-1] if regular[k] else Pirr[where[k]]
        x = (P[0, 0] * x if b == 1 else np.einsum("ijm,jm->im", P, x)) + last[k]
    # 3. outputs
    reg = np.flatnonzero(regular)
    if reg.size:
        corr = RealProduct(W, dtype)(C[reg].reshape(reg.size, b * nb))          # (nreg, Lb p)
        y[reg] += corr.reshape(reg.size, Lb, p)
    if irr.size:
        out = RealProduct(Yf, dtype)
        xh = C[irr]
        for j in range(Lb):
            Ej = Et[H[0, j]] if same[j] else Et[H[irr, j]]
            xn = np.empty_like(xh)
            _apply(Ej, xh, np.zeros_like(xh), xn)
            xh = xn
            y[irr, j] += out(xh.reshape(irr.size, b * nb))
    return y.reshape(B * Lb, p), x


FACTORED_MAX = 2**23
"""Largest number of entries of either array :func:`_factored_blocks` forms (the (Lb p, Lb c)
Toeplitz matrix, the (Lb c, b nb) stacked powers): 64 MB of floats. Beyond it (many outputs and
inputs on a large model) step 1 loops over the steps with the forcing formed per step."""


def _factored_fits(Lb: int, p: int, c: int, bnb: int) -> bool:
    """Whether the arrays of :func:`_factored_blocks` stay within :data:`FACTORED_MAX` entries."""
    return Lb * p * Lb * c <= FACTORED_MAX and Lb * c * bnb <= FACTORED_MAX // 2


def _factored_blocks(D: LowRank, pw: np.ndarray, Y: np.ndarray, dtype: np.dtype) -> tuple[np.ndarray, np.ndarray]:
    """Step 1 of :func:`_blocks` for one step length and a factored forcing ``d[i] = V[i] F``.

    From a zero state, a block's outputs are a convolution of its ``V`` with the impulse response
    ``h[k] = Re(Y E^k F)`` (k < Lb) -- one GEMM of every block's ``V`` against the (Lb p, Lb c)
    lower block-Toeplitz matrix of ``h`` -- and its end state is ``sum_i E^(Lb-1-i) F^T V[i]``, one
    GEMM against the stacked ``E^(Lb-1-i) F``. The cost is ``Lb`` times a ``p x c x modes`` product
    and two GEMMs, instead of ``Lb`` passes over every block's states.

    Parameters
    ----------
    D : LowRank
        ``V`` (B, Lb, c), ``F`` (c, b, nb).
    pw : (Lb, b, b, nb) ndarray
        ``E^(j+1)`` of the step.
    Y : (p, b, nb) ndarray
        Output map.

    Returns
    -------
    y : (B, Lb, p) ndarray
        Outputs of each block from a zero state.
    last : (B, b, nb) ndarray
        Each block's state after its last step, from a zero state.
    """
    B, Lb, c = D.V.shape
    b, nb = pw.shape[1], pw.shape[3]
    p = Y.shape[0]
    powers = np.empty_like(pw)                 # E^k, k = 0 .. Lb - 1
    powers[0] = np.eye(b)[:, :, None]
    powers[1:] = pw[:-1]
    F = D.F.astype(dtype, copy=False)
    if b == 1:                                                     # (Lb, c, b, nb): E^k F
        EF = powers[:, None, :, 0, :] * F[None]
    else:
        EF = np.einsum("kabm,cbm->kcam", powers, F)
    EFr = EF.reshape(Lb * c, b * nb)
    h = RealProduct(Y.reshape(p, b * nb), dtype)(EFr).reshape(Lb, c, p).transpose(0, 2, 1)   # (Lb, p, c)
    lag = np.arange(Lb)[:, None] - np.arange(Lb)[None, :]          # j - i
    T = np.where((lag >= 0)[:, None, :, None], h[np.maximum(lag, 0)].transpose(0, 2, 1, 3), 0.0)  # (j, p, i, c)
    V = np.ascontiguousarray(D.V.reshape(B, Lb * c))
    y = (V @ T.reshape(Lb * p, Lb * c).T).reshape(B, Lb, p)
    Vr = np.ascontiguousarray(D.V[:, ::-1].reshape(B, Lb * c))    # step i against E^(Lb-1-i) F
    if np.iscomplexobj(EFr):
        last = np.ascontiguousarray(Vr @ EFr.view(float)).view(complex)
    else:
        last = Vr @ EFr
    return y, last.reshape(B, b, nb).astype(dtype, copy=False)
