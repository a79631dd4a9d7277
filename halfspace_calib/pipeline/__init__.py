"""The calibration pipeline (Sec. 3.1 and 4): scene -> surfaces -> sweeps -> fit -> parameters.

- :mod:`.scene`: :class:`Scene` (everything a calibration needs) and :func:`load_scene` (TOML)
- :mod:`.surface_plan`: the plan of a scene's surfaces, every choice of their preparation made
  once (:func:`plan_surfaces` -> :class:`SurfacePlan`)
- :mod:`.scene_surfaces`: the one loader of a scene's surfaces (files or synthetic): the plan,
  run (:func:`run_plan`)
- :mod:`.sweeps`: the per-level normal (and pre-sliding) sweeps as independent jobs
- :mod:`.effects`: the optional effects (tangential, inclined, sliding)
- :mod:`.fit`, :mod:`.params`: the fits of Eqs. 24-25 and the parameter file
- :mod:`.resolution`: the same sweeps and fits at half the grid
- :mod:`.calibration`: :func:`calibrate`, which runs all of the above

It writes no files: :mod:`halfspace_calib.output` does.
"""

from .calibration import Calibration, calibrate
from .fit import fit_first_loading, fit_reload
from .params import make_params
from .scene import Scene, load_scene
from .scene_surfaces import SceneSurfaces, load_scene_surfaces, run_plan
from .surface_plan import SurfacePlan, plan_surfaces
from .sweeps import SweepResult, run_sweeps

__all__ = [
    "Calibration",
    "Scene",
    "SceneSurfaces",
    "SurfacePlan",
    "SweepResult",
    "calibrate",
    "fit_first_loading",
    "fit_reload",
    "load_scene",
    "load_scene_surfaces",
    "make_params",
    "plan_surfaces",
    "run_plan",
    "run_sweeps",
]
