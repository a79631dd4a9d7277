"""Abaqus/Standard's automatic incrementation around ``FRIC``, emulated (private).

:meth:`frictionlaw.export.harness.FricLib.increment` runs one increment the way an implicit host
does (Abaqus User Subroutines Reference, "FRIC": ``STATEV`` and ``TAU`` passed in as at the start
of the increment in every iteration; ``PNEWDT < 1`` abandons the attempt and retries it at
``PNEWDT`` times its size; the state of the converged iteration is committed): the Newton
iterates of each attempt are given by the caller as a function of the attempt's size. The
records here are re-exported by :mod:`frictionlaw.export.harness`.
"""

from dataclasses import dataclass

import numpy as np

__all__ = ["Attempt", "Increment", "run_increment"]


@dataclass(frozen=True)
class Attempt:
    """One attempt of an increment.

    Attributes
    ----------
    dtime : float
        Its size (``DTIME``).
    p_max : float
        The largest pressure of its iterates.
    pnewdt : float
        The smallest ``PNEWDT`` the routine returned in it (the host's preset, a large value,
        where it asked for nothing).
    """

    dtime: float
    p_max: float
    pnewdt: float


@dataclass(frozen=True)
class Increment:
    """What an emulated increment gave.

    Attributes
    ----------
    converged : bool
        An attempt ran through all its iterates without a cut-back request and without an
        error exit.
    attempts : tuple of Attempt
        Every attempt, in order (the last one converged if ``converged``).
    out : dict or None
        ``FRIC``'s outputs at the converged attempt's last iterate (the committed ``statev``
        among them); None if the increment did not converge.
    exits : int
        How often the routine called the host's error exit (the attempt stops there).
    """

    converged: bool
    attempts: tuple
    out: dict | None
    exits: int


def run_increment(
    fric,
    iterates,
    dgam,
    tau_start,
    statev_start,
    chrlngth,
    *,
    kstep=1,
    kinc=1,
    dtime=1.0,
    max_cutbacks=5,
    names=None,
):
    """One increment of automatic incrementation around ``fric`` (a :class:`FricLib`).

    ``iterates(dtime)`` gives the attempt's Newton iterates: a sequence of pressure arrays (n,),
    the last one the converged state. Every iterate calls ``FRIC`` at every point with the
    start-of-increment ``TAU`` and ``STATEV``; a ``PNEWDT < 1`` from any call abandons the
    attempt after that iteration and retries the increment at ``dtime * min(PNEWDT)``, at most
    ``max_cutbacks`` times (Abaqus' ``IA``, ccx's ``ia``: 5); ``names``: the names every call
    passes (``{"ciname": ...}``). Returns an :class:`Increment`.
    """
    attempts = []
    for _ in range(max_cutbacks + 1):
        pnewdt, p_max, out = np.inf, 0.0, None  # inf: no call yet
        for press in iterates(dtime):
            press = np.asarray(press, dtype=float)
            out = fric(
                press,
                dgam,
                tau_start,
                statev_start,
                chrlngth,
                kstep=kstep,
                kinc=kinc,
                dtime=dtime,
                **(names or {}),
            )
            p_max = max(p_max, float(press.max()))
            exits = fric.exits()
            if exits:
                attempts.append(Attempt(dtime, p_max, pnewdt))
                return Increment(False, tuple(attempts), None, exits)
            pnewdt = min(pnewdt, float(out["pnewdt"].min()))
            if pnewdt < 1.0:
                break  # the host abandons the attempt at this iteration's end
        attempts.append(Attempt(dtime, p_max, pnewdt))
        if pnewdt >= 1.0:
            return Increment(True, tuple(attempts), out, 0)
        dtime *= pnewdt
    return Increment(False, tuple(attempts), None, 0)
