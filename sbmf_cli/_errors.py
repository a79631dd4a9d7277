"""Bad input that names parameters: Python names for a library's caller, flags for a command's."""

from __future__ import annotations

import signal

__all__ = ["ParameterError", "Worded", "interrupted_line"]


def _render(template, names, flags, python):
    text = template
    for name in names:
        text = text.replace("{" + name + "}", flags.get(name) or python.get(name, name))
    return text


def _rebuild(template, names, python):
    return ParameterError(template, *names, python=python)


class Worded(str):
    """A text (a problem, a hint) naming parameters, worded for whoever reads it.

    As :class:`ParameterError`, but a string: each parameter stands as ``{name}`` in
    ``template``; the string reads with the Python names, :meth:`render` with a command's flags
    (:meth:`sbmf_cli.Console.text` applies it).
    """

    template: str
    names: tuple
    python: dict

    def __new__(cls, template, *names, python=None):
        python = dict(python or {})
        obj = super().__new__(cls, _render(str(template), names, {}, python))
        obj.template, obj.names, obj.python = str(template), tuple(names), python
        return obj

    def __getnewargs__(self):
        return (self.template, *self.names)

    def render(self, flags):
        """The text with each parameter as ``flags[name]`` (its Python form where missing)."""
        return _render(self.template, self.names, flags, self.python)


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
        return _render(self.template, self.names, flags, self.python)

    def __reduce__(self):  # the error crosses process boundaries with its names
        return _rebuild, (self.template, self.names, self.python)


def interrupted_line(prog, what, signum):
    """The one line an interrupted command prints (stderr)."""
    return (
        f"{prog}: interrupted by {signal.Signals(signum).name} during {what}; the output folder "
        "was not written (an earlier output there is unchanged)"
    )
