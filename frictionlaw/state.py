"""Per-node pressure history ``p_hist`` with trial/commit semantics (docs/design.md, invariants).

The host evaluates the law any number of times during the Newton iterations of
an increment; each evaluation proposes a *trial* history ``max(p_hist, p)`` from
the *committed* one, so iterations never ratchet it. The host calls
:meth:`HistoryState.commit` once the increment is accepted, or
:meth:`HistoryState.rollback` on a cut-back.

Beside ``p_hist`` each node carries its flattening state (issue 43, docs/flattening.md): the
flattened contact fraction ``alpha_f`` (0 for a surface never flattened) and, for the two-state
model (``limit-analysis``), its asperities' flank slope ``slope_f`` (0: never flattened, the
block's slope), under the same rules:
a traction update with the bulk strain increment writes the trial fraction from the committed
one, the commit keeps it, a cut-back discards it, remeshing and restarts carry it.
"""

import os
from pathlib import Path
from typing import IO

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._io import atomic_write
from .law import as_float_array

__all__ = ["HistoryState"]

_RESTART_FORMAT = "sbmf-friction-restart"
_RESTART_VERSION = 3  # 3: with slope_f, 2: with alpha_f; versions 1 and 2 are read too


class HistoryState:
    """Committed and trial ``p_hist`` (Pa) for ``n_nodes`` contact nodes.

    Parameters
    ----------
    n_nodes : int, optional
        Number of nodes (an integer ``>= 0``); 0 by default, or the size of ``p_hist``
        (which it must then equal).
    p_hist : array_like, optional
        Initial committed history (finite, ``>= 0``); zeros by default.
    alpha_f : array_like, optional
        Initial committed flattened contact fraction (in ``[0, 1]``, one per node); zeros
        (never flattened) by default.
    slope_f : array_like, optional
        Initial committed flank slope of the two-state flattening (finite, ``>= 0``, one per
        node); zeros (never flattened) by default.
    """

    def __init__(
        self,
        n_nodes: int | None = None,
        p_hist: ArrayLike | None = None,
        alpha_f: ArrayLike | None = None,
        slope_f: ArrayLike | None = None,
    ) -> None:
        if p_hist is None:
            committed = np.zeros(_count("n_nodes", 0 if n_nodes is None else n_nodes))
        else:
            committed = _check_hist(p_hist).copy()
            if n_nodes is not None and _count("n_nodes", n_nodes) != committed.size:
                raise ValueError(
                    f"n_nodes = {n_nodes!r} disagrees with p_hist of {committed.size} nodes"
                )
        self._committed = committed
        self._trial = committed.copy()
        if alpha_f is None:
            self._a_committed = np.zeros(committed.size)
        else:
            self._a_committed = _check_fraction(alpha_f, committed.size).copy()
        self._a_trial = self._a_committed.copy()
        if slope_f is None:
            self._s_committed = np.zeros(committed.size)
        else:
            self._s_committed = _check_slope(slope_f, committed.size).copy()
        self._s_trial = self._s_committed.copy()

    @property
    def n_nodes(self) -> int:
        """Number of nodes."""
        return self._committed.size

    def __len__(self) -> int:
        return self.n_nodes

    @property
    def p_hist(self) -> NDArray[np.float64]:
        """Committed history (read-only view)."""
        v = self._committed.view()
        v.flags.writeable = False
        return v

    def committed_array(self) -> NDArray[np.float64]:
        """The committed history array itself (no copy), for kernels that only read it."""
        return self._committed

    def trial_array(self) -> NDArray[np.float64]:
        """The trial history array itself (no copy), for kernels that write ``max(p_hist, p)``."""
        return self._trial

    @property
    def p_hist_trial(self) -> NDArray[np.float64]:
        """Trial history of the current increment (read-only view)."""
        v = self._trial.view()
        v.flags.writeable = False
        return v

    @property
    def alpha_f(self) -> NDArray[np.float64]:
        """Committed flattened contact fraction (read-only view; 0: never flattened)."""
        v = self._a_committed.view()
        v.flags.writeable = False
        return v

    @property
    def alpha_f_trial(self) -> NDArray[np.float64]:
        """Trial flattened contact fraction of the current increment (read-only view)."""
        v = self._a_trial.view()
        v.flags.writeable = False
        return v

    @property
    def slope_f(self) -> NDArray[np.float64]:
        """Committed flank slope of the two-state flattening (read-only view; 0: never)."""
        v = self._s_committed.view()
        v.flags.writeable = False
        return v

    @property
    def slope_f_trial(self) -> NDArray[np.float64]:
        """Trial flank slope of the current increment (read-only view)."""
        v = self._s_trial.view()
        v.flags.writeable = False
        return v

    def flattening_arrays(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(committed, trial)`` ``alpha_f`` arrays themselves (no copy), for the kernels."""
        return self._a_committed, self._a_trial

    def slope_arrays(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(committed, trial)`` ``slope_f`` arrays themselves (no copy), for the kernels."""
        return self._s_committed, self._s_trial

    def propose(self, p: ArrayLike) -> None:
        """Set the trial history to ``max(committed, p)`` (``p <= 0`` leaves it as committed)."""
        p = as_float_array("p", p)
        if p.shape != self._committed.shape:
            raise ValueError(f"p must have shape {self._committed.shape}, got {p.shape}")
        if not np.isfinite(p).all():
            raise ValueError("p must be finite")
        np.maximum(self._committed, np.where(p > 0, p, 0.0), out=self._trial)

    def commit(self) -> None:
        """Accept the increment: the trial history (and flattening) becomes the committed one."""
        self._committed[:] = self._trial
        self._a_committed[:] = self._a_trial
        self._s_committed[:] = self._s_trial

    def rollback(self) -> None:
        """Discard the trial history and flattening (cut-back): back to the committed ones."""
        self._trial[:] = self._committed
        self._a_trial[:] = self._a_committed
        self._s_trial[:] = self._s_committed

    def resize(self, n_nodes: int) -> None:
        """Grow (new nodes: ``p_hist``, ``alpha_f``, ``slope_f`` 0) or shrink to ``n_nodes``."""
        n = _count("n_nodes", n_nodes)
        old = self.n_nodes
        for name in _ARRAYS:
            arr = getattr(self, name)
            new = np.zeros(n)
            new[: min(n, old)] = arr[: min(n, old)]
            setattr(self, name, new)

    def grow(self, n_new: int) -> NDArray[np.intp]:
        """Append ``n_new`` nodes (new contact) with ``p_hist = 0``; returns their indices."""
        n_new = _count("n_new", n_new)
        start = self.n_nodes
        self.resize(start + n_new)
        return np.arange(start, start + n_new)

    def remap(self, index_map: ArrayLike) -> None:
        """Renumber nodes: new node ``i`` takes old node ``index_map[i]``; ``-1`` means a new node.

        For remeshing: the host gives, for each new node, the old node it inherits
        (nearest node or a transfer of its choice); ``alpha_f`` and ``slope_f`` go with
        ``p_hist``.
        """
        idx = np.asarray(index_map)
        if idx.ndim != 1 or not np.issubdtype(idx.dtype, np.integer):
            raise ValueError("index_map must be a 1-D integer array")
        if idx.size and (idx.min() < -1 or idx.max() >= self.n_nodes):
            raise ValueError(f"index_map entries must be in [-1, {self.n_nodes - 1}]")
        for name in _ARRAYS:
            arr = getattr(self, name)
            new = np.zeros(idx.size)
            keep = idx >= 0
            new[keep] = arr[idx[keep]]
            setattr(self, name, new)

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the committed history and flattening to a restart file (``.npz``, atomic)."""

        def write(fh: IO[bytes]) -> None:
            np.savez(
                fh,
                format=np.array(_RESTART_FORMAT),
                version=np.array(_RESTART_VERSION),
                p_hist=self._committed,
                alpha_f=self._a_committed,
                slope_f=self._s_committed,
            )

        return atomic_write(path, write)

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> "HistoryState":
        """Read a restart file written by :meth:`save`.

        Raises ``ValueError`` naming ``path`` for anything but such a file: unreadable,
        truncated or damaged archives, missing fields, a format, version (an integer) or
        ``p_hist`` (finite, ``>= 0``, 1-D), ``alpha_f`` (in ``[0, 1]``, one per node) or
        ``slope_f`` (finite, ``>= 0``, one per node) that is not what :meth:`save` writes. A
        version 1 file (``p_hist`` alone) reads with ``alpha_f = 0``, a version 2 file (before
        the two-state flattening) with ``slope_f = 0``.
        """
        try:
            with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as data:
                missing = [k for k in ("format", "version", "p_hist") if k not in data.files]
                if missing:
                    raise ValueError(f"{path}: not a friction restart file (missing {missing})")
                fmt, ver, p_hist = data["format"], data["version"], data["p_hist"]
                alpha_f = data["alpha_f"] if "alpha_f" in data.files else None
                slope_f = data["slope_f"] if "slope_f" in data.files else None
        except ValueError as exc:
            if str(exc).startswith(f"{path}:"):
                raise
            raise ValueError(f"{path}: not a friction restart file ({exc})") from None
        except Exception as exc:  # zip, zlib, EOF, OS and header errors alike
            raise ValueError(
                f"{path}: not a friction restart file or a damaged one "
                f"({type(exc).__name__}: {exc})"
            ) from None
        if fmt.shape != () or fmt.dtype.kind != "U" or str(fmt) != _RESTART_FORMAT:
            raise ValueError(f"{path}: format {fmt!r} is not {_RESTART_FORMAT!r}")
        if ver.shape != () or ver.dtype.kind not in "iu":
            raise ValueError(f"{path}: version must be an integer, got {ver!r}")
        if int(ver) not in (1, 2, _RESTART_VERSION):
            raise ValueError(
                f"{path}: unsupported restart version {int(ver)}, expected 1 to {_RESTART_VERSION}"
            )
        if int(ver) >= 2 and alpha_f is None:
            raise ValueError(f"{path}: a version {int(ver)} restart file without alpha_f")
        if int(ver) == _RESTART_VERSION and slope_f is None:
            raise ValueError(f"{path}: a version {_RESTART_VERSION} restart file without slope_f")
        try:
            return cls(p_hist=p_hist, alpha_f=alpha_f, slope_f=slope_f)
        except ValueError as exc:
            raise ValueError(f"{path}: {exc}") from None


_ARRAYS = ("_committed", "_trial", "_a_committed", "_a_trial", "_s_committed", "_s_trial")


def _count(name: str, value: object) -> int:
    """A node count: an integer (not a bool, not a float) ``>= 0``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an integer >= 0, got {value!r}")
    if value < 0:
        raise ValueError(f"{name} must be >= 0, got {value!r}")
    return int(value)


def _check_hist(p_hist: ArrayLike) -> NDArray[np.float64]:
    arr = as_float_array("p_hist", p_hist)
    if arr.ndim != 1:
        raise ValueError(f"p_hist must be 1-D, got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise ValueError("p_hist must be finite")
    if (arr < 0).any():
        raise ValueError("p_hist must be >= 0")
    return arr


def _check_fraction(alpha_f: ArrayLike, n: int) -> NDArray[np.float64]:
    arr = as_float_array("alpha_f", alpha_f)
    if arr.shape != (n,):
        raise ValueError(f"alpha_f must have one value per node, shape ({n},), got {arr.shape}")
    if not (np.isfinite(arr).all() and (arr >= 0).all() and (arr <= 1).all()):
        raise ValueError("alpha_f must be contact fractions in [0, 1]")
    return arr


def _check_slope(slope_f: ArrayLike, n: int) -> NDArray[np.float64]:
    arr = as_float_array("slope_f", slope_f)
    if arr.shape != (n,):
        raise ValueError(f"slope_f must have one value per node, shape ({n},), got {arr.shape}")
    if not (np.isfinite(arr).all() and (arr >= 0).all()):
        raise ValueError("slope_f must be finite and >= 0 (0: never flattened)")
    return arr
