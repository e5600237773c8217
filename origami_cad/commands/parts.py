"""The parametric hardware command: ``part`` (``origami_cad.parts``)."""

from __future__ import annotations

import re

from origami_cad.commands._base import FOLDER_HELP, Command, Option, Outputs, moved, register, wrote
from origami_cad.errors import FabricationError, OptionsError

__all__: list[str] = []


@register
class Part(Command):
    """Build a parametric part and write NAME.step and NAME.stl.

    The part's own parameters (mm, degrees) are options of their own: ``--list``
    shows them, e.g. ``part tsa-module --hub-thickness 5``. With ``pattern``, a
    ``tsa-module`` is fitted to ``panel`` and a ``blocker`` to ``crease``.

    From Python, ``params`` gives them as values; the parts are
    :mod:`origami_cad.parts`.
    """

    NAME, EXTRA, ARGS = "part", True, ("name", "folder", "params")
    OPTIONS = (
        Option(
            "name",
            help="the part: tsa-module, ring-rail, blocker or driver-adapter (--list)",
            nargs="?",
            positional=True,
        ),
        Option("folder", help=FOLDER_HELP, flag="--output", short="-o"),
        Option("params", "object", "the part's own parameters", flag=""),
        Option("list", "flag", "list the parts and their parameters"),
        Option("pattern", help="design or pattern file the part is made for"),
        Option("panel", help="panel label the tsa-module is fitted to (e.g. c0r1s2)"),
        Option(
            "crease",
            "int",
            "crease (edge index) the blocker is fitted to",
            min=0,
            max=10**9,
            metavar="EDGE",
        ),
    )

    def inputs(self, a):
        return [a.pattern] if a.pattern else []

    def outputs(self, a):
        return [], [a.folder] if a.folder and a.name and not a.list else []

    def prepare(self, a):
        from origami_cad.parts import parse_part_options

        if a.extra:  # the part's own --name value options, from the command line
            a.params = parse_part_options(a.extra)
        if a.name and not a.list and not a.folder:
            raise OptionsError("give the output folder with -o DIR")
        super().prepare(a)

    def run(self, a) -> Outputs:
        from origami_cad.fabrication.exports import export_part
        from origami_cad.parts import build_part, parts_listing

        if a.list or not a.name:
            return Outputs(messages=[parts_listing()])
        try:
            part = build_part(a.name, a.params, pattern=a.pattern, panel=a.panel, crease=a.crease)
        except FabricationError as exc:  # a parameter as the command line gave it: --reach
            if not a.extra:
                raise
            raise FabricationError(_as_typed(str(exc), a.params)) from None
        with self.stage(a) as stage:
            files = moved(export_part(part, stage, a.name), stage, a.folder)
        volume = f"{part.volume / 1000:.2f} cm3"
        return Outputs(
            files=files,
            numbers=[(f"{a.name}: volume", volume)],
            messages=[f"{a.name}: volume {volume}; {wrote(a.folder, files)}"],
        )


def _as_typed(message: str, given: dict) -> str:
    """``parameter guide_distance`` as the command line gave it, ``--guide-distance``.

    >>> _as_typed("part x: parameter reach (mm): expected ...", {"reach": "-1"})
    'part x: --reach (mm): expected ...'
    """

    def flag(m: re.Match) -> str:
        return "--" + m[1].replace("_", "-") if m[1] in given else m[0]

    return re.sub(r"\bparameter (\w+)", flag, message)
