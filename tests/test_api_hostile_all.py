"""Every public call of the curated API (``origami_cad.__all__``) and of
``origami_cad.parts``, one argument at a time replaced by a hostile value (NaN,
infinity, negative, zero, huge, text, bytes, None, empty, a wrong type), returns or
raises an ``origami_cad.errors`` type in one line, within a time bound; never a bare
Python error or a call that does not return.

The table below starts each call from arguments that work (checked first); the suite
tries a small budget per call, ``make fuzz`` (``ORIGAMI_FUZZ_EXAMPLES``) many more."""

from __future__ import annotations

import inspect
import math
import os
import signal
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import origami_cad.parts as parts
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import origami_cad as oc
from origami_cad.design.search import SearchSettings
from origami_cad.errors import ExtraError, OrigamiCadError

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
MOUNTAIN = (
    Path(__file__).parent / "data" / "pygamix" / "descriptionData" / "f-mountain-big-fix-new.json"
)
#: no hostile call may use more CPU time than this, s (CPU, not wall: a loaded machine's
#: other work does not count against the call)
BOUND_S = 30
_EXAMPLES = int(os.environ.get("ORIGAMI_FUZZ_EXAMPLES", "0"))
BUDGET = settings(
    max_examples=_EXAMPLES or 12,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)

HOSTILE = [
    math.nan, math.inf, -math.inf, -1.0, 0, -1e-300, 1e300, 10**12, "x", "", b"x", None, [],
    {}, (), True, object(), [[math.nan]], [1.0, "a"], np.array([math.nan]),
]  # fmt: skip

V = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]
E = [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]]


@contextmanager
def bounded(seconds: int = BOUND_S):
    def _late(signum, frame):
        raise TimeoutError(f"a hostile call ran past {seconds} s of CPU time")

    old = signal.signal(signal.SIGPROF, _late)
    signal.setitimer(signal.ITIMER_PROF, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.signal(signal.SIGPROF, old)


def _fields(cls) -> dict:
    """A dataclass's default instance as keyword arguments."""
    default = cls()
    return {k: getattr(default, k) for k in inspect.signature(cls).parameters}


def _calls(tmp: Path) -> dict:
    cp = oc.CreasePattern(V, E, "BBBBV")
    small = oc.miura_design(2, 2, 20.0, 20.0, 60.0)
    miura = oc.load_design(EXAMPLES / "miura_6x4.toml")
    mountain = oc.read_pattern(MOUNTAIN)
    bench = (np.array([0.0, 2.0, 4.0, 6.0]), np.array([0.0, 1.0, 1.5, 1.8]))  # mm, N
    route = oc.load_route(EXAMPLES / "miura_route.toml", miura.pattern)
    task = oc.ArmTask(points=[[250.0, 0.0], [120.0, 60.0], [50.0, 133.3]], vectors=3, samples=10)
    return {
        "ArmTask": (oc.ArmTask, {"points": task.points.tolist(), "weights": [1.0],
                                 "alpha": 120.0, "vectors": 3, "samples": 10, "start": (0, 0)}),
        "CreasePattern": (oc.CreasePattern, {"vertices": V, "edges": E, "assignments": "BBBBV",
                                             "fold_angles": None, "faces": None, "holes": (),
                                             "face_labels": None, "metadata": None,
                                             "tolerance": None}),
        "Design": (oc.Design, {"pattern": cp, "tg": None, "kind": "file", "source": None}),
        "FabricationParams": (oc.FabricationParams, _fields(oc.FabricationParams)),
        "FoldedState": (oc.FoldedState, {"p": 0.5, "coords": np.zeros((4, 3)),
                                         "fold_angles": np.zeros(5), "strain": 0.0}),
        "RouteSpec": (oc.RouteSpec, {"tsa": route.tsa, "strings": route.strings,
                                     "thickness": 2.2, "step": 0.03, "max_turns": 20.0,
                                     "p0": 0.0, "p_max": None, "take_up": 0.1,
                                     "fixed_panel": None, "fabrication": None}),
        "SimulationParams": (oc.SimulationParams, _fields(oc.SimulationParams)),
        "TGDesign": (oc.TGDesign, {"lengths": (40.0, 30.0, 30.0), "shape_angles": (60.0, 60.0),
                                   "entry_flag": 1, "unit_width": 36.0, "copies": 3,
                                   "start": (0.0, 0.0), "hypar_base": False}),
        "TSAParams": (oc.TSAParams, _fields(oc.TSAParams)),
        "design_arm": (oc.design_arm, {"task": task, "settings": SearchSettings(
            runs=1, popsize=4, max_generations=1), "executor": None, "progress": None,
            "check_strings": False}),
        "calibrate": (oc.calibrate, {"cp": mountain, "route": None, "runs": [bench],
                                     "materials": None, "fit": ("hole_friction",), "step": 3.0,
                                     "max_evaluations": 2, "names": None,
                                     "tendons": (2,)}),
        "fold": (oc.fold, {"design": small, "p": 0.5, "method": "auto", "params": None}),
        "fold_design": (oc.fold_design, {"design": small, "p": 0.5}),
        "fold_sequence": (oc.fold_sequence, {"design": small, "ratios": [0.1, 0.5]}),
        "fold_states": (oc.fold_states, {"design": small, "ratios": [0.1, 0.5], "params": None}),
        "load_design": (oc.load_design, {"path": EXAMPLES / "miura_6x4.toml", "unit": None,
                                         "scale": None, "width": None, "tolerance": None}),
        "load_route": (oc.load_route, {"path": EXAMPLES / "miura_route.toml",
                                       "cp": miura.pattern}),
        "load_task": (oc.load_task, {"path": EXAMPLES / "arm_task.toml"}),
        "miura_design": (oc.miura_design, {"rows": 2, "columns": 2, "panel_length": 20.0,
                                           "panel_width": 20.0, "sector_angle": 60.0,
                                           "entry_flag": 1}),
        "place_on_table": (oc.place_on_table, {"cp": small.pattern,
                                               "coords": oc.fold(small, 0.5).coords}),
        "plan_panels": (oc.plan_panels, {"source": small, "params": None, "bed": (200, 200)}),
        "read_pattern": (oc.read_pattern, {"path": EXAMPLES / "data" / "boat.dxf",
                                           "scale": None, "width": None, "tolerance": None}),
        "simulate_dcqc": (oc.simulate_dcqc, {"design": miura, "route": route, "max_dp": 0.05,
                                             "hole_friction": 0.0}),
        "tg_design": (oc.tg_design, {"vectors": [[40, 0], [30, 25], [30, -10]],
                                     "fold_ratio": 0.5, "entry_flag": 1, "title": ""}),
        "to_mjcf": (oc.to_mjcf, {"source": EXAMPLES / "miura_6x4.toml", "routes": (),
                                 "params": None, "gravity": 9810.0, "friction": None,
                                 "timestep": 0.0005, "contact": None}),
        "write_fold": (oc.write_fold, {"cp": cp, "path": tmp / "x.fold", "frames": ()}),
        "write_pattern": (oc.write_pattern, {"cp": cp, "path": tmp / "x.svg", "fmt": None}),
        "BlockerParams": (parts.BlockerParams, _fields(parts.BlockerParams)),
        "DriverAdapterParams": (parts.DriverAdapterParams, _fields(parts.DriverAdapterParams)),
        "RingRailParams": (parts.RingRailParams, _fields(parts.RingRailParams)),
        "TSAModuleParams": (parts.TSAModuleParams, _fields(parts.TSAModuleParams)),
        "ring_anchor_points": (parts.ring_anchor_points, {"params": None}),
        "parse_part_options": (parts.parse_part_options, {"tokens": ["--angle", "30"]}),
        "build_part": (parts.build_part, {"name": "blocker", "values": None, "pattern": None}),
        "blocker_frame": (parts.blocker_frame, {"pattern": small.pattern, "crease": 2}),
        "TSAModule": (parts.TSAModule, {"params": None, "plan": None, "panel": None}),
        "to_pyvista": (oc.to_pyvista, {"obj": small.pattern, "pattern": None, "coords": None,
                                       "frame": -1}),
    }  # fmt: skip


@pytest.fixture(scope="module")
def calls(tmp_path_factory):
    return _calls(tmp_path_factory.mktemp("hostile"))


NAMES = list(_calls(Path("/nonexistent")).keys())


#: the first calls (in NAMES' order) to run the bar-and-hinge solver's compiled kernels: numba
#: compiles them at their first use after an install (then caches them on disk), 30 s of CPU
#: and more on a fresh clone. That one-time cost is not the call's work: it is paid before
#: the bounded call, which then measures the call itself (and the hostile ones after it).
COMPILES_KERNELS = ("calibrate",)


@pytest.mark.parametrize("name", NAMES)
def test_the_good_call_works(calls, name):
    func, good = calls[name]
    if name in COMPILES_KERNELS:
        func(**good)
    with bounded():
        try:
            func(**good)
        except ExtraError as exc:  # to_pyvista without the viz extra
            pytest.skip(str(exc))


@pytest.mark.parametrize("name", NAMES)
@BUDGET
@given(data=st.data())
def test_one_hostile_argument_raises_only_our_errors(calls, name, data, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # a hostile path ("x") lands here, not in the repository
    func, good = calls[name]
    key = data.draw(st.sampled_from(sorted(good)), label="argument")
    value = data.draw(st.sampled_from(HOSTILE), label="value")
    with bounded():
        try:
            func(**{**good, key: value})
        except OrigamiCadError as exc:
            assert "\n" not in str(exc), str(exc)
        except Exception as exc:  # the one line a reader needs, not the table
            shown = f"{value!r}"[:40]
            pytest.fail(f"{name}({key}={shown}): {type(exc).__name__}: {exc}", pytrace=False)


def test_the_table_covers_the_curated_api_and_the_parts():
    """Each public callable is in the table, or named here with why it is not."""
    elsewhere = {
        # covered by tests/test_api_hostile.py, or need a built fabrication/shape
        "simulate": "test_api_hostile.py: test_simulate_refuses_before_any_work",
        "fabricate": "plan_panels takes the same source, params and bed first",
        "write_fabrication": "test_api_hostile.py: into a file",
        "Fabrication": "made by fabricate only",
        "Calibration": "made by calibrate only",
        "export_step_tree": "a build123d shape (test_parts)",
        "plan_routes": "test_plan_route_small.py",
        "show": "viz, headless in test_viz_pyvista.py",
        "display_mode": "no arguments",
        "RingRail": "test_api_hostile.py: test_parts_refuse_hostile_numbers",
        "Blocker": "test_api_hostile.py: test_parts_refuse_hostile_numbers",
        "DriverAdapter": "test_api_hostile.py: test_parts_refuse_hostile_numbers",
        "OrigamiPart": "the parts' base class",
        "PartSpec": "a registry record",
        "Placement": "an enum",
        "blocker": "build_part('blocker') calls it",
        "driver_adapter": "the DriverAdapterParams row checks its values",
        "ring_rail": "the RingRailParams row checks its values",
        "tsa_module": "the TSAModuleParams row checks its values",
        "parts_listing": "no arguments",
        "with_fold_path": "test_api_probe.py: the stages' entry points",
    }
    public = {
        n
        for mod in (oc, parts)
        for n in mod.__all__
        if callable(getattr(mod, n)) and not n.isupper() and not n.startswith("_")
    }
    missing = public - set(NAMES) - set(elsewhere)
    assert not missing, sorted(missing)


#: Values the sampled test above seldom draws, each a class of failure once found: an
#: integer past a float's range (``float()`` raises OverflowError, not ValueError) and a
#: callback that cannot take the arguments it is called with.
EVERY_ARGUMENT = [10**400, lambda: None]


@pytest.mark.parametrize("name", NAMES)
def test_every_argument_refuses_a_huge_integer_and_a_wrong_callback(calls, name, tmp_path):
    func, good = calls[name]
    failures = []
    for key in sorted(good):
        for value in EVERY_ARGUMENT:
            with bounded():
                try:
                    func(**{**good, key: value})
                except OrigamiCadError as exc:
                    assert "\n" not in str(exc), str(exc)
                except Exception as exc:
                    failures.append(f"{key}={value!r:.30}: {type(exc).__name__}: {exc!s:.100}")
    assert not failures, "\n".join(failures)
