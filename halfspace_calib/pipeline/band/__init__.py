"""Several samples and their band: the samples' calibrations, the pooled law and its bootstrap band.

- :mod:`.samples`: the samples (files, patches), their calibrations, the pooled law
- :mod:`.uncertainty`, :mod:`.band_laws`: the bootstrap band and its edge laws

The top of :mod:`halfspace_calib.pipeline`: imports :mod:`..calibration`, :mod:`..sweep`, :mod:`..law`.
"""
