"""Boxes, rods from arrays and generated rods: round trips, frames and errors."""

import numpy as np
import pytest

import rgc
from geometry import quaternions_onto


def random_rods(n, side, seed):
    rng = np.random.default_rng(seed)
    centres = rng.uniform(0.0, side, size=(n, 3))
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    return centres, d


def test_box_properties_and_wrap():
    b = rgc.Box([4.0, 5.0, 6.0], periodic="xy")
    assert b.sides.dtype == np.float64 and b.sides.tolist() == [4.0, 5.0, 6.0]
    assert b.periodic == "xy" and b.volume == 120.0
    # Exactly L wraps to 0 (np.mod can return L for -tiny), walls leave z alone.
    w = b.wrap(np.array([[4.0, -1.0, 7.0], [-1e-17, 5.0, -1.0]]))
    assert w.tolist() == [[0.0, 4.0, 7.0], [0.0, 0.0, -1.0]]
    # A centred box wraps into [-L/2, L/2), its own frame.
    c = rgc.Box(4.0, centred=True)
    assert c.wrap(np.array([[-2.0, 0.0, 1.9], [2.0, 3.0, -2.5]])).tolist() == [[-2.0, 0.0, 1.9], [-2.0, -1.0, 1.5]]


def test_arrays_round_trip():
    b = rgc.Box(6.0)
    centres, d = random_rods(50, 6.0, 1)
    r = rgc.Rods.from_arrays(b, centres, directions=d, lengths=1.0, radii=np.full(50, 0.02))
    assert len(r) == 50
    assert np.array_equal(r.centres, centres)
    assert np.allclose(r.directions, d, atol=1e-15)
    assert r.lengths.tolist() == [1.0] * 50 and r.radii.tolist() == [0.02] * 50
    assert r.centres.dtype == np.float64 and r.centres.shape == (50, 3)


def test_float32_and_lists_are_taken_as_float64():
    b = rgc.Box(6.0)
    centres, d = random_rods(20, 6.0, 2)
    exact = rgc.Rods.from_arrays(b, centres, directions=d, lengths=1.0, radii=0.05)
    lists = rgc.Rods.from_arrays(b, centres.tolist(), directions=d.tolist(), lengths=[1.0] * 20, radii=0.05)
    assert np.array_equal(exact.centres, lists.centres)
    single = rgc.Rods.from_arrays(b, centres.astype(np.float32), directions=d.astype(np.float32), lengths=1.0, radii=0.05)
    assert np.allclose(single.centres, centres, atol=1e-5)
    # Strided views (columns of a wider table, reversed rows) are read as they lie.
    table = np.column_stack([centres, d])[::-1]
    view = rgc.Rods.from_arrays(b, table[:, :3], directions=table[:, 3:], lengths=np.ones(40)[::2], radii=0.05)
    assert np.array_equal(view.centres, centres[::-1]) and np.allclose(view.directions, d[::-1], atol=1e-15)


def test_quaternions_and_centred_boxes_give_the_same_contacts():
    b = rgc.Box(5.0)
    sys = rgc.generate(b, density=30, gamma=10, seed=4)
    # The same rods given as HOOMD would: a centred box, and quaternions
    # rotating the body axis x onto each direction.
    q = quaternions_onto(sys.directions)
    centred = rgc.Box(5.0, centred=True)
    shifted = sys.centres - 2.5
    again = rgc.Rods.from_arrays(centred, shifted, quaternions=q, lengths=sys.lengths, radii=sys.radii)
    a, c = rgc.contacts(sys), rgc.contacts(again)
    assert len(a) > 0
    assert np.array_equal(a.pairs, c.pairs)
    assert np.array_equal(a.shifts, c.shifts)
    # Contact points come back in the centred frame.
    assert np.allclose(a.points - 2.5, c.points, atol=1e-9)


def test_centred_boxes_give_centres_and_points_back_in_their_frame():
    centred = rgc.Box(5.0, centred=True)
    sys = rgc.generate(centred, density=30, gamma=10, seed=4)
    plain = rgc.generate(rgc.Box(5.0), density=30, gamma=10, seed=4)
    assert sys.box.centred and sys.box == centred and not plain.box.centred
    assert sys.centres.min() >= -2.5 and sys.centres.max() < 2.5
    assert np.allclose(sys.centres, plain.centres - 2.5, atol=1e-15, rtol=0)
    c = rgc.contacts(sys)
    assert c.points.min() >= -2.5 and c.points.max() < 2.5
    assert np.allclose(c.points, rgc.contacts(plain).points - 2.5, atol=1e-15, rtol=0)
    # What goes in comes out: from_arrays in a centred box, walls in z too.
    walls = rgc.Box(5.0, periodic="xy", centred=True)
    again = rgc.Rods.from_arrays(walls, sys.centres, directions=sys.directions, lengths=sys.lengths, radii=sys.radii)
    assert again.box == walls and again.cut > 0
    inside = np.abs(sys.centres[:, 2]) < 2.0
    assert np.allclose(again.centres[inside], sys.centres[inside], atol=1e-15, rtol=0)
    assert "centred" in repr(again) and "centred" not in repr(plain)


def test_generated_systems_are_reproducible():
    b = rgc.Box(4.0)
    one = rgc.generate(b, density=40, gamma=23, seed=7)
    two = rgc.generate(b, density=40, gamma=23, seed=7)
    assert len(one) == 2560 and np.array_equal(one.centres, two.centres)
    assert not np.array_equal(one.centres, rgc.generate(b, density=40, gamma=23, seed=8).centres)
    aligned = rgc.generate(b, density=40, gamma=23, order=0.9, director=(0, 0, 1), seed=1)
    assert np.mean(np.abs(aligned.directions[:, 2])) > 0.9


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: rgc.Box(-1.0), "box sides must be positive finite numbers"),
        (lambda: rgc.Box([1.0, 2.0]), "box sides must be a number or three numbers, got 2"),
        (lambda: rgc.Box(4.0, periodic="yz"), "periodic must be 'xyz', 'xy' or 'none'"),
        (
            lambda: rgc.Rods.from_arrays(rgc.Box(4.0), np.zeros((2, 2)), directions=np.ones((2, 3)), lengths=1.0, radii=0.1),
            "centres must have shape (N, 3)",
        ),
        (
            lambda: rgc.Rods.from_arrays(rgc.Box(4.0), np.ones((2, 3)), lengths=1.0, radii=0.1),
            "give either directions or quaternions",
        ),
        (
            lambda: rgc.Rods.from_arrays(rgc.Box(4.0), np.ones((2, 3)), directions=np.ones((3, 3)), lengths=1.0, radii=0.1),
            "3 directions for 2 centres",
        ),
        (
            lambda: rgc.Rods.from_arrays(rgc.Box(4.0), np.ones((2, 3)), directions=np.ones((2, 3)), lengths=np.ones(3), radii=0.1),
            "lengths has 3 values for 2 rods",
        ),
        (
            lambda: rgc.Rods.from_arrays(rgc.Box(4.0), np.ones((1, 3)), directions=np.zeros((1, 3)), lengths=1.0, radii=0.1),
            "rod 0:",
        ),
        (
            lambda: rgc.Rods.from_arrays(rgc.Box(4.0), np.ones((1, 3)), directions=np.ones((1, 3)), lengths=1.0, radii=-0.1),
            "rod 0:",
        ),
        (
            lambda: rgc.Rods.from_arrays(rgc.Box(4.0), np.ones((2, 3)), directions=np.ones((2, 3)), lengths=1.0, radii=0.1),
            "the same rod as rod 0",
        ),
        (
            lambda: rgc.Rods.from_arrays(rgc.Box(4.0), np.ones((1, 3)), quaternions=np.zeros((1, 4)), lengths=1.0, radii=0.1),
            "quaternion 0 is not a rotation",
        ),
        (
            lambda: rgc.Rods.from_arrays(rgc.Box(4.0), np.array([[1.0, np.nan, 1.0]]), directions=np.ones((1, 3)), lengths=1.0, radii=0.1),
            "centres row 0 is not finite",
        ),
        (lambda: rgc.Box(4.0).wrap(np.array([[np.inf, 0.0, 0.0]])), "points row 0 is not finite"),
        (lambda: rgc.generate(rgc.Box(4.0), density=40, seed=1), "give either gamma or radius"),
        (lambda: rgc.generate(rgc.Box(4.0), density=40, gamma=0.5), "gamma must be at least 1"),
        (lambda: rgc.generate(rgc.Box(4.0), density=-1, gamma=10), "density must be a positive finite number"),
        (lambda: rgc.generate(rgc.Box(2.0), density=10, gamma=10), "is too small"),
        (lambda: rgc.generate(rgc.Box(4.0), density=10, gamma=10, length="normal:1"), "distribution"),
    ],
)
def test_bad_input_is_a_value_error_with_its_message(call, message):
    with pytest.raises(ValueError, match=None) as e:
        call()
    assert message in str(e.value), str(e.value)
