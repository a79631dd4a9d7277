"""The shear flow stress ``k`` against the yield stress ``sigma_y``: the rule a parameter set obeys.

The law uses ``k`` (``tau = m k alpha``); ``sigma_y`` only sets its default, ``sigma_y / 2``
(Tresca, the paper's choice). So that the two can never disagree silently, a ``k`` given
explicitly must be one a yield criterion allows for a material of that ``sigma_y``: for every
isotropic, pressure-insensitive, convex yield criterion the pure-shear yield stress lies
between Tresca's ``sigma_y / 2`` and the twin-shear criterion's ``2 sigma_y / 3`` (von Mises,
``sigma_y / sqrt(3)``, in between). Outside that band (``k = 1 Pa``, or ``sigma_y`` edited
without ``k``) the parameter set is refused with both values in the message.
"""

import math

__all__ = ["K_OVER_SIGMA_Y", "K_TOLERANCE", "check_k_against_sigma_y"]

#: allowed ``k / sigma_y``: Tresca's 1/2 to the twin-shear criterion's 2/3
K_OVER_SIGMA_Y = (0.5, 2.0 / 3.0)

#: relative slack on the band's ends (rounding of values written to a file)
K_TOLERANCE = 1e-9


def check_k_against_sigma_y(k, sigma_y):
    """Raise ``ValueError`` naming ``k`` and ``sigma_y`` unless ``k / sigma_y`` is in the band.

    Both are positive finite floats (Pa), checked before this call.
    """
    lo, hi = K_OVER_SIGMA_Y
    ratio = k / sigma_y
    if lo * (1.0 - K_TOLERANCE) <= ratio <= hi * (1.0 + K_TOLERANCE):
        return
    raise ValueError(
        f"k = {k:g} Pa disagrees with sigma_y = {sigma_y:g} Pa: k / sigma_y = {ratio:.4g}, "
        f"allowed [{lo:g}, {hi:.4g}] (Tresca sigma_y/2 = {lo * sigma_y:g} Pa, von Mises "
        f"sigma_y/sqrt(3) = {sigma_y / math.sqrt(3.0):g} Pa, twin shear 2 sigma_y/3 = "
        f"{hi * sigma_y:g} Pa); give k in Pa consistent with sigma_y, or leave k out for "
        "sigma_y/2"
    )
