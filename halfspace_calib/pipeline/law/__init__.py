"""The law's forms and their acceptance: the fits of both branches, their held-out errors and the parameter file.

- :mod:`.fit`, :mod:`.lsq`, :mod:`.fit_data`, :mod:`.alpha_bound`: the fits of Eqs. 24-25
- :mod:`.first_table`, :mod:`.reload_table`: the tabulated forms' fits
- :mod:`.forms`: each form of each branch as a record; the choice by held-out error
- :mod:`.heldout`, :mod:`.law_checks`: the acceptance and the law's checks
- :mod:`.params`: the parameter file record

Imports nothing of the other parts of :mod:`halfspace_calib.pipeline`.
"""
