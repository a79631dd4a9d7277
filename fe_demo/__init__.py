"""Axisymmetric upsetting and ring-compression models in scikit-fem that use ``frictionlaw``."""

__all__: list[str] = []
