"""The paper's studies on top of the contact solvers (Sec. 3): compute only, typed results.

- :mod:`.presliding`: the pre-sliding curve and the tangential stiffness (Sec. 2.2)
- :mod:`.inclined`: inclined patches and the geometric shear ``tau_geo`` (Eqs. 19-23)
- :mod:`.geometric`: the geometric study of Figs. 9-10 (Sec. 3.2)
- :mod:`.sliding`, :mod:`.sliding_study`: sliding of the tool over the workpiece (Sec. 3.3)
"""

from .geometric import GeometricResult, GeometricStudy, fit_geo_ratio, geometric_study
from .inclined import tau_geo, tau_geo_from_surfaces
from .presliding import PreslidingCurve, presliding_curve, stiffness_power_law
from .sliding import SlidingResult, sliding_surfaces, sliding_sweep, sliding_workpiece
from .sliding_study import SlidingStudy, sliding_study

__all__ = [
    "GeometricResult",
    "GeometricStudy",
    "PreslidingCurve",
    "SlidingResult",
    "SlidingStudy",
    "fit_geo_ratio",
    "geometric_study",
    "presliding_curve",
    "sliding_study",
    "sliding_surfaces",
    "sliding_sweep",
    "sliding_workpiece",
    "stiffness_power_law",
    "tau_geo",
    "tau_geo_from_surfaces",
]
