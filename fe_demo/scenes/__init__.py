"""Scenes: cylinder upsetting, ring compression and upset-unload-reload, with their records.

Each scene returns a :class:`SceneResult` whose ``history`` holds one row per accepted
increment; ``converged`` is False (with ``message``) when an increment failed after
all cut-backs, in which case the history ends at the last accepted state. A scene is a
:class:`~fe_demo.scenes.drive.Run` (model, :class:`~fe_demo.scenes.drive.LawSpec`,
:class:`~fe_demo.scenes.drive.RunSettings`) driven through its stages
(:func:`fe_demo.scenes.drive.drive`).
"""

from .drive import LawSpec, Run, RunSettings, drive
from .multistage import run_multistage
from .press import run_ring, run_upsetting
from .result import SceneResult, contact_profile

__all__ = [
    "SceneResult",
    "run_upsetting",
    "run_ring",
    "run_multistage",
    "contact_profile",
    "LawSpec",
    "RunSettings",
    "Run",
    "drive",
]
