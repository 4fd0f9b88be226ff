"""Input the module must refuse with a clear ValueError or MemoryError, and
input in other common spellings it must take (freud's box, numpy scalars)."""

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import rgc


def rods_of(n=4, side=6.0):
    rng = np.random.default_rng(1)
    centres = rng.uniform(0.0, side, size=(n, 3))
    d = rng.normal(size=(n, 3))
    return centres, d / np.linalg.norm(d, axis=1)[:, None]


def test_a_box_of_three_numbers_as_freud_writes_it():
    b = rgc.Box(5.0, 6.0, 7.0)
    assert b.sides.tolist() == [5.0, 6.0, 7.0] and b.periodic == "xyz" and not b.centred
    assert rgc.Box(5.0, 6.0, 7.0, periodic="xy", centred=True) == rgc.Box([5.0, 6.0, 7.0], periodic="xy", centred=True)
    assert rgc.Box(np.float32(4.0)).sides.tolist() == [4.0] * 3
    with pytest.raises(ValueError, match=r"box sides must be a number or three numbers, got 2 \(periodic and centred are keywords"):
        rgc.Box(5.0, 6.0)
    with pytest.raises(ValueError, match=r"got 'xy' \(periodic and centred are keywords: Box\(5.0, periodic='xy'\)\)"):
        rgc.Box(5.0, 6.0, "xy")


def test_box_repr_is_short():
    assert repr(rgc.Box(1e-300)) == "Box(sides=(1.0000e-300, 1.0000e-300, 1.0000e-300), periodic='xyz', centred=False)".replace("'", '"')
    assert repr(rgc.Box(5.0, 6.0, 7.5, centred=True)) == 'Box(sides=(5, 6, 7.5), periodic="xyz", centred=True)'


def test_runs_are_capped_as_on_the_command_line():
    sys_ = rgc.generate(rgc.Box(4.0), density=10, gamma=10, seed=1)
    assert rgc._rgc.MAX_RUNS == 100_000
    for runs in (100_001, 10**9, 10**30, 0, -1, 2.5, True):
        with pytest.raises(ValueError, match=rf"runs must be an integer from 1 to 100000, got {runs!r}"):
            rgc.compress(sys_, runs=runs)
    assert rgc.compress(sys_, runs=np.int64(3)).report.count('"runs":3') == 1


def test_seeds_are_checked_by_name():
    sys_ = rgc.generate(rgc.Box(4.0), density=10, gamma=10, seed=2**64 - 1)
    for call in (
        lambda s: rgc.generate(rgc.Box(4.0), density=10, gamma=10, seed=s),
        lambda s: rgc.compress(sys_, seed=s),
        lambda s: rgc.truth(sys_, seed=s),
        lambda s: rgc.check("E{Sw", seed=s),
    ):
        for seed in (-1, 2**64, 1.5):
            with pytest.raises(ValueError, match=rf"seed must be an integer from 0 to 18446744073709551615, got {seed!r}"):
                call(seed)


def test_generating_more_rods_than_fit_is_a_memory_error():
    with pytest.raises(MemoryError, match="1000000000 rods, more than the 50000000 that fit in memory"):
        rgc.generate(rgc.Box(1000.0), density=1.0, gamma=23)
    with pytest.raises(ValueError, match="density must be a positive finite number"):
        rgc.generate(rgc.Box(4.0), density=float("inf"), gamma=23)


def test_memory_limit_must_be_a_positive_number_of_bytes():
    sys_ = rgc.generate(rgc.Box(4.0), density=10, gamma=10, seed=1)
    for limit in (0, -1, -(10**20), 1.5e9, "4G"):
        with pytest.raises(ValueError, match=rf"memory_limit \(bytes\) must be an integer from 1 to 18446744073709551615, got {limit!r}"):
            rgc.truth(sys_, memory_limit=limit)
    assert rgc.truth(sys_, memory_limit=10**30 // 10**11).method == "exact"


@pytest.mark.parametrize(
    "centres, message",
    [
        (lambda c: c + 1j, "centres must be real numbers, got an array of dtype complex128"),
        (lambda c: c.astype(str).astype(object), "centres must be real numbers, got an array of dtype object"),
        (lambda c: c.astype(str), "centres must be real numbers, got an array of dtype <U"),
        (lambda c: c.ravel(), "centres must have shape (N, 3), got (12,)"),
        (lambda c: [[1.0, 2.0, 3.0], [1.0, 2.0]], "centres must be an array of real numbers: setting an array element with a sequence"),
        (lambda c: c[None], "centres must have shape (N, 3), got (1, 4, 3)"),
        (lambda c: c[:, :2], "centres must have shape (N, 3), got (4, 2)"),
    ],
)
def test_centres_that_are_not_real_n_by_3_are_refused(centres, message):
    c, d = rods_of()
    with pytest.raises(ValueError) as e:
        rgc.Rods.from_arrays(rgc.Box(6.0), centres(c), directions=d, lengths=1.0, radii=0.05)
    assert message in str(e.value)


def test_other_arrays_are_checked_by_name():
    c, d = rods_of()
    b = rgc.Box(6.0)
    with pytest.raises(ValueError, match=r"directions must have shape \(N, 3\), got \(4, 4\)"):
        rgc.Rods.from_arrays(b, c, directions=np.ones((4, 4)), lengths=1.0, radii=0.05)
    with pytest.raises(ValueError, match=r"quaternions must have shape \(N, 4\), got \(4, 3\)"):
        rgc.Rods.from_arrays(b, c, quaternions=d, lengths=1.0, radii=0.05)
    with pytest.raises(ValueError, match="radii must be real numbers, got an array of dtype complex128"):
        rgc.Rods.from_arrays(b, c, directions=d, lengths=1.0, radii=0.05 + 0j)
    with pytest.raises(ValueError, match=r"lengths must be a number or an array of shape \(N,\), got shape \(4, 1\)"):
        rgc.Rods.from_arrays(b, c, directions=d, lengths=np.ones((4, 1)), radii=0.05)
    with pytest.raises(ValueError, match="lengths are needed"):
        rgc.Rods.from_arrays(b, c, directions=d, radii=0.05)
    with pytest.raises(ValueError, match=r"points must have shape \(N, 3\), got \(3,\)"):
        b.wrap([1.0, 2.0, 3.0])


@pytest.mark.parametrize("one", [1.0, 1, np.float32(1.0), np.float64(1.0), np.array(1.0), np.array(1, dtype=np.int32)])
def test_numpy_scalars_for_lengths_and_radii_are_numbers(one):
    c, d = rods_of(100, 20.0)
    plain = rgc.Rods.from_arrays(rgc.Box(20.0), c, directions=d, lengths=1.0, radii=0.05)
    given = rgc.Rods.from_arrays(rgc.Box(20.0), c, directions=d, lengths=one, radii=one * 0.05)
    assert np.array_equal(given.lengths, plain.lengths)
    assert np.allclose(given.radii, plain.radii, rtol=1e-7)


def test_a_radius_larger_than_the_length_is_refused():
    # The library's own check (Rod::defect), which from_arrays goes through.
    c, d = rods_of(1, 30.0)
    with pytest.raises(ValueError, match="rod 0: radius 2 is more than half the length 1: the rod is wider than long"):
        rgc.Rods.from_arrays(rgc.Box(30.0), c, directions=d, lengths=1.0, radii=2.0)


def test_more_rods_than_the_library_holds_are_a_memory_error_before_any_allocation():
    # 60 million rows that take no memory: one row broadcast.
    centres = np.broadcast_to(np.array([1.0, 1.0, 1.0]), (60_000_000, 3))
    with pytest.raises(MemoryError, match="60000000 rods, more than the 50000000 that fit in memory"):
        rgc.Rods.from_arrays(rgc.Box(10.0), centres, directions=centres, lengths=1.0, radii=0.01)


def under_memory_limit(code):
    """What ``code`` prints in a child process whose address space is held
    to 1.5 GiB more than the interpreter holds once rgc is imported."""
    script = textwrap.dedent(
        """
        import resource
        import numpy as np
        import rgc
        held = int(open("/proc/self/status").read().split("VmSize:")[1].split()[0]) * 1024
        limit = held + (3 << 29)
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        try:
        """
    ) + textwrap.indent(textwrap.dedent(code), "    ") + textwrap.dedent(
        """
        except MemoryError as e:
            print("MemoryError:", e)
        """
    )
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    return out.stdout.rstrip()


def test_rods_beyond_the_memory_available_are_a_memory_error():
    # 10 million rods (about 4 GB to build) in rows that take no memory.
    out = under_memory_limit(
        """
        centres = np.broadcast_to(np.array([1.0, 1.0, 1.0]), (10_000_000, 3))
        rgc.Rods.from_arrays(rgc.Box(10.0), centres, directions=centres, lengths=1.0, radii=0.01)
        """
    )
    assert out.startswith("MemoryError: over the memory limit: building 10000000 rods needs about "), out
    assert out.endswith("(ulimit -v)"), out


def test_runs_whose_answers_pass_the_memory_available_are_a_memory_error():
    # 100,000 runs of 2,560 rods keep about 4 GB of answers.
    out = under_memory_limit(
        """
        rods = rgc.generate(rgc.Box(4.0), density=40, gamma=23, seed=1)
        print(rgc.compress(rods, runs=10).runs_spanning >= 0)
        rgc.compress(rods, runs=100_000)
        """
    )
    first, second = out.splitlines()
    assert first == "True"
    assert second.startswith("MemoryError: over the memory limit: the system of 2560 rods (about "), second
    assert " contacts) with 100000 runs needs about " in second, second
    assert second.endswith("(ulimit -v); take a smaller box or density, or fewer runs"), second
