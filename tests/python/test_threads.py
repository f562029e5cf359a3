"""Stepping runs in C++ with the GIL released: another Python thread runs meanwhile, a read of
the simulation from it is refused while it steps, and Ctrl-C stops a long advance_to between two
steps, leaving a whole state that steps on."""

import os
import signal
import sys
import threading
import time

import numpy as np
import pytest

import granular


@pytest.fixture
def sim(bed_path):
    with granular.Simulation(granular.load_scene(bed_path)) as s:
        yield s


@pytest.fixture
def no_thread_switches():
    """Python switches threads only where one blocks or releases the GIL."""
    before = sys.getswitchinterval()
    sys.setswitchinterval(100.0)
    yield
    sys.setswitchinterval(before)


def test_another_thread_runs_while_the_simulation_steps(sim, no_thread_switches):
    counted = [0]
    done = threading.Event()

    def count():
        while not done.is_set():
            counted[0] += 1
            time.sleep(0.001)  # releases the GIL

    helper = threading.Thread(target=count)
    helper.start()
    try:
        before = counted[0]
        sim.advance_to(0.2)  # about a thousand steps
        during = counted[0] - before
    finally:
        done.set()
        helper.join()
    # With the GIL held through the call, and no switch between threads otherwise, the helper
    # could not have counted while it ran.
    assert during > 0


def test_a_read_from_another_thread_while_stepping_is_refused(sim):
    refused = []
    started = threading.Event()

    def read():
        started.wait()
        time.sleep(0.02)
        try:
            sim.positions
        except RuntimeError as e:
            refused.append(str(e))

    helper = threading.Thread(target=read)
    helper.start()
    started.set()
    sim.advance_to(2.0)  # some ten thousand steps
    helper.join()
    assert refused and "stepping on another thread" in refused[0]


@pytest.mark.parametrize("how", ["advance_to", "step"])
def test_ctrl_c_stops_between_two_steps_and_the_run_goes_on(sim, how):
    def interrupt():
        time.sleep(0.05)
        os.kill(os.getpid(), signal.SIGINT)

    helper = threading.Thread(target=interrupt)
    helper.start()
    with pytest.raises(KeyboardInterrupt):
        if how == "advance_to":
            sim.advance_to(100.0)  # minutes, were it not stopped
        else:
            sim.step(10**7)
    helper.join()
    stopped = sim.time
    assert 0.0 < stopped < 100.0
    assert np.all(np.isfinite(sim.positions))
    sim.advance_to(stopped + 0.01)
    assert sim.time == stopped + 0.01
