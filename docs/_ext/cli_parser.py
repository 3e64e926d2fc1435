"""The ``shakedown`` parser for sphinx-argparse, with its help texts made safe for reStructuredText.

sphinx-argparse renders every help string as reStructuredText, where ``|ft|`` (an absolute value in the
help of ``--amplitude``) would be a substitution reference; the text printed by ``--help`` is unchanged.
"""

import argparse

from core.command.cli import build_parser

_RST = str.maketrans({"|": r"\|", "*": r"\*", "`": r"\`"})


def _escape(parser: argparse.ArgumentParser) -> None:
    for text in ("description", "epilog"):
        if getattr(parser, text):
            setattr(parser, text, getattr(parser, text).translate(_RST))
    for action in parser._actions:
        if action.help and action.help is not argparse.SUPPRESS:
            action.help = action.help.translate(_RST)
        if isinstance(action, argparse._SubParsersAction):
            for choice in action._choices_actions:
                if choice.help:
                    choice.help = choice.help.translate(_RST)
            for sub in action.choices.values():
                _escape(sub)


def parser() -> argparse.ArgumentParser:
    """:func:`core.command.cli.build_parser`, its help texts escaped for reStructuredText."""
    p = build_parser()
    _escape(p)
    return p
