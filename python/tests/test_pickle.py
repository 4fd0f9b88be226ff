"""Every class pickles and comes back equal, in this process and through a
multiprocessing pool."""

import json
import multiprocessing
import pickle

import numpy as np
import pytest

import rgc
from workers import dof_of, truth_of, undecided


@pytest.fixture(scope="module")
def system():
    return rgc.generate(rgc.Box(4.0, 4.5, 5.0, periodic="xy", centred=True), density=30, gamma=10, seed=2)


def facts(report):
    """A report's JSON without its timings, which differ between two runs."""

    def drop(x):
        if isinstance(x, dict):
            return {k: drop(v) for k, v in x.items() if not k.startswith("seconds")}
        return [drop(v) for v in x] if isinstance(x, list) else x

    return drop(json.loads(report))


def same_rods(a, b):
    return (
        a.box == b.box
        and len(a) == len(b)
        and a.cut == b.cut
        and np.array_equal(a.centres, b.centres)
        and np.array_equal(a.directions, b.directions)
        and np.array_equal(a.lengths, b.lengths)
        and np.array_equal(a.radii, b.radii)
    )


def same_contacts(a, b):
    return a.n_rods == b.n_rods and all(
        np.array_equal(getattr(a, k), getattr(b, k)) for k in ("pairs", "points", "params", "shifts")
    )


def same_compression(a, b):
    return (
        np.array_equal(a.body_idx, b.body_idx)
        and np.array_equal(a.spans, b.spans)
        and (a.spanning, a.runs_spanning, a.run, facts(a.report)) == (b.spanning, b.runs_spanning, b.run, facts(b.report))
    )


def same_truth(a, b):
    return (
        np.array_equal(a.cluster_idx, b.cluster_idx)
        and [c.tolist() for c in a.clusters] == [c.tolist() for c in b.clusters]
        and (a.dof, a.spanning, a.method, a.reason, a.memory_refused, facts(a.report))
        == (b.dof, b.spanning, b.method, b.reason, b.memory_refused, facts(b.report))
        and (a.strain_rank, a.strains_resisted, a.strains_considered, a.strain_reason)
        == (b.strain_rank, b.strains_resisted, b.strains_considered, b.strain_reason)
    )


@pytest.mark.parametrize("protocol", [2, pickle.HIGHEST_PROTOCOL])
def test_every_class_round_trips(system, protocol):
    again = lambda x: pickle.loads(pickle.dumps(x, protocol=protocol))
    for box in (rgc.Box(5.0), rgc.Box(4.0, 5.0, 6.0, periodic="none", centred=True)):
        assert again(box) == box and repr(again(box)) == repr(box)
    rods = again(system)
    assert isinstance(rods, rgc.Rods) and same_rods(rods, system)
    c = rgc.contacts(system)
    assert same_contacts(again(c), c) and len(c) > 0
    k = rgc.compress(system, runs=3)
    assert same_compression(again(k), k) and again(k).motifs == k.motifs
    t = rgc.truth(system)
    assert same_truth(again(t), t) and again(t).report == t.report
    # What the rods unpickle to gives the same answers.
    assert same_contacts(rgc.contacts(rods), c)
    assert same_truth(rgc.truth(rods), t)


def test_a_pickled_state_is_checked_again(system):
    rebuild, state = system.__reduce__()
    centres = state[1].copy()
    centres[1] = centres[0]
    directions = state[2].copy()
    directions[1] = directions[0]
    with pytest.raises(ValueError, match="rod 1: .*the same rod as rod 0"):
        rebuild(state[0], centres, directions, *state[3:])


def test_results_come_back_from_a_process_pool(system):
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        # A result that failed to unpickle would hang map() for ever.
        results = pool.map_async(truth_of, [1, 2]).get(timeout=120)
        dofs = pool.map_async(dof_of, [system, system]).get(timeout=120)
        # An exception a worker raises comes back whole.
        with pytest.raises(rgc.UndecidedError, match="truth is undecided: a forced plane class") as e:
            pool.apply_async(undecided, (1,)).get(timeout=120)
    for seed, (rods, c, k, t) in zip([1, 2], results):
        mine = rgc.generate(rgc.Box(4.0, centred=True), density=40, gamma=23, seed=seed)
        assert same_rods(rods, mine)
        assert same_contacts(c, rgc.contacts(mine))
        assert same_compression(k, rgc.compress(mine, seed=seed))
        assert same_truth(t, rgc.truth(mine, seed=seed))
    assert dofs == [rgc.truth(system).dof] * 2
    assert e.value.truth.undecided and e.value.reason == e.value.truth.reason
