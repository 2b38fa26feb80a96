"""Pops, jitter and teleports (core.checks.spikes): the robust level on gaps and long takes, a
zigzag that is no spike, the root's children following it, jitter of a child after its
parent's, jitter to the last frame, a teleport while the root speeds up."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from gmr_studio.core.checks import CheckSettings, run_checks
from gmr_studio.core.checks.context import CheckData
from gmr_studio.core.checks.spikes import (
    block_noise,
    jitter,
    jittery_blocks,
    noisiest_product,
    pop,
    robust_level,
    teleport,
)
from gmr_studio.core.kinematics.fk import world_positions
from tests.checks_walk import clean_walk
from tests.test_checks import CM, cm, with_translation


def test_robust_level_is_the_median_and_scaled_mad_with_gaps_left_out():
    values = np.array([[1.0, 10.0], [2.0, np.nan], [4.0, 30.0], [np.nan, 20.0], [8.0, 60.0]])
    median, spread = robust_level(values)
    np.testing.assert_allclose(median, [3.0, 25.0])
    # |x - m|: 2, 1, 1, 5 -> 1.5 and 15, 5, 5, 35 -> 10; times 1.4826
    np.testing.assert_allclose(spread, [1.4826 * 1.5, 1.4826 * 10.0])
    same, same_spread = robust_level(values[[0, 2, 4]][:, :1])
    assert (same[0], same_spread[0]) == (4.0, pytest.approx(1.4826 * 3.0))  # 1, 4, 8: |x - 4| 3, 0, 4


def test_the_robust_level_of_a_long_take_is_its_rows_level():
    """100,000 rows of normal noise (mean 3, deviation 2) in two columns, the second shifted
    by a steady drift: the level and spread of each column, to the sampling's precision."""
    rng = np.random.default_rng(9)
    values = 3.0 + 2.0 * rng.normal(size=(100_000, 2))
    values[:, 1] += np.linspace(0.0, 0.1, 100_000)
    median, spread = robust_level(values)
    np.testing.assert_allclose(median, np.median(values, axis=0), atol=0.05)
    np.testing.assert_allclose(spread, [2.0, 2.0], rtol=0.05)


def test_a_two_frame_zigzag_is_no_pop_but_one_frame_knocked_is():
    """Knocked +d then -d: each frame deviates 1.5 d, its neighbour as much (a bend, not a
    spike, by the 1.5 factor); the same d at one frame is a pop."""
    at = 200

    def zigzag(f):
        shift = np.zeros((f.size, 3))
        shift[f == at, 0] = cm(5.0, CM)
        shift[f == at + 1, 0] = -cm(5.0, CM)
        return shift

    def knock(f):
        shift = np.zeros((f.size, 3))
        shift[f == at, 0] = cm(5.0, CM)
        return shift

    pops = CheckSettings(kinds=("pop",))
    walk = clean_walk(120.0, unit=CM)
    assert run_checks(with_translation(walk, "LeftHand", zigzag), pops) == []
    (finding,) = run_checks(with_translation(walk, "LeftHand", knock), pops)
    assert (finding.start, finding.names) == (at, ("LeftHand",))


def test_the_roots_children_knocked_with_it_are_not_named():
    """The Hips knocked for one frame carry every joint: one pop, of the Hips only (their
    children Spine and the thighs follow their parent, joint 0)."""
    motion = clean_walk(120.0, unit=CM)
    translations = motion.translations.copy()
    translations[200, 0, 0] += cm(5.0, CM)
    (finding,) = run_checks(motion.replace(translations=translations), CheckSettings(kinds=("pop",)))
    assert (finding.kind, finding.start, finding.end, finding.names) == ("pop", 200, 200, ("Hips",))
    assert finding.value == pytest.approx(cm(5.0, CM), rel=0.1)


def _shake(rng, scale, a, b):
    def shake(f):
        shift = np.zeros((f.size, 3))
        inside = (f >= a) & (f <= b)
        shift[inside] = rng.normal(scale=scale, size=(inside.sum(), 3))
        return shift

    return shake


def test_a_child_jittering_after_its_parent_is_its_own_finding():
    """The forearm shakes over frames 60-180 (the hand with it: one finding), the hand alone
    over 360-480: a second finding, of the hand, not the first one stretched."""
    rng = np.random.default_rng(3)
    motion = with_translation(clean_walk(120.0, unit=CM), "RightForeArm", _shake(rng, cm(0.5, CM), 60, 180))
    motion = with_translation(motion, "RightHand", _shake(rng, cm(0.5, CM), 360, 480))
    findings = run_checks(motion, CheckSettings(kinds=("jitter",)))
    arm = [f for f in findings if "RightForeArm" in f.names]
    hand = [f for f in findings if f.names == ("RightHand",) or f.names[:1] == ("RightHand",)]
    assert len(arm) == 1 and "RightHand" in arm[0].names
    assert abs(arm[0].start - 60) <= 24 and abs(arm[0].end - 180) <= 24
    assert len(hand) == 1 and abs(hand[0].start - 360) <= 24 and abs(hand[0].end - 480) <= 24


def test_jitter_to_the_end_ends_at_the_last_frame():
    """603 frames at 120 Hz: 25 blocks of 24 frames cover 600 steps, the last block's
    products reach frame 602, the last one."""
    motion = clean_walk(120.0, seconds=603 / 120.0, unit=CM)
    assert motion.n_frames == 603
    rng = np.random.default_rng(5)
    motion = with_translation(motion, "RightHand", _shake(rng, cm(0.5, CM), 300, 602))
    (finding,) = run_checks(motion, CheckSettings(kinds=("jitter",)))
    assert finding.end == 602 and abs(finding.start - 300) <= 24


def test_a_teleport_while_the_root_speeds_up():
    """The root jumps J at step 349 -> 350 and moves J / 3 a frame faster from then on: the
    jump beyond its velocity is J - J / 6, 2.5 times the change of velocity around it (at
    least 2: a teleport)."""
    at, jump = 350, cm(50.0, CM)
    motion = clean_walk(120.0, unit=CM)
    f = np.arange(motion.n_frames)
    translations = motion.translations.copy()
    translations[:, 0, 0] += np.where(f >= at, jump + jump / 3 * (f - at), 0.0)
    (finding,) = run_checks(motion.replace(translations=translations), CheckSettings(kinds=("teleport",)))
    assert (finding.start, finding.end, finding.names) == (at - 1, at, ("Hips",))
    assert finding.value == pytest.approx(jump * 5 / 6, rel=0.05)


def test_jitter_in_a_take_of_one_block():
    """40 frames at 120 Hz: one block of 24 frames, shaken throughout: one finding."""
    motion = clean_walk(120.0, seconds=40 / 120.0, unit=CM)
    rng = np.random.default_rng(11)
    motion = with_translation(motion, "RightHand", _shake(rng, cm(0.5, CM), 0, 39))
    (finding,) = run_checks(motion, CheckSettings(kinds=("jitter",)))
    assert (finding.start, finding.end, finding.names[:1]) == (0, 26, ("RightHand",))


@pytest.mark.parametrize("n_frames", [1, 2, 3, 20])
def test_takes_too_short_to_measure_give_nothing_and_warn_nothing(n_frames):
    """Pops need 3 frames, teleports 4, jitter one block (24 frames at 120 Hz) and 3 more:
    shorter takes give no finding, without numpy's warnings of empty medians."""
    motion = clean_walk(120.0, seconds=n_frames / 120.0, unit=CM)
    assert motion.n_frames == n_frames
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert run_checks(motion, CheckSettings(kinds=("pop", "jitter", "teleport"))) == []


def _still(n_frames: int = 20):
    """The walk's skeleton (its first frames) with every joint at the origin: positions to
    plant exact values in (CheckData of size 1)."""
    motion = clean_walk(120.0, seconds=n_frames / 120.0, unit=CM)
    return motion, np.zeros((n_frames, motion.n_joints, 3))


def test_pop_boundaries_on_exact_values():
    """A spike exactly 1.5 times its larger neighbour pops (at least 1.5); one sideways of
    exactly the span of its neighbours does not (it must exceed it)."""
    motion, p = _still()
    p[2:5, 10, 0] = [0.0, 1.0, -0.25]  # frame 3 deviates 1.125, frame 4 0.75 (span 0.25)
    (finding,) = pop(CheckData(motion, p, 1.0), CheckSettings())
    assert (finding.start, finding.names, finding.value) == (3, ("LeftHand",), 1.125)
    motion, p = _still()
    p[:, 20, 0] = 0.5 * np.arange(20)  # steady along x
    p[8, 20, 1] = 1.0  # sideways at frame 8 by exactly |P_9 - P_7| = 1
    assert pop(CheckData(motion, p, 1.0), CheckSettings()) == []
    p[8, 20, 1] = 1.0 + 1e-9
    assert [f.start for f in pop(CheckData(motion, p, 1.0), CheckSettings())] == [8]


def test_a_teleport_of_exactly_twice_the_change_of_velocity():
    """Steps 0, 0, 0, 2.5, 1, 1...: the jump at step 3 is 2.5 - 0.5 = 2, twice the change of
    velocity around it (1): a teleport (at least twice)."""
    motion, p = _still()
    p[:, 0, 0] = np.concatenate([[0.0] * 4, 2.5 + np.arange(16)])
    (finding,) = teleport(CheckData(motion, p, 1.0), CheckSettings())
    assert (finding.start, finding.end, finding.names, finding.value) == (3, 4, ("Hips",), 2.0)
    p[:, 0, 0] = np.concatenate([[0.0] * 4, 1.5 + np.arange(16)])  # jump 1, change 1: a step
    assert teleport(CheckData(motion, p, 1.0), CheckSettings()) == []
    p[:, 0, 0] = np.concatenate([[0.0] * 4, [0.05] * 16])  # jump 0.05, change 0: the first limit
    (finding,) = teleport(CheckData(motion, p, 1.0), CheckSettings())
    assert (finding.start, finding.end, finding.value, finding.severity) == (3, 4, 0.05, "info")


def test_a_knocked_child_of_the_root_is_named():
    motion = clean_walk(120.0, unit=CM)
    (finding,) = run_checks(with_translation(motion, "Spine", _knock(200, 5.0)), CheckSettings(kinds=("pop",)))
    assert (finding.start, finding.names) == (200, ("Spine",))


def test_a_small_pop_is_an_info():
    """1.2 cm is 0.7% of the 173 cm walk: past the first limit (0.5%) only."""
    motion = with_translation(clean_walk(120.0, unit=CM), "LeftHand", _knock(200, 1.2))
    (finding,) = run_checks(motion, CheckSettings(kinds=("pop",)))
    assert (finding.start, finding.severity) == (200, "info")
    assert finding.value == pytest.approx(1.2, rel=0.1)


def test_two_joints_popping_together_largest_first():
    motion = with_translation(clean_walk(120.0, unit=CM), "LeftHand", _knock(200, 5.0))
    motion = with_translation(motion, "RightHand", _knock(200, 8.0))
    (finding,) = run_checks(motion, CheckSettings(kinds=("pop",)))
    assert finding.names == ("RightHand", "LeftHand")
    assert finding.value == pytest.approx(8.0, rel=0.1)


def _knock(at: int, size_cm: float):
    def knock(f):
        shift = np.zeros((f.size, 3))
        shift[f == at, 0] = cm(size_cm, CM)
        return shift

    return knock


def test_noise_is_no_pop_and_the_clean_walk_warns_nothing():
    """A hand shaken by 0.5 cm throughout: jitter, and no pop (its deviations are its own
    typical motion: the robust level rises with them)."""
    rng = np.random.default_rng(2)
    motion = with_translation(clean_walk(120.0, unit=CM), "RightHand", _shake(rng, cm(0.5, CM), 0, 599))
    kinds = {f.kind for f in run_checks(motion, CheckSettings(kinds=("pop", "jitter")))}
    assert kinds == {"jitter"}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert run_checks(clean_walk(120.0, unit=CM)) == []


@pytest.mark.parametrize(("quiet_blocks", "count"), [(1, 1), (2, 2)])
def test_jitter_runs_joined_across_one_quiet_block(quiet_blocks, count):
    """Blocks of 24 frames at 120 Hz: the hand shaken over blocks 2-5 and again from
    ``quiet_blocks`` later to block 9: one finding across a gap of one block, two across two."""
    resume = 24 * (6 + quiet_blocks)
    rng = np.random.default_rng(4)
    motion = with_translation(clean_walk(120.0, unit=CM), "RightHand", _shake(rng, cm(0.5, CM), 48, 143))
    motion = with_translation(motion, "RightHand", _shake(rng, cm(0.5, CM), resume, resume + 95))
    findings = run_checks(motion, CheckSettings(kinds=("jitter",)))
    assert len(findings) == count
    assert findings[0].start == 48 and findings[-1].end == resume + 96 + 2


def test_jitter_at_30_hz_takes_blocks_of_10_frames():
    """0.2 s is 6 frames at 30 Hz: blocks are the 10 frames at least; 20 frames hold one."""
    motion = clean_walk(30.0, seconds=20 / 30.0, unit=CM)
    rng = np.random.default_rng(6)
    motion = with_translation(motion, "RightHand", _shake(rng, cm(0.5, CM), 0, 19))
    (finding,) = run_checks(motion, CheckSettings(kinds=("jitter",)))
    assert (finding.start, finding.end) == (0, 12)


def test_faint_jitter_is_an_info():
    """Noise of 0.3 cm per axis: 0.52 cm RMS, 0.3% of the size: above the first limit only."""
    rng = np.random.default_rng(8)
    motion = with_translation(clean_walk(120.0, unit=CM), "RightHand", _shake(rng, cm(0.3, CM), 60, 539))
    (finding,) = run_checks(motion, CheckSettings(kinds=("jitter",)))
    assert finding.severity == "info"
    assert finding.value == pytest.approx(0.3 * np.sqrt(3), rel=0.15)


def test_a_small_teleport_is_an_info_and_four_frames_suffice():
    """12 cm is 7% of the 173 cm walk: past the first limit (5%) only."""
    motion = clean_walk(120.0, unit=CM)
    translations = motion.translations.copy()
    translations[350:, 0, 0] += 12.0
    (finding,) = run_checks(motion.replace(translations=translations), CheckSettings(kinds=("teleport",)))
    assert (finding.start, finding.severity) == (349, "info")
    short = motion.frame_slice(slice(0, 4))
    translations = short.translations.copy()
    translations[2:, 0, 0] += 50.0
    (finding,) = run_checks(short.replace(translations=translations), CheckSettings(kinds=("teleport",)))
    assert (finding.start, finding.end) == (1, 2)


def test_a_teleport_of_a_fast_root():
    """At 24 Hz a root moving 5 m/s steps 21 cm a frame; a jump of 50 cm is a teleport
    (the change of its velocity is none, whatever the velocity)."""
    motion = clean_walk(24.0, unit=CM)
    f = np.arange(motion.n_frames)
    translations = motion.translations.copy()
    translations[:, 0, 2] += 500.0 / 24.0 * f + np.where(f >= 60, 50.0, 0.0)
    (finding,) = run_checks(motion.replace(translations=translations), CheckSettings(kinds=("teleport",)))
    assert (finding.start, finding.end) == (59, 60)


@pytest.mark.parametrize("limit", [0.0, 1e-3, 0.05, 1e-170, np.inf])
def test_jittery_blocks_are_those_whose_median_noise_reaches_the_limit(limit):
    """Counting the products up to the noisiest that reaches the limit picks the blocks the
    median picks, on products at and around that boundary (ties, NaN gaps, blocks of 10 to 24)."""
    boundary = noisiest_product(limit)
    rng = np.random.default_rng(2)
    near = boundary if np.isfinite(boundary) else -1e-300
    around = near + np.array([-1.0, 0.0, 1.0]) * max(abs(near), 1e-300) * 2e-16
    choices = np.concatenate([around, np.nextafter(near, [-np.inf, np.inf]), [-1.0, 0.0, 1.0, np.nan]])
    products = rng.choice(choices, size=(480, 6))
    products[:, 5] = near
    with np.errstate(over="ignore"):  # the noise of products near -1e308 is infinite
        for block in (10, 11, 24):
            expected = jittery_blocks(products, block, limit, backend="numpy")
            np.testing.assert_array_equal(jittery_blocks(products, block, limit), expected)
        assert block_noise(np.float64(boundary)) >= limit  # the largest that reaches it: the next does not
        assert boundary == np.inf or not block_noise(np.nextafter(boundary, np.inf)) >= limit


def test_jitter_and_pops_find_the_same_alone_or_together():
    """A hand shaken over frames 60 to 540 and knocked at 200 (120 Hz, cm): jitter and pops
    run alone give what they give among every kind (they share one pass when both run)."""
    rng = np.random.default_rng(7)

    def shake(f):
        shift = rng.normal(scale=cm(0.5, CM), size=(f.size, 3)) * ((f >= 60) & (f <= 540))[:, None]
        shift[f == 200] += np.array([3.0, 4.0, 0.0]) * cm(1.0, CM)
        return shift

    motion = with_translation(clean_walk(120.0, unit=CM), "RightHand", shake)
    positions = world_positions(motion)
    together, settings = CheckData(motion, positions, motion.size), CheckSettings()
    found = jitter(together, settings) + pop(together, settings)
    assert {f.kind for f in found} == {"jitter", "pop"}
    alone = [
        check(CheckData(motion, positions, motion.size), settings.with_kinds([kind]))
        for check, kind in ((jitter, "pop"), (pop, "pop"))
    ]
    assert alone[0] + alone[1] == found
