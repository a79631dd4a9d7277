"""Influence coefficients of the elastic half-space and their FFT application (Sec. 2.1).

The surface is discretised into ``Nx x Ny`` rectangular elements of size ``2a x 2b``
(``dx = 2a``, ``dy = 2b``) carrying a uniform pressure each. The normal displacement at the
centre of element ``k`` is ``u_k = sum_l C_kl p_l`` (Eq. 3) with Love's closed form of the
Boussinesq integral (Eq. 4) and the composite modulus ``E_star`` of Eq. 2.

``C_kl`` depends only on the offset ``x_k - x_l, y_k - y_l``, so the sum is a discrete
convolution evaluated by FFT in two modes:

- non-periodic (DC-FFT, Liu, Wang and Liu 2000): the coefficients for all offsets
  ``-(N-1) .. N-1`` are laid out on a zero-padded grid of at least ``2N - 1`` points per axis
  (rounded up to a fast FFT length), so that the circular convolution equals the linear one:
  the exact finite-body result of Eq. 3 (Hertz, isolated contacts).
- periodic: the surface is one period of an infinite periodic surface. Either the coefficients
  are taken at minimal-image offsets (``from_coefficients(..., periodic=True)``) or an exact
  spectral Green's function is used (``from_spectrum``). For the normal problem the default is
  the exact spectral periodic Green's function ``2 / (E_star |q|)`` (see ``normal_operator``).
- mirror (:class:`MirrorOperator`, normal problem only): the patch is one quarter of the period
  of its mirror-symmetric extension (reflected across each edge, period ``2 Lx x 2 Ly``),
  which is continuous across every edge: no seam, and no edge of a finite body. A symmetric
  pressure has a symmetric displacement, so the periodic operator of the extension restricted
  to the patch is diagonal in the cosine basis of the patch (DCT-II): FFTs of the patch's size.

The operator is generic: any even-or-odd kernel given as a function of the offset (for instance
the Cerruti coefficients of Eq. 16) reuses the same FFT machinery and the cached spectrum.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.fft as sfft

from ..common.checks import positive
from ..common.jobs import fft_threads

__all__ = [
    "BOUNDARIES",
    "InfluenceOperator",
    "MirrorOperator",
    "boundary_of",
    "love_coefficients",
    "normal_operator",
    "periodic_spectrum_normal",
]

#: the boundary treatments of a patch: one period of a periodic surface (its opposite edges
#: joined), one quarter of the period of its mirror-symmetric extension, an isolated body
BOUNDARIES = ("periodic", "mirror", "isolated")


def boundary_of(periodic=None, boundary=None) -> str:
    """The boundary treatment named by ``boundary`` or, older switch, ``periodic``.

    ``boundary``: one of :data:`BOUNDARIES`. ``periodic``: ``True`` is ``"periodic"``,
    ``False`` a boundary other than ``"periodic"`` (``"isolated"`` when ``boundary`` is not
    given: the zero-padded DC-FFT solve the switch always meant). Both ``None``:
    ``"periodic"``. A ``ValueError`` names a boundary that is not one of :data:`BOUNDARIES`
    and a ``periodic`` that contradicts ``boundary``.
    """
    if boundary is not None and boundary not in BOUNDARIES:
        raise ValueError(f"boundary must be one of {', '.join(BOUNDARIES)}, got {boundary!r}")
    if periodic is not None and not isinstance(periodic, (bool, np.bool_)):
        raise ValueError(f"periodic must be True, False or None, got {periodic!r}")
    if boundary is None:
        return "isolated" if periodic is not None and not periodic else "periodic"
    if periodic is not None and bool(periodic) != (boundary == "periodic"):
        raise ValueError(
            f"periodic={periodic!r} contradicts boundary={boundary!r} (periodic=True is "
            "boundary='periodic'); give boundary alone"
        )
    return boundary


def _check_shape(shape) -> tuple[int, int]:
    try:
        nx, ny = (int(s) for s in shape)
    except (TypeError, ValueError):
        raise ValueError(f"shape must be a pair of integers >= 1, got {shape!r}") from None
    if nx < 1 or ny < 1:
        raise ValueError(f"shape must be a pair of integers >= 1, got {shape!r}")
    return nx, ny


def _xasinh(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``x * asinh(y / |x|)``, continuous with value 0 at ``x = 0``."""
    ax = np.abs(x)
    safe = np.where(ax > 0.0, ax, 1.0)
    return np.where(ax > 0.0, x * np.arcsinh(y / safe), 0.0)


def _love_primitive(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Primitive ``F`` with ``d2F/dx dy = 1 / sqrt(x^2 + y^2)``."""
    return _xasinh(x, y) + _xasinh(y, x)


def love_coefficients(x, y, a: float, b: float, E_star: float) -> np.ndarray:
    """Love's closed form of the normal influence coefficient. This is Eq. 4.

    Normal surface displacement at offset ``(x, y)`` from the centre of a ``2a x 2b``
    rectangle loaded by a unit uniform pressure on an elastic half-space,
    ``C = 1 / (pi E_star) * iint_{-a,-b}^{a,b} d xi d eta / rho`` with ``rho`` of Eq. 5.

    Parameters
    ----------
    x, y : array_like
        Offsets ``x_k - x_l`` and ``y_k - y_l`` in m (broadcast together).
    a, b : float
        Half-widths of the element in m (``dx = 2a``, ``dy = 2b``).
    E_star : float
        Composite modulus of Eq. 2 in Pa.

    Returns
    -------
    numpy.ndarray
        Influence coefficients in m/Pa.

    Notes
    -----
    Evaluated as ``F(x+a, y+b) - F(x-a, y+b) - F(x+a, y-b) + F(x-a, y-b)`` with the primitive
    ``F(X, Y) = X asinh(Y/|X|) + Y asinh(X/|Y|)``, which is Love's (1929) logarithmic form
    rewritten without cancellation (the ``X ln|X|`` terms of the log form cancel pairwise).
    """
    a = positive("a", a)
    b = positive("b", b)
    E_star = positive("E_star", E_star)
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    F = _love_primitive
    val = F(x + a, y + b) - F(x - a, y + b) - F(x + a, y - b) + F(x - a, y - b)
    return val / (np.pi * E_star)


def periodic_spectrum_normal(qx: np.ndarray, qy: np.ndarray, E_star: float) -> np.ndarray:
    """Exact periodic Green's function of the half-space in Fourier space, ``2 / (E_star |q|)``.

    A pressure ``p cos(q . x)`` gives the displacement ``2 p cos(q . x) / (E_star |q|)`` (the
    Fourier transform of Eq. 1). The ``q = 0`` mode (the mean displacement of a periodic
    surface, undefined for a half-space) is set to 0; it is absorbed by the approach ``u0``.
    """
    q = np.hypot(qx, qy)
    safe = np.where(q > 0.0, q, 1.0)
    return np.where(q > 0.0, 2.0 / (E_star * safe), 0.0)


def _offsets(n: int, m: int, periodic: bool) -> np.ndarray:
    """Integer offsets laid out in FFT order on an axis of length ``m``."""
    i = np.arange(m)
    if periodic:
        # minimal image: 0, 1, .., ceil(n/2)-1, -floor(n/2), .., -1
        return (i + n // 2) % n - n // 2
    # linear convolution: offsets 0..n-1 then -(n-1)..-1 at the end, zeros in between
    off = np.where(i < n, i, i - m)
    return off


class InfluenceOperator:
    """Discrete convolution ``u = C * p`` applied by FFT with a cached spectrum.

    Build with :meth:`from_coefficients` (a real-space kernel, e.g. Love's Eq. 4 or Cerruti's
    Eq. 16) or :meth:`from_spectrum` (periodic only, an exact spectral Green's function).

    Attributes
    ----------
    shape : tuple of int
        Grid ``(Nx, Ny)`` of the pressure and displacement fields.
    fft_shape : tuple of int
        FFT grid: ``shape`` when periodic, ``>= 2N - 1`` per axis otherwise (a fast length
        when built by :meth:`from_coefficients`).
    periodic : bool
        Periodic (circular) or non-periodic (zero-padded, linear) convolution.
    spectrum : numpy.ndarray
        ``rfft2`` of the kernel on ``fft_shape`` (complex, cached).
    kernel : numpy.ndarray
        The real-space kernel on ``fft_shape`` in FFT order (offset ``(0, 0)`` at index
        ``(0, 0)``); used by :meth:`apply_sparse` and :meth:`dense_matrix`.
    """

    def __init__(self, kernel: np.ndarray, shape, periodic: bool, workers: int | None = None):
        self.shape = _check_shape(shape)
        self.periodic = bool(periodic)
        kernel = np.ascontiguousarray(kernel, dtype=float)
        if self.periodic and kernel.shape != self.shape:
            raise ValueError(f"periodic kernel must have shape {self.shape}, got {kernel.shape}")
        if not self.periodic and (
            kernel.shape[0] < 2 * self.shape[0] - 1 or kernel.shape[1] < 2 * self.shape[1] - 1
        ):
            raise ValueError(
                f"non-periodic kernel must be at least (2Nx-1, 2Ny-1) = "
                f"{(2 * self.shape[0] - 1, 2 * self.shape[1] - 1)}, got {kernel.shape}"
            )
        self.fft_shape = kernel.shape
        self.workers = workers if workers is not None else fft_threads()
        self.kernel = kernel
        self.boundary = "periodic" if self.periodic else "isolated"
        self.spectrum = sfft.rfft2(kernel, workers=self.workers)
        self._weights = None
        self._spec_real = None
        self.inverse_spectrum = None
        self.real_dtype = np.float64

    # ------------------------------------------------------------------ builders
    @classmethod
    def from_coefficients(
        cls,
        coeff_fn: Callable[[np.ndarray, np.ndarray], np.ndarray],
        shape,
        dx: float,
        dy: float | None = None,
        periodic: bool = True,
        workers: int | None = None,
    ) -> InfluenceOperator:
        """Operator from a kernel given as a function of the offset.

        Parameters
        ----------
        coeff_fn : callable
            ``coeff_fn(x, y)`` returns the influence of element ``l`` on element ``k`` for the
            offsets ``x = x_k - x_l``, ``y = y_k - y_l`` in m (2-D arrays, broadcast).
        shape : tuple of int
            Grid ``(Nx, Ny)``; axis 0 is x (spacing ``dx``), axis 1 is y (spacing ``dy``).
        dx, dy : float
            Element sizes ``2a`` and ``2b`` in m; ``dy`` defaults to ``dx``.
        periodic : bool
            Minimal-image offsets on the ``Nx x Ny`` torus when True, zero-padded linear
            convolution (DC-FFT) when False.
        workers : int, optional
            Threads for ``scipy.fft`` (default: :func:`~halfspace_calib.common.jobs.fft_threads`).
        """
        nx, ny = _check_shape(shape)
        dx = positive("dx", dx)
        dy = dx if dy is None else positive("dy", dy)
        if periodic:
            mx, my = nx, ny
        else:
            mx, my = (
                sfft.next_fast_len(2 * nx - 1, real=True),
                sfft.next_fast_len(2 * ny - 1, real=True),
            )
        ox = _offsets(nx, mx, periodic)
        oy = _offsets(ny, my, periodic)
        X = (ox * dx)[:, None]
        Y = (oy * dy)[None, :]
        kernel = np.asarray(coeff_fn(X, Y), dtype=float)
        kernel = np.broadcast_to(kernel, (mx, my)).copy()
        if not periodic:
            # offsets beyond +-(N-1) never pair two elements: keep them zero
            kernel[(ox > nx - 1) | (ox < -(nx - 1)), :] = 0.0
            kernel[:, (oy > ny - 1) | (oy < -(ny - 1))] = 0.0
        return cls(kernel, (nx, ny), periodic, workers)

    @classmethod
    def from_spectrum(
        cls,
        spectrum_fn: Callable[[np.ndarray, np.ndarray], np.ndarray],
        shape,
        dx: float,
        dy: float | None = None,
        workers: int | None = None,
    ) -> InfluenceOperator:
        """Periodic operator from a Green's function in Fourier space.

        ``spectrum_fn(qx, qy)`` gives the displacement per unit pressure amplitude of the mode
        ``exp(i (qx x + qy y))`` with angular wavenumbers in rad/m on the grid's period
        ``Lx = Nx dx``, ``Ly = Ny dy``.
        """
        nx, ny = _check_shape(shape)
        dx = positive("dx", dx)
        dy = dx if dy is None else positive("dy", dy)
        qx = 2.0 * np.pi * sfft.fftfreq(nx, d=dx)[:, None]
        qy = 2.0 * np.pi * sfft.rfftfreq(ny, d=dy)[None, :]
        spec = np.broadcast_to(np.asarray(spectrum_fn(qx, qy), dtype=float), (nx, ny // 2 + 1))
        kernel = sfft.irfft2(spec, s=(nx, ny))
        op = cls(kernel, (nx, ny), True, workers)
        # keep the exact spectrum (the round trip above only adds roundoff)
        op.spectrum = np.asarray(spec, dtype=complex).copy()
        op._weights = None
        return op

    # ------------------------------------------------------------------ application
    def apply(self, p: np.ndarray) -> np.ndarray:
        """Displacement ``u = C * p`` (Eq. 3) for a field ``p`` of shape ``shape``."""
        p = np.asarray(p, dtype=float)
        if p.shape != self.shape:
            raise ValueError(f"p must have shape {self.shape}, got {p.shape}")
        nx, ny = self.shape
        # spectrum first: a complex product rounds differently with its operands swapped, and
        # this order keeps the tangential solver's iterates as they were before it used this class
        ph = self.spectrum * sfft.rfft2(p, s=self.fft_shape, workers=self.workers)
        u = sfft.irfft2(ph, s=self.fft_shape, workers=self.workers, overwrite_x=True)
        if self.periodic:
            return u
        return np.ascontiguousarray(u[:nx, :ny])

    __call__ = apply

    def single(self) -> InfluenceOperator:
        """A copy that runs the FFTs in single precision (float32 / complex64).

        Concerns :meth:`forward`, :meth:`backward` and :meth:`apply_inverse`; results are
        returned as float64.

        A speed-accuracy trade (relative roundoff about 1e-7 instead of 1e-16), never a default.
        """
        import copy

        op = copy.copy(self)
        op.real_dtype = np.float32
        op.spectrum = self.spectrum.astype(np.complex64)
        op._weights = None
        if self.inverse_spectrum is not None:
            op.inverse_spectrum = self.inverse_spectrum.astype(np.float32)
        return op

    def forward(self, p: np.ndarray) -> np.ndarray:
        """``rfft2`` of ``p`` on the (padded) FFT grid: the half spectrum used by :meth:`backward`."""
        return sfft.rfft2(
            np.asarray(p, dtype=self.real_dtype), s=self.fft_shape, workers=self.workers
        )

    def backward(self, p_hat: np.ndarray) -> np.ndarray:
        """Displacement from a pressure half spectrum: ``apply(p) == backward(forward(p))``."""
        nx, ny = self.shape
        u = sfft.irfft2(
            p_hat * self.spectrum, s=self.fft_shape, workers=self.workers, overwrite_x=True
        )
        u = u if self.periodic else u[:nx, :ny]
        return np.ascontiguousarray(u, dtype=np.float64)

    def apply_inverse(self, u: np.ndarray) -> np.ndarray:
        """Approximate inverse ``C^-1 u`` by ``inverse_spectrum`` (a preconditioner).

        Requires ``inverse_spectrum`` (set by :func:`normal_operator`: ``E_star |q| / 2``).
        """
        nx, ny = self.shape
        uh = sfft.rfft2(
            np.asarray(u, dtype=self.real_dtype), s=self.fft_shape, workers=self.workers
        )
        uh *= self.inverse_spectrum
        z = sfft.irfft2(uh, s=self.fft_shape, workers=self.workers, overwrite_x=True)
        z = z if self.periodic else z[:nx, :ny]
        return np.ascontiguousarray(z, dtype=np.float64)

    def energy(self, p_hat: np.ndarray) -> float:
        """Quadratic form ``dot(p, C p)`` from the half spectrum of ``p`` (Parseval).

        For a symmetric kernel; exact in both modes because ``p`` vanishes on the padding.
        """
        if self._weights is None:
            my = self.fft_shape[1]
            w = np.full(my // 2 + 1, 2.0)
            w[0] = 1.0
            if my % 2 == 0:
                w[-1] = 1.0
            self._weights = w / (self.fft_shape[0] * my)
            self._spec_real = np.ascontiguousarray(self.spectrum.real)
        a = p_hat.real.astype(np.float64) ** 2 + p_hat.imag.astype(np.float64) ** 2
        a *= self._spec_real
        return float(a.sum(axis=0) @ self._weights)

    def apply_sparse(self, rows, cols, values) -> np.ndarray:
        """``C * p`` for a field with few non-zeros, by direct summation of kernel columns.

        Costs ``O(len(values) * Nx * Ny)``; cheaper than :meth:`apply` for a handful of
        elements (e.g. the response to a few point loads).
        """
        nx, ny = self.shape
        mx, my = self.fft_shape
        u = np.zeros(self.shape)
        ix = np.arange(nx)
        iy = np.arange(ny)
        for i0, j0, v in zip(
            np.atleast_1d(rows), np.atleast_1d(cols), np.atleast_1d(values), strict=True
        ):
            u += v * self.kernel[np.ix_((ix - i0) % mx, (iy - j0) % my)]
        return u

    @property
    def norm(self) -> float:
        """Bound of the operator's 2-norm: the largest modulus of the spectrum (for a step length, say).

        Exact when periodic (the spectrum holds the eigenvalues of the circulant); an upper bound
        when not (the operator is a principal block of the circulant embedding on ``fft_shape``).
        """
        return float(np.max(np.abs(self.spectrum)))

    def dense_matrix(self, idx=None) -> np.ndarray:
        """Dense influence matrix ``C[k, l]`` between the flat (row-major) grid indices ``idx``.

        All ``Nx Ny`` elements by default; for tests of small grids and dense reference solvers.
        """
        mx, my = self.fft_shape
        if idx is None:
            idx = np.arange(self.shape[0] * self.shape[1])
        ix, iy = np.unravel_index(idx, self.shape)
        return self.kernel[(ix[:, None] - ix[None, :]) % mx, (iy[:, None] - iy[None, :]) % my]

    dense = dense_matrix


class MirrorOperator:
    """The normal operator of a patch's mirror-symmetric extension, applied on the patch.

    The patch of ``Nx x Ny`` elements is reflected across each of its edges into a surface
    of period ``2 Lx x 2 Ly`` (``Lx = Nx dx``) that is continuous across every edge: the
    heights of the elements on either side of an edge are equal. Pressed at a uniform mean
    pressure, the extension's pressure and displacement are mirror-symmetric too, so the whole
    problem lives on the patch. The periodic Green's function of the extension,
    ``2 / (E_star |q|)`` (:func:`periodic_spectrum_normal`), restricted to symmetric fields is
    diagonal in the patch's cosine basis ``cos(pi k (i + 1/2) / Nx)``: the orthonormal DCT-II
    of the patch, with the mode ``k`` at ``q = pi k / Lx``. The operator is therefore exactly
    the periodic operator of the ``2 Nx x 2 Ny`` extension read on the patch (tested), at the
    cost of transforms of the patch's own size.

    Same interface as :class:`InfluenceOperator` for the normal solver (:meth:`forward` gives
    the cosine coefficients instead of the half spectrum). ``periodic`` is ``False``: the
    patch's opposite edges are not joined (:attr:`boundary` is ``"mirror"``).
    """

    periodic = False
    boundary = "mirror"

    def __init__(self, shape, dx: float, E_star: float, dy: float | None = None, workers=None):
        self.shape = _check_shape(shape)
        self.fft_shape = self.shape
        nx, ny = self.shape
        dx = positive("dx", dx)
        dy = dx if dy is None else positive("dy", dy)
        E_star = positive("E_star", E_star)
        self.workers = workers if workers is not None else fft_threads()
        qx = (np.pi / (nx * dx)) * np.arange(nx)[:, None]
        qy = (np.pi / (ny * dy)) * np.arange(ny)[None, :]
        self.spectrum = periodic_spectrum_normal(qx, qy, E_star)
        inv = 0.5 * E_star * np.hypot(qx, qy)
        inv[0, 0] = 0.5 * E_star * np.pi / max(nx * dx, ny * dy)  # the lowest mode's value
        self.inverse_spectrum = inv
        self.real_dtype = np.float64

    def _dct(self, a):
        a = np.asarray(a, dtype=self.real_dtype)
        return sfft.dctn(a, type=2, norm="ortho", workers=self.workers)

    def _idct(self, a):
        z = sfft.idctn(a, type=2, norm="ortho", workers=self.workers, overwrite_x=True)
        return np.ascontiguousarray(z, dtype=np.float64)

    def forward(self, p: np.ndarray) -> np.ndarray:
        """Cosine coefficients of ``p`` (orthonormal DCT-II), used by :meth:`backward`."""
        return self._dct(p)

    def backward(self, p_hat: np.ndarray) -> np.ndarray:
        """Displacement from the cosine coefficients: ``apply(p) == backward(forward(p))``."""
        return self._idct(p_hat * self.spectrum)

    def apply(self, p: np.ndarray) -> np.ndarray:
        """Displacement ``u = C p`` of the mirror-symmetric extension, on the patch."""
        p = np.asarray(p, dtype=float)
        if p.shape != self.shape:
            raise ValueError(f"p must have shape {self.shape}, got {p.shape}")
        return self.backward(self.forward(p))

    __call__ = apply

    def apply_inverse(self, u: np.ndarray) -> np.ndarray:
        """Approximate inverse ``C^-1 u`` by ``E_star |q| / 2`` (the preconditioner)."""
        uh = self._dct(u)
        uh *= self.inverse_spectrum
        return self._idct(uh)

    def energy(self, p_hat: np.ndarray) -> float:
        """Quadratic form ``dot(p, C p)`` from the cosine coefficients of ``p`` (Parseval)."""
        a = p_hat.astype(np.float64) ** 2
        return float(np.sum(a * self.spectrum))

    @property
    def norm(self) -> float:
        """The operator's 2-norm: its largest eigenvalue, that of the lowest cosine mode."""
        return float(self.spectrum.max())

    def single(self) -> MirrorOperator:
        """A copy that runs the transforms in single precision (see :meth:`InfluenceOperator.single`)."""
        import copy

        op = copy.copy(self)
        op.real_dtype = np.float32
        return op

    def dense_matrix(self) -> np.ndarray:
        """Dense matrix ``C[k, l]`` over the flat (row-major) patch elements (small grids, tests)."""
        n = self.shape[0] * self.shape[1]
        cols = [self.apply(e.reshape(self.shape)).ravel() for e in np.eye(n)]
        return np.array(cols).T


def normal_operator(
    shape,
    dx: float,
    E_star: float,
    *,
    dy: float | None = None,
    periodic: bool | None = None,
    kernel: str = "spectral",
    workers: int | None = None,
    boundary: str | None = None,
) -> InfluenceOperator | MirrorOperator:
    """The normal influence operator of the elastic half-space. It is Eqs. 3-4.

    Parameters
    ----------
    shape : tuple of int
        Grid ``(Nx, Ny)``.
    dx, dy : float
        Element sizes ``2a``, ``2b`` in m (``dy`` defaults to ``dx``).
    E_star : float
        Composite modulus (Eq. 2) in Pa.
    periodic : bool, optional
        The older switch of ``boundary`` (:func:`boundary_of`): True is ``"periodic"``, False
        ``"isolated"``.
    kernel : {"spectral", "love"}
        Periodic mode only: ``"spectral"`` (default) uses the exact periodic Green's function
        ``2 / (E_star |q|)`` (point values of the displacement of a sampled pressure field,
        exact for every Fourier mode of the grid); ``"love"`` uses Love's coefficients at
        minimal-image offsets (a truncated periodisation: accurate at short wavelengths, the
        long-range 1/r tail beyond half a period is cut). Non-periodic mode always uses Love;
        the mirror mode only the spectral Green's function.
    workers : int, optional
        Threads for ``scipy.fft`` (default: :func:`~halfspace_calib.common.jobs.fft_threads`).
    boundary : {"periodic", "mirror", "isolated"}, optional
        The patch as one period of a periodic surface (default), as one quarter of the period
        of its mirror-symmetric extension (:class:`MirrorOperator`), or as an isolated finite
        body (DC-FFT).
    """
    E_star = positive("E_star", E_star)
    dx = positive("dx", dx)
    dy = dx if dy is None else positive("dy", dy)
    if kernel not in ("spectral", "love"):
        raise ValueError(f"kernel must be 'spectral' or 'love', got {kernel!r}")
    boundary = boundary_of(periodic, boundary)
    if boundary == "mirror":
        if kernel != "spectral":
            raise ValueError(
                "kernel='love' applies to the periodic boundary; the mirror one is spectral"
            )
        return MirrorOperator(shape, dx, E_star, dy=dy, workers=workers)
    periodic = boundary == "periodic"
    if periodic and kernel == "spectral":
        op = InfluenceOperator.from_spectrum(
            lambda qx, qy: periodic_spectrum_normal(qx, qy, E_star), shape, dx, dy, workers
        )
    else:
        op = InfluenceOperator.from_coefficients(
            lambda x, y: love_coefficients(x, y, dx / 2, dy / 2, E_star),
            shape,
            dx,
            dy,
            periodic=periodic,
            workers=workers,
        )
    op.inverse_spectrum = inverse_spectrum_normal(op.fft_shape, dx, dy, E_star)
    return op


def inverse_spectrum_normal(fft_shape, dx: float, dy: float, E_star: float) -> np.ndarray:
    """Inverse of the continuous Green's function, ``E_star |q| / 2``, on an FFT half spectrum.

    Used as preconditioner; the ``q = 0`` mode gets the value of the lowest mode.
    """
    mx, my = fft_shape
    qx = 2.0 * np.pi * sfft.fftfreq(mx, d=dx)[:, None]
    qy = 2.0 * np.pi * sfft.rfftfreq(my, d=dy)[None, :]
    inv = 0.5 * E_star * np.hypot(qx, qy)
    inv[0, 0] = 0.5 * E_star * 2.0 * np.pi / max(mx * dx, my * dy)
    return inv
