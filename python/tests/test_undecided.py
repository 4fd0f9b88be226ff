"""An undecided truth raises, so it is never read as "not spanning",
unless the caller asks for it."""

import os

import numpy as np
import pytest

import rgc


@pytest.fixture(scope="module")
def flat():
    """Gamma 10 in a box of 4: a forced plane class through three box
    directions, which the line model cannot realize (undecided at once)."""
    return rgc.generate(rgc.Box(4.0), density=30, gamma=10, seed=1)


def test_an_undecided_truth_raises_with_its_reason(flat):
    with pytest.raises(rgc.UndecidedError) as e:
        rgc.truth(flat)
    assert isinstance(e.value, RuntimeError) and not isinstance(e.value, (MemoryError, ValueError))
    assert type(e.value) is rgc.UndecidedError
    assert str(e.value).startswith("truth is undecided: a forced plane class of ")
    assert e.value.reason.endswith("the line model has no realization in this box")
    assert e.value.truth.undecided and e.value.truth.spanning is None


def test_an_undecided_truth_is_returned_when_asked_for(flat):
    t = rgc.truth(flat, allow_undecided=True)
    assert t.undecided and t.method == "undecided" and t.dof is None and t.spanning is None
    assert not t.memory_refused and t.reason.startswith("a forced plane class of ")
    assert np.all(t.cluster_idx == -1)


def resident_bytes():
    """What this process holds now (Linux), as the library's guard reads it."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def test_a_memory_refusal_is_an_undecided_memory_error():
    big = rgc.generate(rgc.Box(6.0), density=40, gamma=23, seed=1)
    # Room for the system's rods and contacts (6 MiB), not for its truth.
    limit = resident_bytes() + 8 * 2**20
    with pytest.raises(MemoryError) as e:
        rgc.truth(big, memory_limit=limit)
    assert type(e.value) is rgc.UndecidedMemoryError and isinstance(e.value, rgc.UndecidedError)
    assert str(e.value).startswith("truth refused this system: ")
    assert str(e.value).endswith(" (memory_limit)") and "--memory-limit" not in str(e.value), str(e.value)
    # The process holds more now: the same room above what it holds.
    t = rgc.truth(big, memory_limit=resident_bytes() + 8 * 2**20, allow_undecided=True)
    assert t.undecided and t.memory_refused and t.spanning is None
    for reason in (t.reason, e.value.reason):
        assert ", the process holds " in reason and ", over the limit of " in reason, reason


def test_rods_too_large_for_the_memory_limit_are_refused_before_the_work():
    big = rgc.generate(rgc.Box(6.0), density=40, gamma=23, seed=1)
    with pytest.raises(MemoryError, match=r"over the memory limit: the system of 8640 rods \(about .* contacts\) needs about .*, the process holds .*, over the limit of 1000 B"):
        rgc.truth(big, memory_limit=1000)
