"""Contact-area estimators from a solver's contact mask (docs/normal_contact.md, "Contact-area estimators").

The solver's contact ratio counts elements with ``p > 0`` (``alpha = N_c / N``). On a grid that
resolves the contact clusters coarsely this count carries a discretisation error proportional to
the length of the contact boundary. Yastrebov, Anciaux and Molinari (2017, "On the accurate
computation of the true contact-area in mechanical contact of random rough surfaces", Tribology
International, arXiv:1701.02727) correct it with that length:

    A = dx dy (N_c - c N_p),   c = (pi - 1 + ln 2) / 24 = 0.1181...

with ``N_p`` the number of element edges between a contact and a non-contact element (the
contact/non-contact interface length in element edges). The formula is taken as public
Tamaas-based code applies it "according to Yastrebov" (``A_raw - (pi - 1 + ln 2) / 24 * M * dx
* dx``, ``M`` the number of contact/non-contact switches along the rows and the columns); it is
not written from memory. It is derived for square elements, which is what the calibration's
grids have (measured files are resampled onto square elements).

Only the mask is needed, so the estimator works on any solver's output (``NormalResult.pressure
> 0``) without touching the solver. Whether it helps is measured, not assumed
(``benchmarks/contact_area_correction.py``).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["YAM_COEFFICIENT", "contact_perimeter", "corrected_contact_ratio"]

#: ``(pi - 1 + ln 2) / 24`` of Yastrebov, Anciaux and Molinari (2017)
YAM_COEFFICIENT = (math.pi - 1.0 + math.log(2.0)) / 24.0


def _mask(contact):
    m = np.asarray(contact)
    if m.ndim != 2 or m.size == 0:
        raise ValueError(f"contact must be a non-empty 2-D mask, got shape {m.shape}")
    if m.dtype != bool:
        if not np.issubdtype(m.dtype, np.number) or not np.isfinite(m).all():
            raise ValueError("contact must be a boolean mask or a finite pressure map")
        m = m > 0
    return m


def contact_perimeter(contact, *, periodic):
    """Number ``N_p`` of element edges between a contact and a non-contact element.

    Parameters
    ----------
    contact : array_like (n, m)
        Boolean contact mask, or a pressure map (contact where ``p > 0``).
    periodic : bool
        Count the edges across the patch's opposite sides (a periodic solve). Non-periodic: the
        patch's own border is not a contact boundary (nothing is known beyond it), so contact
        elements on it add no edge there.

    Returns
    -------
    int
        The interface length in element edges (x- and y-edges together).
    """
    m = _mask(contact)
    if periodic:
        return int(
            np.count_nonzero(m != np.roll(m, 1, axis=0))
            + np.count_nonzero(m != np.roll(m, 1, axis=1))
        )
    return int(np.count_nonzero(m[1:, :] != m[:-1, :]) + np.count_nonzero(m[:, 1:] != m[:, :-1]))


def corrected_contact_ratio(contact, *, periodic):
    """Contact ratio corrected for the discretisation of its boundary (Yastrebov et al. 2017).

    ``alpha_c = (N_c - c N_p) / N`` with ``c`` = :data:`YAM_COEFFICIENT`, ``N_c`` the contact
    elements, ``N_p`` = :func:`contact_perimeter` and ``N`` all elements; clipped to ``>= 0``.
    Square elements are assumed, as in the paper.

    Parameters
    ----------
    contact : array_like (n, m)
        Boolean contact mask, or a pressure map (contact where ``p > 0``).
    periodic : bool
        As in :func:`contact_perimeter`.
    """
    m = _mask(contact)
    n_c = np.count_nonzero(m)
    n_p = contact_perimeter(m, periodic=periodic)
    return max(0.0, (n_c - YAM_COEFFICIENT * n_p) / m.size)
