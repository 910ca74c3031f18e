r"""Influence coefficients of the elastic half-space on a square grid, and their products by FFT.

Two identical elastic bodies (each E, ν; G = E/(2(1 + ν)), E* = E/(2(1 − ν²))) touch over a
plane surface cut into square elements of side h carrying uniform tractions. The relative
surface displacement at an element's centre due to a unit traction on an element at offset
``(x, y)`` (centre to centre) is, from the point-load solutions integrated over the square
(Love's rectangle solutions; Johnson, Contact Mechanics, §3.2-3.3):

* normal (Boussinesq): ``A = I₁ / (π E*)``;
* tangential (Cerruti), along x due to a shear along x: ``(1/(π G)) ((1 − ν) I₁ + ν I_xx)``;
  along y due to a shear along x (the coupling, zero at ν = 0): ``(ν/(π G)) I_xy``; along y
  due to y: the x-x coefficient with x and y swapped;

with ``I₁ = ∬ 1/r``, ``I_xx = ∬ x²/r³``, ``I_xy = ∬ xy/r³`` over the element. Their
antiderivatives ``F`` (``∂²F/∂x∂y`` the integrand) are ``x asinh(y/|x|) + y asinh(x/|y|)``,
``y asinh(x/|y|)`` and ``−r``; each integral is F's alternating sum over the four corners (the
terms ``x ln|x|`` and ``y ln|y|`` that the asinh forms drop cancel in that sum). At ν = 0 the
tangential coefficient equals the normal one (G = E*), as the contact notes say.

On a grid of N x N elements the product with an influence matrix is a discrete convolution:
zero-padded to at least 2N − 1 per side (a non-periodic half-space: Liu, Wang and Liu, Wear
2000), it is one FFT pair, O(N² log N) and nothing N⁴ in memory: a real pair for one component,
and for both (d = 2) one complex pair of ``z = q_x + i q_y``. With ``A = (K_xx + K_yy)/2`` and
``B = (K_xx − K_yy)/2 + i K_xy`` the 2 x 2 Cerruti operator is ``w = A z + B z̄`` (``w = u_x + i
u_y``), and the transform of ``z̄`` at the wave vector k is ``conj(Z(−k))``: one complex pair
costs about 1.5 real pairs, against 2 for the components one by one.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.fft as sfft

__all__ = ["Counted", "element_integrals", "kernels", "Convolution"]


def _asinh_ratio(a, b):
    """``a asinh(b/|a|)``, 0 where a = 0."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(a == 0.0, 0.0, a * np.arcsinh(b / np.abs(a)))


def element_integrals(x, y, h):
    """``(I₁, I_xx, I_xy)`` over a square of side h centred at offset ``(x, y)`` from the field
    point (any broadcastable arrays)."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    out = [np.zeros(np.broadcast(x, y).shape) for _ in range(3)]
    for sx, sy, sign in ((1, 1, 1.0), (-1, 1, -1.0), (1, -1, -1.0), (-1, -1, 1.0)):
        u, v = x + sx * h / 2, y + sy * h / 2
        out[0] += sign * (_asinh_ratio(u, v) + _asinh_ratio(v, u))
        out[1] += sign * _asinh_ratio(v, u)
        out[2] += sign * -np.hypot(u, v)
    return tuple(out)


def kernels(N: int, h: float, E: float, nu: float, dims: int = 1, second=None) -> dict:
    """The influence coefficients at every offset ``(i, j) h``, ``|i|, |j| < N``, as arrays of
    shape ``(2N − 1, 2N − 1)`` indexed by ``(i + N − 1, j + N − 1)`` (i along x): ``"n"``
    (normal), ``"xx"`` (and with ``dims = 2`` and ν > 0, ``"xy"`` and ``"yy"``). ``second``:
    body 2's ``(E2, ν2)`` if it differs (``E2 = inf``: rigid), each body's Boussinesq and
    Cerruti terms summed (:mod:`.dissimilar`); None: two bodies (E, ν)."""
    k = np.arange(-(N - 1), N) * h
    X, Y = np.meshgrid(k, k, indexing="ij")
    I1, Ixx, Ixy = element_integrals(X, Y, h)
    if second is not None:
        return _kernels_pair(I1, Ixx, Ixy, ((E, nu), second), dims)
    G = E / (2.0 * (1.0 + nu))
    Estar = E / (2.0 * (1.0 - nu * nu))
    out = {"n": I1 / (math.pi * Estar), "xx": ((1.0 - nu) * I1 + nu * Ixx) / (math.pi * G)}
    if dims == 2:
        if nu != 0.0:
            out["xy"] = nu * Ixy / (math.pi * G)
        out["yy"] = out["xx"].T.copy()
    return out


def _kernels_pair(I1, Ixx, Ixy, bodies, dims):
    """:func:`kernels` of two different bodies: each one's half-space terms (a rigid one,
    ``E = inf``, none), ``1/(2π G_k)`` in place of ``1/(π G)``."""
    n, xx, xy = 0.0, 0.0, 0.0
    for E, nu in bodies:
        if math.isinf(E):
            continue
        G = E / (2.0 * (1.0 + nu))
        n = n + (1.0 - nu) * I1 / (2.0 * math.pi * G)
        xx = xx + ((1.0 - nu) * I1 + nu * Ixx) / (2.0 * math.pi * G)
        xy = xy + nu * Ixy / (2.0 * math.pi * G)
    out = {"n": n, "xx": xx}
    if dims == 2:
        if np.any(xy):
            out["xy"] = xy
        out["yy"] = xx.T.copy()
    return out


def _backend():
    """scipy.fft's own pocketfft bindings (``r2c``, ``c2c``, ``c2r`` with the axes, the
    direction, the normalization code, the output array and the threads): one FFT along one
    axis of a block of rows costs a call of a few microseconds where ``scipy.fft``'s functions
    add about 7 µs of argument handling each, which the pruned pair's four calls would pay
    (measured on the 90 x 90 grid of a 44 x 44 one: a pruned real pair 42 µs against 67 µs for
    ``rfftn`` + ``irfftn``, complex 71 against 107). Where a scipy has no such bindings, the
    same transforms through ``scipy.fft``'s public functions (:class:`_Public`)."""
    global _FFT
    if _FFT is None:
        fft = _Public()
        try:
            from scipy.fft._pocketfft import pypocketfft as private

            if _agrees(private, fft):  # private API: used only where it gives the same numbers
                fft = private
        except Exception:  # pragma: no cover - another scipy
            pass
        _FFT = fft
    return _FFT


def _agrees(fft, public) -> bool:
    """Whether the bindings ``fft`` give what ``public`` gives (:class:`_Public`) on a random
    block: each of the three calls, to round-off."""
    x = np.random.default_rng(0).standard_normal((3, 8))
    outs = []
    for impl in (fft, public):
        X = np.empty((3, 5), dtype=complex)
        impl.r2c(x, (1,), True, 0, X, 1)
        Y = np.empty((3, 5), dtype=complex)
        impl.c2c(X, (0,), True, 0, Y, 1)
        Z = np.empty((3, 5), dtype=complex)
        impl.c2c(Y, (0,), False, 0, Z, 1)
        z = np.empty((3, 8))
        impl.c2r(Z, (1,), 8, False, 0, z, 1)
        outs.append(np.concatenate([X.ravel(), Y.ravel(), Z.ravel(), z.ravel()]))
    return bool(np.allclose(outs[0], outs[1], rtol=1e-12, atol=1e-12))


_FFT = None


class _Public:
    """The pocketfft bindings' calls (:func:`_backend`) by ``scipy.fft``'s public functions
    (no normalization: the callers' spectra carry it)."""

    @staticmethod
    def r2c(a, axes, forward, inorm, out, nthreads):
        out[...] = sfft.rfft(a, axis=axes[0], norm="backward")
        return out

    @staticmethod
    def c2c(a, axes, forward, inorm, out, nthreads):
        f = sfft.fft if forward else sfft.ifft
        out[...] = f(a, axis=axes[0], norm="backward" if forward else "forward")
        return out

    @staticmethod
    def c2r(a, axes, lastsize, forward, inorm, out, nthreads):
        out[...] = sfft.irfft(a, n=lastsize, axis=axes[0], norm="forward")
        return out


class Convolution:
    """Products with the influence matrices of an ``N x N`` grid by zero-padded FFT.

    ``normal(p)`` maps pressures ``(N, N)`` to normal displacements; ``tangential(q)`` maps
    shears ``(N, N)`` (d = 1, along x) or ``(2, N, N)`` (d = 2) to tangential displacements of
    the same shape. ``dense(name)`` forms one influence matrix (small grids only: tests and the
    cross-checks with the convex backends). The operator holds no count of its products: a
    solve counts its own through :class:`Counted`. ``second``: body 2's ``(E2, ν2)`` where it
    differs from body 1 (:func:`kernels`)."""

    def __init__(self, N: int, h: float, E: float, nu: float, dims: int = 1, second=None):
        self.N, self.h, self.dims = int(N), float(h), int(dims)
        self.M = self.padded_size(self.N)
        self.kernel = kernels(self.N, self.h, E, nu, self.dims, second)
        self.spectra = {name: self._spectrum(k) for name, k in self.kernel.items()}
        self.coupled = "xy" in self.spectra

    @staticmethod
    def padded_size(N: int) -> int:
        """The side M of the zero-padded FFT grid for an N x N grid (at least 2N − 1, a fast
        FFT length)."""
        return sfft.next_fast_len(2 * int(N) - 1, real=True)

    def _spectrum(self, k):
        N, M = self.N, self.M
        pad = np.zeros((M, M))
        idx = np.r_[np.arange(0, N), np.arange(M - N + 1, M)]  # offsets 0..N-1, -(N-1)..-1
        src = np.r_[np.arange(N - 1, 2 * N - 1), np.arange(0, N - 1)]
        pad[np.ix_(idx, idx)] = k[np.ix_(src, src)]
        return sfft.rfft2(pad)

    def normal(self, p):
        """The normal displacements ``A p`` of pressures ``(N, N)``: one pruned real FFT pair
        (:meth:`_real`)."""
        return self._normal_kind("normal", p)

    def _normal_kind(self, kind, p):
        N = self.N
        rows = np.zeros((N, self.M))
        rows[:, :N] = p
        return self._real(rows, self._scaled(kind, 1.0)["n"])[:N, :N]

    def _real(self, rows, K):
        """The real product of the spectrum K (scaled by ``1/M²``, on the real transform's half
        plane) with the padded array whose first N rows are ``rows`` (``(N, M)``; zero below):
        a new ``(M, M)`` array, the answer in its first N rows. Pruned: the forward transform
        along the rows of those N rows only, the inverse along the rows of the N rows wanted
        only."""
        N, M = self.N, self.M
        fft = _backend()
        X = np.empty((M, M // 2 + 1), dtype=complex)
        X[N:] = 0.0
        fft.r2c(rows, (1,), True, 0, X[:N], 1)
        fft.c2c(X, (0,), True, 0, X, 1)
        X *= K
        fft.c2c(X, (0,), False, 0, X, 1)
        out = np.empty((M, M))
        fft.c2r(X[:N], (1,), M, False, 0, out[:N], 1)
        return out

    def tangential(self, q):
        """Tangential displacements from shears ``(N, N)`` (d = 1) or ``(2, N, N)`` (d = 2,
        the x and y components)."""
        return self.unpad(self.padded("tangential", self.pad(q)), q.ndim)

    # -- the padded layout --------------------------------------------------------------------
    # The solvers' vectors live in the FFT's padded layout: one ``M x M`` array, zero outside
    # its ``N x N`` corner, real for d = 1 (the x components) and complex for d = 2 (x + i y:
    # one complex FFT pair then does both components, and Cerruti's 2 x 2 operator is
    # ``w = A z + B z̄``, below). ``view`` gives its components node-major, ``(M, M, d)``.
    def empty(self):
        """A zeroed array in the padded layout."""
        return np.zeros((self.M, self.M), dtype=float if self.dims == 1 else complex)

    def view(self, buf):
        """The components of a padded array, ``(M, M, d)`` (a view: writable)."""
        return (
            buf.reshape(self.M, self.M, 1)
            if self.dims == 1
            else buf.view(float).reshape(self.M, self.M, 2)
        )

    def pad(self, q):
        """Fields ``(N, N)`` (d = 1) or ``(2, N, N)`` (d = 2) in the padded layout."""
        q = np.asarray(q, dtype=float)
        buf = self.empty()
        self.view(buf)[: self.N, : self.N] = q[..., None] if q.ndim == 2 else np.moveaxis(q, 0, -1)
        return buf

    def unpad(self, buf, ndim: int = 3):
        """The fields of a padded array, a copy: ``(d, N, N)`` (``(N, N)`` if ``ndim`` is 2 and
        d = 1)."""
        out = np.moveaxis(self.view(buf)[: self.N, : self.N], -1, 0)
        return (out[0] if ndim == 2 else out).copy()

    def padded(self, kind: str, buf, factor: float = 1.0):
        """The product ``kind`` (``"tangential"``, or ``"precondition"``: the floored inverse
        of the padded circulant operator) of an array in the padded layout (:meth:`pad`),
        times ``factor``: a new array in that layout, the answer in its first N rows (the
        rest is not computed: only the corner ``[:N, :N]`` is the product, the rest of those
        rows the circular convolution's wrap-around). One FFT pair, real (d = 1) or complex
        (d = 2), pruned: the forward transform along the rows of the N rows that are not zero
        padding only, the inverse along the rows of the N rows wanted only (:func:`_backend`).
        The solvers' inner loops keep their vectors in this layout (no padding or cropping
        copies)."""
        K = self._scaled(kind, factor)
        N, M = self.N, self.M
        fft = _backend()
        if self.dims == 1:
            return self._real(buf[:N], K["xx"])
        Z = np.empty((M, M), dtype=complex)
        Z[N:] = 0.0
        fft.c2c(buf[:N], (1,), True, 0, Z[:N], 1)
        fft.c2c(Z, (0,), True, 0, Z, 1)
        if "B" in K:  # w = A z + B z̄: the transform of z̄ at k is conj(Z(−k))
            K["cerruti"](Z, K["A"], K["B"])
        else:
            Z *= K["A"]
        fft.c2c(Z, (0,), False, 0, Z, 1)
        out = np.empty((M, M), dtype=complex)
        fft.c2c(Z[:N], (1,), False, 0, out[:N], 1)
        return out

    def _scaled(self, kind, factor):
        """The spectra of ``kind`` times ``factor / M²`` (the inverse transform's
        normalization; cached): d = 1 ``{"xx"}`` on the real
        transform's half plane; d = 2 ``{"A", "B"}`` on the whole plane, with ``A = (xx +
        yy)/2`` and ``B = (xx − yy)/2 + i xy`` (no ``B`` when it is round-off: ν = 0; with
        ``B``, ``"cerruti"``: the compiled product);
        ``"normal"`` and ``"precondition_normal"``: ``{"n"}`` on the half plane."""
        cache = self.__dict__.setdefault("_scaled_cache", {})
        key = (kind, factor)
        K = cache.get(key)
        if K is None and kind in ("normal", "precondition_normal"):
            src = self.spectra if kind == "normal" else self._inverse
            K = {"n": (src["n"].real * (factor / (self.M * self.M))).astype(complex)}
            cache[key] = K
        if K is None:
            src = (
                self.spectra
                if kind == "tangential"
                # ixx, ixy, iyy
                else {name[1:]: v for name, v in self._inverse.items() if name != "n"}
            )
            factor = factor / (self.M * self.M)  # the inverse transform's normalization
            xx = src["xx"].real * factor
            # stored complex: a complex array times a real one is slower (a cast per entry)
            if self.dims == 1:
                K = {"xx": xx.astype(complex)}
            else:
                yy = src.get("yy", src["xx"]).real * factor
                xy = src["xy"].real * factor if "xy" in src else 0.0 * xx
                K = {"A": self._whole(0.5 * (xx + yy)).astype(complex)}
                B = self._whole(0.5 * (xx - yy) + 1j * xy)
                if np.max(np.abs(B)) > 1e-14 * np.max(np.abs(K["A"])):  # else round-off
                    from . import halfspace_kernels  # numba: compiled on first use

                    K["B"] = B
                    K["cerruti"] = halfspace_kernels.cerruti_product
            cache[key] = K
        return K

    def _whole(self, half):
        """A spectrum on the real transform's half plane ``(M, M//2 + 1)``, of a kernel even in
        both offsets (or odd in both: the same symmetry, ``K(−k) = K(k)``), on the whole
        plane ``(M, M)``."""
        M = self.M
        out = np.empty((M, M), dtype=half.dtype)
        out[:, : M // 2 + 1] = half
        rest = np.arange(M // 2 + 1, M)
        out[:, rest] = half[(-np.arange(M)) % M][:, M - rest]
        return out

    @property
    def _inverse(self):
        """The inverse of the padded (circulant) operators' spectra, each 2 x 2 block's
        eigenvalues floored at 1e-3 of the largest (the padded Cerruti spectrum dips a little
        below zero at the highest frequencies): a symmetric positive definite
        preconditioner."""
        inv = self.__dict__.get("_inv")
        if inv is None:
            K = {k: v.real for k, v in self.spectra.items()}
            floor = 1e-3 * float(K["xx"].max())
            inv = {"n": 1.0 / np.maximum(K["n"], floor)}
            if "xy" in K:
                a, b, c = K["xx"], K["xy"], K["yy"]
                m, r = 0.5 * (a + c), np.hypot(0.5 * (a - c), b)
                l1, l2 = m + r, m - r
                i1, i2 = 1.0 / np.maximum(l1, floor), 1.0 / np.maximum(l2, floor)
                with np.errstate(divide="ignore", invalid="ignore"):
                    w = np.where(r > 0, 0.5 / r, 0.0)  # P1 = (A - l2 I) / (l1 - l2)
                p_xx = np.where(r > 0, (a - l2) * w, 0.5)
                p_yy = np.where(r > 0, (c - l2) * w, 0.5)
                p_xy = b * w
                inv.update(
                    ixx=i2 + (i1 - i2) * p_xx, iyy=i2 + (i1 - i2) * p_yy, ixy=(i1 - i2) * p_xy
                )
            else:
                inv.update(
                    ixx=1.0 / np.maximum(K["xx"], floor),
                    iyy=1.0 / np.maximum(K.get("yy", K["xx"]), floor),
                )
            self.__dict__["_inv"] = inv
        return inv

    def precondition_normal(self, p):
        """The (floored) inverse of the padded circulant normal operator applied to ``p``."""
        return self._normal_kind("precondition_normal", p)

    def precondition(self, q):
        """The (floored) inverse of the padded circulant tangential operator applied to ``q``:
        a symmetric positive definite preconditioner for the operator restricted to any set of
        nodes. One FFT pair."""
        return self.unpad(self.padded("precondition", self.pad(q)), q.ndim)

    def diagonal(self, name: str) -> float:
        """The self-influence of an element (every diagonal entry)."""
        return float(self.kernel[name][self.N - 1, self.N - 1])

    def dense(self, name: str) -> np.ndarray:
        """The ``N² x N²`` influence matrix ``name`` (row-major nodes: ``i N + j``)."""
        N = self.N
        i, j = np.divmod(np.arange(N * N), N)
        return self.kernel[name][
            (i[:, None] - i[None, :]) + N - 1, (j[:, None] - j[None, :]) + N - 1
        ]


class Counted:
    """A :class:`Convolution` whose FFT pairs are counted (``products``): what one solve (a
    normal problem, a stepper's cycles) holds, so that the operator, part of the model, holds
    no count. Every other attribute is the operator's."""

    def __init__(self, op: Convolution, products: int = 0):
        self.op = op
        self.products = int(products)

    def __getattr__(self, name):
        return getattr(self.op, name)

    def normal(self, p):
        self.products += 1
        return self.op.normal(p)

    def precondition_normal(self, p):
        self.products += 1
        return self.op.precondition_normal(p)

    def padded(self, kind: str, buf, factor: float = 1.0):
        self.products += 1
        return self.op.padded(kind, buf, factor)

    def tangential(self, q):
        return self.op.unpad(self.padded("tangential", self.op.pad(q)), q.ndim)

    def precondition(self, q):
        return self.op.unpad(self.padded("precondition", self.op.pad(q)), q.ndim)
