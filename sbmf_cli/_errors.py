"""Bad input that names parameters: Python names for a library's caller, flags for a command's."""

from __future__ import annotations

__all__ = ["ParameterError"]


def _rebuild(template, names, python):
    return ParameterError(template, *names, python=python)


class ParameterError(ValueError):
    """Bad input naming one or more parameters, worded for whoever passed them.

    The message is a template in which each named parameter stands as ``{name}``, ``name`` its
    Python name. ``str(err)`` reads with the Python names (what a library's caller typed); a
    command reads it with its own flags (:meth:`render`, which :meth:`sbmf_cli.Console.error`
    applies), so that the same check speaks ``lambda_s`` to a Python user and ``--lambda-s`` to
    a command-line user. Only the declared names are replaced: braces in the rest of the text (a
    path, a repr) are kept as they are.

    Parameters
    ----------
    template : str
        The message, each parameter as ``{name}``.
    *names : str
        The parameters the message names.
    python : dict, optional
        How a name reads for a Python caller where the bare name would not do
        (``{"force": "force=True"}``).
    """

    def __init__(self, template, *names, python=None):
        self.template = str(template)
        self.names = tuple(names)
        self.python = dict(python or {})
        super().__init__(self.render({}))

    def render(self, flags):
        """The message with each parameter as ``flags[name]`` (its Python form where missing)."""
        text = self.template
        for name in self.names:
            text = text.replace("{" + name + "}", flags.get(name) or self.python.get(name, name))
        return text

    def __reduce__(self):  # the error crosses process boundaries with its names
        return _rebuild, (self.template, self.names, self.python)
