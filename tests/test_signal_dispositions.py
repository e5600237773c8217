"""The signal handling gives back whatever SIGINT disposition it found, and a signal the
process ignores (a background job's SIGINT, ``nohup ... &``) is not turned into an
interrupt by the blocks that hold signals."""

from __future__ import annotations

import os
import signal

import pytest

from origami_cad._signals import Interrupted, finishing, handle_signals, interrupted
from origami_cad.drive.errors import hold_ctrl_c


def _custom(signum, frame) -> None:
    """A program's own handler (never called here)."""


DISPOSITIONS = {
    "ignored": signal.SIG_IGN,
    "default": signal.SIG_DFL,
    "python": signal.default_int_handler,
    "custom": _custom,
}


@pytest.fixture(params=sorted(DISPOSITIONS))
def disposition(request):
    """SIGINT set to each disposition a test run may inherit or a program may install; the
    run's own is restored afterwards."""
    wanted = DISPOSITIONS[request.param]
    previous = signal.signal(signal.SIGINT, wanted)
    try:
        yield wanted
    finally:
        signal.signal(signal.SIGINT, signal.SIG_DFL if previous is None else previous)


@pytest.mark.parametrize(
    "block", [handle_signals, finishing, hold_ctrl_c], ids=lambda f: f.__name__
)
def test_every_block_restores_the_sigint_disposition_it_found(disposition, block):
    with block():
        inside = signal.getsignal(signal.SIGINT)
    assert signal.getsignal(signal.SIGINT) is disposition
    if block is handle_signals:  # the command line's handler, whatever was inherited
        assert inside is not disposition and callable(inside)
    if disposition is signal.SIG_IGN and block is not handle_signals:
        assert inside is signal.SIG_IGN  # an ignored signal stays ignored within


def test_an_ignored_sigint_is_not_noted_as_an_interrupt():
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with finishing():
            os.kill(os.getpid(), signal.SIGINT)
        assert interrupted() is None  # no output is refused because of it
    finally:
        signal.signal(signal.SIGINT, previous)


def test_a_handled_sigint_within_finishing_is_noted_and_delivered_later(python_sigint):
    with pytest.raises(Interrupted), handle_signals():
        with finishing():
            os.kill(os.getpid(), signal.SIGINT)
        assert interrupted() == signal.SIGINT  # the block's outputs completed; noted
        raise Interrupted(interrupted())
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_hold_ctrl_c_delivers_a_held_sigint_to_pythons_handler(python_sigint):
    with pytest.raises(KeyboardInterrupt):
        with hold_ctrl_c():
            os.kill(os.getpid(), signal.SIGINT)
            held = True  # reached: the signal waits for the end of the block
    assert held
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
