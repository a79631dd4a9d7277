"""Calibration of the SBMF friction law from elasto-plastic half-space contact of rough surfaces.

Sec. 2-3 of the paper: surfaces in, ``FrictionParams`` JSON out.
"""

__all__: list[str] = []
