"""The calibration pipeline (Sec. 3.1 and 4): scene -> surfaces -> sweeps -> fit -> parameters.

- :mod:`.sweep.scene`: :class:`Scene` (everything a calibration needs) and :func:`load_scene` (TOML)
- :mod:`.sweep.surface_plan`: the plan of a scene's surfaces, every choice of their preparation made
  once (:func:`plan_surfaces` -> :class:`SurfacePlan`)
- :mod:`.sweep.scene_surfaces`: the one loader of a scene's surfaces (files or synthetic): the plan,
  run (:func:`run_plan`)
- :mod:`.sweep.sweeps`: the per-level normal (and pre-sliding) sweeps as independent jobs
- :mod:`.sweep.effects`: the optional effects (tangential, inclined, sliding)
- :mod:`.law.fit`, :mod:`.law.params`: the fits of Eqs. 24-25 and the parameter file
- :mod:`.sweep.resolution`: the same sweeps and fits at half the grid
- :mod:`.calibration`: :func:`calibrate`, which runs all of the above

Its parts by role, imported one way (tests/test_architecture.py): :mod:`.law` (the forms of
both branches, their fits and acceptance) <- :mod:`.sweep` (the scene, its surfaces, levels,
sweeps and effects) <- :mod:`.calibration` <- :mod:`.band` (several samples and their band).

It writes no files: :mod:`halfspace_calib.output` does.
"""

from .calibration import Calibration, calibrate
from .law.fit import fit_first_loading, fit_reload
from .law.params import make_params
from .sweep.scene import Scene, load_scene
from .sweep.scene_surfaces import SceneSurfaces, load_scene_surfaces, run_plan
from .sweep.surface_plan import SurfacePlan, plan_surfaces
from .sweep.sweeps import SweepResult, run_sweeps

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
