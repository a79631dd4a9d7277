"""Options every command shares: ``--version``, ``--quiet``, ``--no-progress``, help with defaults."""

from __future__ import annotations

import argparse
import sys
import weakref
from importlib import metadata
from pathlib import Path

__all__ = [
    "DISTRIBUTION",
    "HelpFormatter",
    "add_common_options",
    "add_version",
    "existing_file",
    "flags_of",
    "file_path",
    "parse",
    "print_version",
    "refuse_repeats",
    "version",
]

#: the distribution whose version ``--version`` prints
DISTRIBUTION = "sbmf-friction"


def version():
    """The installed version of the ``sbmf-friction`` distribution (``"unknown"`` if not installed)."""
    try:
        return metadata.version(DISTRIBUTION)
    except metadata.PackageNotFoundError:
        return "unknown (not installed as a distribution)"


class HelpFormatter(argparse.HelpFormatter):
    """Help that shows each option's default unless its help text already states one.

    Flags (``store_true``/``store_false``) are off/on by default and say nothing more; an option
    whose default is ``None`` must state in its help what applies when it is omitted.
    """

    def _get_help_string(self, action):
        text = action.help or ""
        if (
            not action.option_strings
            or "default" in text
            or action.default in (None, argparse.SUPPRESS)
            or isinstance(action.default, bool)
            or action.nargs == 0
        ):
            return text
        return f"{text} (default: %(default)s)"


def add_common_options(parser, *, quiet=True, progress=True):
    """Add ``--quiet`` and/or ``--no-progress`` (see the package docstring).

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The parser (or sub-parser) to add to.
    quiet : bool
        Add ``--quiet`` (hide progress and the summary on stdout).
    progress : bool
        Add ``--no-progress`` (hide only the progress bar).
    """
    if quiet:
        parser.add_argument(
            "--quiet",
            action="store_true",
            help="print no summary and no progress bar (warnings and errors still go to stderr)",
        )
    if progress:
        parser.add_argument(
            "--no-progress", action="store_true", help="hide the progress bar, keep the summary"
        )


def add_version(parser):
    """Add ``--version`` (prints ``<prog> <version>`` and exits 0)."""
    parser.add_argument(
        "--version", action="version", version=f"%(prog)s {version()}", help="print the version"
    )


def print_version(prog, argv=None):
    """Print ``<prog> <version>`` and return True if ``argv`` asks for ``--version``, else False.

    What ``--version`` (:func:`add_version`) prints, before any of the command is imported: a
    command's light entry point (``halfspace_calib.__main__``, ``fe_demo.__main__``) answers it
    without loading NumPy, SciPy or numba. ``argv``: the arguments (``sys.argv[1:]`` if None);
    a ``--version`` after ``--`` is an argument, not the option.
    """
    args = sys.argv[1:] if argv is None else [str(a) for a in argv]
    if "--" in args:
        args = args[: args.index("--")]
    if "--version" not in args:
        return False
    print(f"{prog} {version()}")
    return True


def parse(parser, argv=None):
    """``(args, None)``, or ``(None, exit code)`` where argparse exits.

    argparse exits 2 for a bad option (its message already on stderr) and 0 for ``--help`` and
    ``--version``; a command returns that code instead of raising ``SystemExit``.
    """
    try:
        args, extra = parser.parse_known_args(argv)
        if extra:  # a typo in a subcommand's option: that subcommand's usage, not the top level's
            _subparser(parser, args).error(f"unrecognized arguments: {' '.join(extra)}")
        return args, None
    except SystemExit as exc:
        return None, exc.code if isinstance(exc.code, int) else 2


def _subparser(parser, args):
    """The subcommand parser ``args`` came through, or ``parser`` itself."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            chosen = getattr(args, action.dest, None)
            return parser if chosen is None else action.choices.get(chosen, parser)
    return parser


def flags_of(parser, **renamed):
    """``{Python name: flag}`` of a parser's options: how a command names a parameter.

    Each option's ``dest`` maps to its long flag (the one spelt like the ``dest``, else the first
    long one); ``renamed`` adds the library's names for options whose ``dest`` differs
    (``n_increments="--increments"``). A command gives the map to its :class:`sbmf_cli.Console`,
    which words a :class:`sbmf_cli.ParameterError` with it.
    """
    flags = {}
    for action in parser._actions:
        longs = [s for s in action.option_strings if s.startswith("--")]
        if not longs or action.dest in flags:
            continue
        spelt = "--" + action.dest.replace("_", "-")
        flags[action.dest] = spelt if spelt in longs else longs[0]
    flags.update(renamed)
    return flags


def file_path(text):
    """The argparse ``type`` of a file option: the text; an empty (or blank) value is refused.

    An empty path would read as the working folder (``Path("")`` is ``.``) or, where an option's
    value is tested for truth, as the option not given; argparse reports the error naming the
    option (exit 2).
    """
    if not text.strip():
        raise argparse.ArgumentTypeError("an empty value: give a file path")
    return text


def existing_file(option, path, kind):
    """``Path(path)`` of an option's input file, read before any work.

    ``ValueError`` naming the option and the path where it is no file: ``"<option> <path>: no
    such file"``, or ``"... : a folder, not <kind>"`` (``kind``: what the option takes, e.g.
    ``"a CSV file"``).
    """
    path = Path(path)
    if not path.is_file():
        what = f"a folder, not {kind}" if path.is_dir() else "no such file"
        raise ValueError(f"{option} {path}: {what}")
    return path


class _StoreOnce(argparse._StoreAction):
    """A value option that refuses a second occurrence in one command line."""

    def __call__(self, parser, namespace, values, option_string=None):
        seen = getattr(self, "_seen", None)
        if seen is not None and seen() is namespace:
            raise argparse.ArgumentError(
                self,
                f"given more than once ({getattr(namespace, self.dest)!r}, then {values!r}): "
                "give it once",
            )
        self._seen = weakref.ref(namespace)
        super().__call__(parser, namespace, values, option_string)


def refuse_repeats(parser):
    """Make every value option of ``parser`` (and its subcommands) refuse a repetition.

    argparse keeps the last of ``--opt A --opt B`` and drops ``A`` without a word; after this
    call the command line is refused (exit 2) naming the option. Flags (``store_true``) and
    options that collect (``append``) are left as they are. Returns ``parser``.
    """
    for action in parser._actions:
        if type(action) is argparse._StoreAction:
            action.__class__ = _StoreOnce
        elif isinstance(action, argparse._SubParsersAction):
            for sub in set(action.choices.values()):
                refuse_repeats(sub)
    return parser
