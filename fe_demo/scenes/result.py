"""What a scene returns: :class:`SceneResult`, and the die-contact profile of a model's state."""

from dataclasses import dataclass, field

import numpy as np

from ..output.figures import die_profile_figure, force_stroke_figure
from ..solver.model import FormingModel

__all__ = ["SceneResult", "contact_profile"]


@dataclass
class SceneResult:
    """Outcome of a scene.

    Attributes
    ----------
    converged : bool
        True if every increment was accepted.
    message : str
    history : dict of str -> ndarray
        One entry per accepted increment (see the scene functions for columns).
    model : FormingModel
        The model at its last accepted state.
    wall_time : float
        Seconds.
    snapshots : list of dict
        Nodal/element fields at selected increments (for VTU output).
    """

    converged: bool
    message: str
    history: dict
    model: FormingModel
    wall_time: float
    snapshots: list = field(default_factory=list)
    info: dict = field(default_factory=dict)

    def figures(self, title=None):
        """The run's figures, for a notebook (nothing written; not held by pyplot).

        ``{"force_stroke.png": Figure, "die_profile.png": Figure}`` (the force-stroke plot only
        with an accepted increment): the files ``fe-demo`` writes for a run.
        """
        title = title or str(self.info.get("scene", "run"))
        figs = {}
        if self.history:
            figs["force_stroke.png"] = force_stroke_figure([self.history], [title], title=title)
        figs["die_profile.png"] = die_profile_figure(contact_profile(self.model), title=title)
        return figs


def contact_profile(model):
    """Die-contact data of the accepted state, sorted by radius.

    Returns a dict with ``r`` (m), ``p``, ``tau`` (Pa, shear on the workpiece
    opposing outward flow is positive), ``p_hist`` (committed, Pa), ``status`` and
    ``height_reduction`` (the fraction of the initial height at which the profile is taken).
    """
    ev = model.accepted
    nodes = model.contact.nodes
    r = model.x[nodes, 0]
    red = float(model.height_reduction)
    if ev is None:
        z = np.zeros(nodes.size)
        return {
            "r": r,
            "p": z,
            "tau": z,
            "p_hist": z,
            "status": z.astype(np.int8),
            "height_reduction": red,
        }
    order = np.argsort(r)
    return {
        "height_reduction": red,
        "r": r[order],
        "p": ev.p[order],
        "tau": ev.tau[order],
        "p_hist": np.asarray(model.contact.state.p_hist)[order],
        "status": ev.status[order],
    }
