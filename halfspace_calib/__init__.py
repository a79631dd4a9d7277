"""Calibration of the SBMF friction law from elasto-plastic half-space contact of rough surfaces.

Sec. 2-3 of the paper: surfaces in, ``FrictionParams`` JSON out. Start with ``docs/architecture.md``
(the subpackages and what each may import). The main entry points:

- :func:`calibrate` with a :class:`Scene`, then :func:`write_outputs` (and the
  ``halfspace-calib`` command)
- :func:`solve_normal`, :func:`solve_normal_pair` (Sec. 2.1), :func:`solve_tangential` (Sec. 2.2)
- surfaces: :func:`read_surface`, :func:`dc04_edt_like`, :func:`tool_like`, :func:`self_affine`
- fits: :func:`fit_first_loading` (Eq. 24), :func:`fit_reload` (Eq. 25)
- studies: :func:`geometric_study` (Sec. 3.2), :func:`sliding_study` (Sec. 3.3), each taking a
  :class:`Materials` and a :class:`SolverSettings` record
- subpackages, one way down: ``cli`` -> ``pipeline`` -> ``output`` -> ``studies`` ->
  ``contact`` / ``topography`` -> ``common``

Importing the package loads none of it: each name is imported on first use (PEP 562), so that
the ``halfspace-calib`` command (:mod:`halfspace_calib.__main__`) starts, answers ``--version``
and handles Ctrl-C before NumPy, SciPy and numba are loaded.
"""

from sbmf_cli import lazy_names

#: the public names and the module each comes from (imported on first use)
_SOURCES = {
    "block_average": ".topography",
    "calibrate": ".pipeline.calibration",
    "Calibration": ".pipeline.calibration",
    "calibration_figures": ".output.report",
    "composite_heights": ".contact.normal",
    "composite_modulus": ".contact.normal",
    "dc04_edt_like": ".topography",
    "fit_first_loading": ".pipeline.law.fit",
    "fit_reload": ".pipeline.law.fit",
    "geometric_study": ".studies.geometric",
    "InfluenceOperator": ".contact.influence",
    "level": ".topography",
    "load_scene": ".pipeline.sweep.scene",
    "love_coefficients": ".contact.influence",
    "make_params": ".pipeline.law.params",
    "Materials": ".contact.materials",
    "normal_operator": ".contact.influence",
    "NormalResult": ".contact.normal",
    "read_surface": ".topography",
    "roughness": ".topography",
    "Scene": ".pipeline.sweep.scene",
    "self_affine": ".topography",
    "sigma_y_from_hardness": ".contact.materials",
    "sliding_study": ".studies.sliding_study",
    "sliding_sweep": ".studies.sliding",
    "solve_normal": ".contact.normal",
    "solve_normal_pair": ".contact.normal",
    "solve_tangential": ".contact.tangential",
    "SolverSettings": ".contact.materials",
    "Surface": ".topography",
    "tau_adh_full_sliding": ".contact.tangential",
    "tool_like": ".topography",
    "write_outputs": ".output.report",
}
#: the subpackages, as attributes (``halfspace_calib.pipeline``), imported on first use
_SUBPACKAGES = ("cli", "common", "contact", "output", "pipeline", "studies", "topography")

__all__: list[str] = sorted(_SOURCES, key=str.lower)


__getattr__, __dir__ = lazy_names(__name__, _SOURCES, _SUBPACKAGES)
