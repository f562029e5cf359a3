"""Simulation from Python: stepping in C++ (the same bits however it is called), the state as
read-only NumPy copies in SI units, the energy ledger, and refusals of bad arguments."""

import math

import numpy as np
import pytest

import granular


@pytest.fixture
def sim(bed_path):
    with granular.Simulation(granular.load_scene(bed_path)) as s:
        yield s


def test_a_new_simulation_is_at_rest_at_time_zero(sim):
    assert sim.time == 0.0
    assert sim.step_count == 0
    assert sim.particle_count == 120
    assert sim.time_step == pytest.approx(1.7e-4, rel=1e-12)


def test_the_state_arrays_have_their_shapes_and_units(sim):
    n = sim.particle_count
    for name in ("positions", "velocities", "spins"):
        a = getattr(sim, name)
        assert a.shape == (n, 3) and a.dtype == np.float64, name
    for name in ("radii", "masses"):
        a = getattr(sim, name)
        assert a.shape == (n,) and a.dtype == np.float64, name
    # Each sphere's mass is its volume times the density (500 kg/m³).
    volume = 4.0 / 3.0 * math.pi * sim.radii**3
    np.testing.assert_allclose(sim.masses, 500.0 * volume, rtol=1e-12)
    assert np.all((sim.radii >= 0.030) & (sim.radii <= 0.035))
    assert np.all(sim.positions >= 0.0) and np.all(sim.positions[:, :2] <= 0.4)


def test_the_arrays_are_read_only_copies_that_outlive_steps(sim):
    before = sim.positions
    with pytest.raises(ValueError):
        before[0, 0] = 1.0
    kept = before.copy()
    sim.step(50)
    np.testing.assert_array_equal(before, kept)  # a copy: the steps do not move it
    assert not np.array_equal(sim.positions, kept)


def test_free_fall_follows_gravity(sim):
    # Before any contact (the grid's spheres are apart), each sphere falls freely: over 20 steps
    # its vertical velocity changes by g t, to the integrator's rounding.
    v0 = sim.velocities
    sim.step(20)
    t = sim.time
    assert t == pytest.approx(20 * 1.7e-4, rel=1e-12)
    np.testing.assert_allclose(sim.velocities[:, 2] - v0[:, 2], -9.81 * t, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(sim.velocities[:, :2], v0[:, :2], atol=1e-15)


def test_advance_to_lands_on_the_time_exactly(sim):
    sim.advance_to(0.0123)
    assert sim.time == 0.0123
    sim.advance_to(0.0123)  # already there: nothing to do
    assert sim.time == 0.0123


def test_one_call_and_many_give_the_same_bits(bed_path):
    scene = granular.load_scene(bed_path)
    with granular.Simulation(scene) as a, granular.Simulation(scene) as b:
        a.step(300)
        for _ in range(300):
            b.step()
        assert a.state_hash == b.state_hash
        assert a.step_count == b.step_count == 300


def test_the_ledger_closes_while_the_bed_lands(sim):
    start = sim.energy()
    sim.advance_to(0.3)
    e = sim.energy()
    assert set(start) == set(e)
    for key in ("kinetic_translational_J", "gravity_work_J", "energy_total_J"):
        assert key in e
    assert e["gravity_work_J"] > 1.0  # the spheres fell
    assert any(k.startswith("dissipated_") and v > 0 for k, v in e.items())
    drift = e["energy_total_J"] - start["energy_total_J"]
    assert abs(drift) < 0.02 * e["gravity_work_J"]


@pytest.mark.parametrize("n", [0, -3])
def test_a_step_count_below_one_is_refused(sim, n):
    with pytest.raises(ValueError, match="n must be >= 1"):
        sim.step(n)


@pytest.mark.parametrize("n", [1.5, "3", None])
def test_a_step_count_that_is_not_an_integer_is_a_type_error(sim, n):
    with pytest.raises(TypeError):
        sim.step(n)


@pytest.mark.parametrize("t", [math.nan, math.inf, -math.inf])
def test_a_time_that_is_not_finite_is_refused(sim, t):
    with pytest.raises(ValueError, match="finite"):
        sim.advance_to(t)


def test_a_time_before_the_clock_is_refused(sim):
    sim.advance_to(0.01)
    with pytest.raises(granular.ConfigError, match="before the clock"):
        sim.advance_to(0.005)
    assert sim.time == 0.01


def test_a_closed_simulation_refuses_every_use(bed_path):
    s = granular.Simulation(granular.load_scene(bed_path))
    s.close()
    for use in (
        lambda: s.step(),
        lambda: s.advance_to(1.0),
        lambda: s.positions,
        lambda: s.time,
        lambda: s.energy(),
    ):
        with pytest.raises(RuntimeError, match="closed"):
            use()
    s.close()  # closing again does nothing, as a file's close does


def test_a_time_step_above_the_stable_limit_is_refused_with_its_key(bed_text, write_scene):
    path = write_scene(bed_text.replace("time_step = 1.7e-4", "time_step = 0.5"))
    with pytest.raises(granular.SceneError, match=r"simulation\.time_step = 0\.5: .*stable limit"):
        granular.load_scene(path)


def test_a_particle_outside_the_box_is_refused_naming_its_file_and_row(write_scene, tmp_path):
    scene = """
[material]
density = 500.0
[simulation]
time_step = 1e-4
[box]
min = [0.0, 0.0, 0.0]
max = [0.4, 0.4, 1.0]
[[particles]]
type = "csv"
file = "particles.csv"
[[stages]]
name = "fall"
max_time = 0.1
"""
    (tmp_path / "particles.csv").write_text("x,y,z,r\n0.2,0.2,0.5,0.03\n0.2,5.0,0.5,0.03\n")
    with pytest.raises(granular.SceneError, match=r"particles\.csv:3: row 2 .* outside the box"):
        granular.load_scene(write_scene(scene))
