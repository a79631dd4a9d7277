"""The scene, its surfaces, its load levels and sweeps, the effects and the resolution check.

- :mod:`.scene`: :class:`Scene` and :func:`load_scene`; :mod:`.surface_plan`,
  :mod:`.scene_surfaces`, :mod:`.length_scale`, :mod:`.lateral_scale`: its surfaces
- :mod:`.levels`, :mod:`.sweeps`: the load levels (where ``alpha`` changes) and their solves
- :mod:`.effects`, :mod:`.registry`: the optional effects; :mod:`.resolution`: half the grid
- :mod:`.conformity`, :mod:`.hardness`, :mod:`.flattening`: diagnoses and inputs of a scene

Imports :mod:`..law` (the forms the levels are checked with), nothing above.
"""
