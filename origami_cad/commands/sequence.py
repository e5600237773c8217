"""The sequence command: ``sequence`` (fold-ratio keyframes to TSA turns, for ``drive``)."""

from __future__ import annotations

from pathlib import Path

from origami_cad._fileio import atomic_path
from origami_cad._names import one_line
from origami_cad._toml import load_toml
from origami_cad.commands._base import Command, Option, Outputs, register, wrote
from origami_cad.commands.drive import parse_ids
from origami_cad.errors import DriveError, OptionsError

__all__: list[str] = []

_IDS = Option("ids", "object", "servo IDs, e.g. 1,2 (one per route)", parse=parse_ids)
RATE = 10.0  # Hz: the command rate of a generated sequence, unless given


def _sequence_header(a, routes) -> str:
    """The comment lines of a generated sequence file: where it comes from, how to remake it."""
    argv = " ".join(
        [
            "origami-cad sequence", str(a.design), str(routes[0]), "-o", str(a.output),
            *(f"--more-routes {r}" for r in routes[1:]),
            f"--model {a.model}",
            *([f"--fixed-panel {a.fixed_panel}"] if a.fixed_panel else []),
            "--ids " + ",".join(map(str, a.ids)),
            "--keyframes", *map(str, a.keyframes),
        ]
    )  # fmt: skip
    return (
        f"# Generated from the {a.model} model of {one_line(a.design)} folded by its strings, "
        "not typed by\n"
        f"# hand: each TSA's mapping is the fold ratio its route's strings reach against the\n"
        "# contraction of its onboard TSA (every keyframe's fold ratio included), so drive\n"
        "# commands the turns the model needed. Regenerate with:\n"
        f"#   {one_line(argv)}\n"
    )


def _route_tsa(a, loaded, path, servo: int, at):
    """Fold ``loaded`` by one route: its TSA entry of the sequence, its numbers, the result."""
    from origami_cad.drive.from_model import route_tsa
    from origami_cad.simulation.string_models import fold_by_strings
    from origami_cad.strings import load_route

    spec = load_route(path, loaded.pattern)
    result = fold_by_strings(loaded, spec, a.model, fixed_panel=a.fixed_panel)
    name = Path(path).stem.removesuffix("_route").removeprefix("route_")
    tsa, fig = route_tsa(
        loaded.pattern, spec.tsa, result, at, servo=servo, name=name, points=a.points,
        where=f"{path} ({a.model})", label=f"{Path(path).name}, {a.model} model",
    )  # fmt: skip
    (lo, hi), need = fig["p_range"], ", ".join(f"{v:.2f}" for v in fig["turns_at"])
    numbers = [
        (f"servo {servo}: fold range of its strings", f"p = {lo:.3f} .. {hi:.3f}"),
        (f"servo {servo}: turns at the keyframes", need),
        (f"servo {servo}: largest TSA torque", f"{fig['peak_torque']:.3g} N mm"),
    ]
    return tsa, numbers, result


def _robot_sequence(a) -> Outputs:
    """A robot file and its gait file as the sequence ``drive`` runs (what ``crawl`` writes,
    without the simulated loads): each leg's mapping from the robot's leg model; the gait
    file's ``[sequence]`` table (checked as ``drive`` checks it) unless ``--rate`` or
    ``--repeat`` is given."""
    from origami_cad.crawler.robot import load_gait, load_robot
    from origami_cad.crawler.walk import check_servo_speed, gait_sequence
    from origami_cad.crawler.walk import gait_sequence_header as header
    from origami_cad.drive.sequence import dump_sequence, load_sequence, load_sequence_table

    shown = {o.name: o.shown for o in SequenceCommand.OPTIONS}
    given = [n for n in ("keyframes", "more_routes", "ids", "fixed_panel") if getattr(a, n)]
    given += ["model"] if a.model != "dcqc" else []  # the robot's own leg model is used
    if given:
        raise OptionsError(
            f"{shown[given[0]]}: not with a robot file ({one_line(a.design)}): its gait "
            f"{one_line(a.route)} gives the keyframes and the robot its legs"
        )
    table = {"rate": RATE, "repeat": 1, "current_limit": 1200.0} | load_sequence_table(a.route)
    if "tsa" in load_toml(a.route, DriveError):  # drive runs it too: checked as drive reads it
        load_sequence(a.route)
    rate = a.rate if a.rate is not None else table["rate"]
    repeat = a.repeat if a.repeat is not None else table["repeat"]
    robot = load_gait(a.route, load_robot(a.design))
    check_servo_speed(robot, where=str(a.route))
    argv = f"origami-cad sequence {a.design} {a.route} -o {a.output} --rate {rate:g}"
    seq = gait_sequence(robot, repeat=repeat, rate=rate, current_limit=table["current_limit"])
    text = dump_sequence(seq, header=header(robot, f"{argv} --repeat {repeat}"), layout="gait")
    with atomic_path(a.output) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
        load_sequence(tmp)  # drive reads it: every keyframe reachable within the twist
    return Outputs(
        files=[Path(a.output)],
        numbers=[("keyframes of the gait", f"{len(robot.gait_t)} over {robot.cycle:g} s")],
        messages=[f"{len(robot.legs)} TSA(s) of {one_line(a.design)}; {wrote(a.output)}"],
        result=seq,
    )


@register
class SequenceCommand(Command):
    """Fold-ratio keyframes to TSA turns through a string model: the sequence file ``drive`` runs.

    Each route (``route``, then ``more_routes``: one onboard TSA each, servo IDs
    ``ids``, default 1, 2, ...) folds ``design`` in the DCQC model (``model`` dcqc)
    or the bar-and-hinge simulation (``model`` simulation); the fold ratio
    it reaches against the TSA's turns becomes that TSA's mapping (fold ratio to
    contraction of the onboard TSA model, every keyframe's fold ratio included),
    so ``drive`` commands the turns the model needed. ``keyframes`` are
    ``TIME:P`` or ``TIME:P1,P2,...`` (s, fold ratios, one per route). A pattern
    without a one-parameter folding is measured by its most folded crease
    (max |fold angle| / 180). ``fixed_panel`` holds that panel in every route
    (e.g. a robot's body while one leg folds), instead of each route's own setting.

    With a robot file as ``design`` (``[robot]``, legs with their routes), ``route`` is
    a gait file (``design-gait``'s ``gait.toml``, or any gait ``crawl --gait`` reads):
    its keyframes, checked against the blockers and the servos' speed, become the
    sequence with each leg's mapping from the robot's leg model, as ``crawl`` writes it
    (without the simulated loads); ``keyframes`` and the route options are then not taken.
    """

    NAME, INPUTS, OUTPUT = "sequence", ("design", "route"), "output"
    SUFFIXES, WHAT = (".toml",), "a sequence"
    OPTIONS = (
        Option("keyframes", help="time s : fold ratio (one per route; not with a robot file)",
               nargs="+", metavar="T:P[,P...]"),
        Option("more_routes", help="more TSAs", nargs="+", metavar="ROUTE"),
        Option("model", help="string model", default="dcqc", choices=("dcqc", "simulation")),
        _IDS,
        Option("rate", "float", "command rate (default 10; with a robot file, its gait "
               "file's [sequence] rate)", "Hz", min=0, open_min=True, max=1000),
        Option("repeat", "int", "cycles (default 1; with a robot file, its gait file's)",
               min=1, max=1_000_000),
        Option("points", "int", "mapping points besides the keyframes", default=21, min=2,
               max=1000),
        Option("fixed_panel", help="hold this panel in every route", metavar="PANEL"),
    )  # fmt: skip

    def inputs(self, a):
        return [a.design, a.route, *(a.more_routes or ())]

    def run(self, a) -> Outputs:
        from origami_cad.crawler.robot import is_robot_file
        from origami_cad.drive.from_model import model_sequence, parse_keyframes
        from origami_cad.drive.sequence import dump_sequence, load_sequence
        from origami_cad.pattern.design import load_pattern_source

        if is_robot_file(a.design):
            return _robot_sequence(a)
        if not a.keyframes:
            raise OptionsError("--keyframes: required (unless DESIGN is a robot file)")
        routes = [a.route, *(a.more_routes or [])]
        a.ids = list(a.ids) if a.ids else list(range(1, len(routes) + 1))
        if len(a.ids) != len(routes):
            raise DriveError(f"{len(a.ids)} servo IDs for {len(routes)} routes")
        frames = parse_keyframes(a.keyframes, len(routes))
        loaded = load_pattern_source(a.design)
        tsas, numbers, results = [], [], []
        for k, path in enumerate(routes):
            at = [values[k] for _, values in frames]
            tsa, more, result = _route_tsa(a, loaded, path, a.ids[k], at)
            tsas.append(tsa)
            numbers += more
            results.append(result)
        rate, repeat = RATE if a.rate is None else a.rate, 1 if a.repeat is None else a.repeat
        seq = model_sequence(tsas, frames, rate=rate, repeat=repeat)
        text = dump_sequence(seq, header=_sequence_header(a, routes), layout="model")
        with atomic_path(a.output) as tmp:
            Path(tmp).write_text(text, encoding="utf-8")
            load_sequence(tmp)  # drive reads it: every keyframe reachable within the twist
        return Outputs(
            files=[Path(a.output)],
            numbers=numbers,
            messages=[f"{len(tsas)} TSA(s), {len(frames)} keyframes; {wrote(a.output)}"],
            result=results,
        )
