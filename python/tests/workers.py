"""Functions a multiprocessing pool runs (importable by its workers)."""

import rgc


def truth_of(seed):
    """A system's truth, computed in a worker and pickled back with its rods."""
    rods = rgc.generate(rgc.Box(4.0, centred=True), density=40, gamma=23, seed=seed)
    return rods, rgc.contacts(rods), rgc.compress(rods, seed=seed), rgc.truth(rods, seed=seed)


def dof_of(rods):
    """A system sent to a worker pickled, its DOF sent back."""
    return rgc.truth(rods).dof


def undecided(seed):
    """Truth of a system it cannot decide (gamma 10 in a box of 4 forces
    planes through three box directions): raises UndecidedError."""
    return rgc.truth(rgc.generate(rgc.Box(4.0), density=30, gamma=10, seed=seed))
