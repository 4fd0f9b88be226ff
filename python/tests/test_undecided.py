"""An undecided truth raises, so it is never read as "not spanning",
unless the caller asks for it."""

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


def test_a_memory_refusal_is_an_undecided_memory_error():
    big = rgc.generate(rgc.Box(6.0), density=40, gamma=23, seed=1)
    with pytest.raises(MemoryError) as e:
        rgc.truth(big, memory_limit=20_000_000)
    assert type(e.value) is rgc.UndecidedMemoryError and isinstance(e.value, rgc.UndecidedError)
    assert str(e.value).startswith("truth refused this system: ")
    assert str(e.value).endswith("(raise memory_limit)")
    t = rgc.truth(big, memory_limit=20_000_000, allow_undecided=True)
    assert t.undecided and t.memory_refused and t.spanning is None
    assert t.reason == e.value.reason


def test_rods_too_large_for_the_memory_limit_are_refused_before_the_work():
    big = rgc.generate(rgc.Box(6.0), density=40, gamma=23, seed=1)
    with pytest.raises(MemoryError, match=r"over the memory limit: 8640 rods \(about .* contacts\) need an estimated .*, more than the limit of 1000 B"):
        rgc.truth(big, memory_limit=1000)
