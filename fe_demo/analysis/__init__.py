"""Analyses built on the scenes.

The friction factor from ring tests (:mod:`.ringfit`), the upper-bound ring chart
(:mod:`.ring_chart`), and the law's band carried to the FE result (:mod:`.band`).
"""
