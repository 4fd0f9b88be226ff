"""rgc: rigidity percolation in random 3-D rod systems, from Python.

Rods go in as numpy arrays (or are generated), and results come out as
numpy arrays: contacts as (M, 2) pairs with their points and image
offsets, 3D-RGC bodies and exact rigid clusters as per-rod labels of shape
(N,). The work runs in Rust with the interpreter released, and Ctrl-C
stops a long call at once; the answers are those of the ``rgc`` command
line for the same seed. Bad input raises ValueError, work too large for
the memory available MemoryError, an undecided truth UndecidedError.
Boxes, rods, contacts and results pickle.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Optional, Sequence, Tuple, Union

import numpy as np

from ._rgc import Box, Compression, Contacts, Rods, Truth
from ._rgc import check_graph6 as _check_graph6
from ._rgc import compress, contacts, generate
from ._rgc import moduli as _moduli
from ._rgc import truth as _truth

__all__ = [
    "moduli",
    "Box",
    "Rods",
    "Contacts",
    "Compression",
    "Truth",
    "UndecidedError",
    "UndecidedMemoryError",
    "generate",
    "contacts",
    "compress",
    "truth",
    "check",
    "to_networkx",
    "to_rustworkx",
    "load_study",
]


def to_networkx(c: Contacts) -> Any:
    """The contact graph as a ``networkx.Graph``: one node per rod, one
    edge per contact carrying its ``point``, ``params`` and ``shift``."""
    import networkx as nx

    g = nx.Graph()
    g.add_nodes_from(range(c.n_rods))
    pairs, points, params, shifts = c.pairs, c.points, c.params, c.shifts
    g.add_edges_from(
        (int(a), int(b), {"point": points[i], "params": params[i], "shift": shifts[i]})
        for i, (a, b) in enumerate(pairs)
    )
    return g


def to_rustworkx(c: Contacts) -> Any:
    """The contact graph as a ``rustworkx.PyGraph`` (node i is rod i; each
    edge's payload is its contact index)."""
    import rustworkx as rx

    g = rx.PyGraph(multigraph=False)
    g.add_nodes_from(range(c.n_rods))
    g.add_edges_from([(int(a), int(b), i) for i, (a, b) in enumerate(c.pairs)])
    return g


def _real(a: Any, name: str) -> np.ndarray:
    """``a`` as a numpy array of real numbers (any float or integer dtype),
    or a ValueError naming it: complex numbers would lose their imaginary
    part and strings would be parsed as numbers by a plain conversion."""
    try:
        arr = np.asarray(a)
    except ValueError as e:  # ragged lists
        raise ValueError(f"{name} must be an array of real numbers: {e}") from None
    if arr.dtype.kind not in "iuf":
        raise ValueError(f"{name} must be real numbers, got an array of dtype {arr.dtype}")
    return arr


def _points(a: Any, name: str, cols: int) -> np.ndarray:
    """An (N, cols) array of real numbers as float64 (float32 from OVITO
    or gsd and lists too; float64 views as they are, not copied), or a
    ValueError naming the shape."""
    arr = _real(a, name)
    if arr.ndim != 2 or arr.shape[1] != cols:
        raise ValueError(f"{name} must have shape (N, {cols}), got {arr.shape}")
    return arr.astype(np.float64, copy=False)


def _per_rod(a: Any, name: str) -> Tuple[Optional[float], Optional[np.ndarray]]:
    """A number for every rod (a Python, numpy or 0-d array number) or an
    (N,) float64 array, as (number, None) or (None, array)."""
    if a is None:
        raise ValueError(f"{name} are needed")
    if isinstance(a, bool):
        raise ValueError(f"{name} must be a number or an array of shape (N,), got {a!r}")
    arr = _real(a, name)
    if arr.ndim == 0:
        return float(arr), None
    if arr.ndim != 1:
        raise ValueError(f"{name} must be a number or an array of shape (N,), got shape {arr.shape}")
    return None, arr.astype(np.float64, copy=False)


def from_arrays(
    box: Box,
    centres: Any,
    directions: Any = None,
    quaternions: Any = None,
    lengths: Any = None,
    radii: Any = None,
    axis: Sequence[float] = (1.0, 0.0, 0.0),
) -> Rods:
    """Rods from arrays: ``centres`` (N, 3) in the box's frame (wrapped
    along periodic axes, so centred boxes and ``np.mod`` at exactly ``L``
    work), and either ``directions`` (N, 3) or ``quaternions`` (N, 4,
    ``(w, x, y, z)`` rotating ``axis``); ``lengths`` and ``radii`` are
    numbers or (N,) arrays. Any real dtype and lists are taken as float64;
    complex or text input, wrong shapes and rods the library refuses raise
    ValueError; rods too many for the memory available raise MemoryError
    before anything is allocated. Cores crossing a wall are cut to the box,
    as reading a file does."""
    if not isinstance(box, Box):
        raise ValueError(f"box must be an rgc.Box, got {type(box).__name__}")
    length, length_array = _per_rod(lengths, "lengths")
    radius, radius_array = _per_rod(radii, "radii")
    return Rods._from_arrays(
        box,
        _points(centres, "centres", 3),
        None if directions is None else _points(directions, "directions", 3),
        None if quaternions is None else _points(quaternions, "quaternions", 4),
        length,
        length_array,
        radius,
        radius_array,
        tuple(float(x) for x in _real(axis, "axis")),
    )


_wrap = Box.wrap


def wrap(self: Box, points: Any) -> np.ndarray:
    return _wrap(self, _points(points, "points", 3))


wrap.__doc__ = _wrap.__doc__
Box.wrap = wrap  # type: ignore[method-assign]
Rods.from_arrays = staticmethod(from_arrays)  # type: ignore[attr-defined]
Contacts.to_networkx = to_networkx  # type: ignore[attr-defined]
Contacts.to_rustworkx = to_rustworkx  # type: ignore[attr-defined]
Compression.motifs = property(  # type: ignore[attr-defined]
    lambda self: json.loads(self.report)["motifs"],
    doc="Motif instances compressed in the reported run, by motif.",
)


class UndecidedError(RuntimeError):
    """Truth could not decide this system: nothing is claimed about it.

    A RuntimeError, not a ValueError: the input was fine, the method ran
    out of ways to decide. ``reason`` says why; ``truth`` is the undecided
    answer (``method == 'undecided'``, no DOF, spanning None). Pass
    ``allow_undecided=True`` to ``rgc.truth`` to get that answer back
    instead."""

    def __init__(self, truth: Truth):
        self.truth = truth
        self.reason = truth.reason
        super().__init__(self._message())

    def _message(self) -> str:
        return f"truth is undecided: {self.reason}"

    def __reduce__(self) -> Tuple[type, Tuple[Truth]]:
        # Rebuilt from the answer, so a pool's worker can raise it too.
        return type(self), (self.truth,)


class UndecidedMemoryError(UndecidedError, MemoryError):
    """Truth stopped before work that would pass its ``memory_limit``: an
    UndecidedError that is also a MemoryError."""

    def _message(self) -> str:
        return f"truth refused this system: {self.reason}"


def truth(
    rods: Rods,
    criterion: str = "wrap",
    seed: int = 1,
    memory_limit: Optional[int] = None,
    allow_undecided: bool = False,
) -> Truth:
    """The exact generic rigidity of ``rods`` (the same answer as ``rgc
    truth`` with that seed): degrees of freedom, rigid clusters and
    spanning under 'wrap', 'faces' or 'solid' (the rods resist every
    strain of the box's periodic axes, all six in a periodic box; None
    where the strain rank is unknown), and the strain rank (``strain_rank``:
    how many strains of the box the rods resist, 6 for a solid;
    ``strains_resisted``: the coordinate strains resisted alone, 'xx' to
    'xy'; None with ``strain_reason`` where unknown). ``memory_limit`` (bytes, positive)
    refuses a system whose elimination would pass it.

    An undecided answer raises UndecidedError (UndecidedMemoryError, also a
    MemoryError, when the memory limit was the reason), so that it is never
    read as "not spanning"; with ``allow_undecided=True`` it is returned
    (``t.undecided``, ``t.reason``). Rods estimated to need more memory
    than available raise MemoryError before the work; Ctrl-C stops the call
    within a fraction of a second."""
    t = _truth(rods, criterion=criterion, seed=seed, memory_limit=memory_limit)
    if t.undecided and not allow_undecided:
        raise (UndecidedMemoryError if t.memory_refused else UndecidedError)(t)
    return t


def moduli(
    rods: Rods,
    k: float = 1.0,
    seed: int = 1,
    memory_limit: Optional[int] = None,
    solver: str = "auto",
    lsmr_iterations: int = 10000,
) -> dict:
    """The elastic moduli of ``rods`` in a cubic periodic box (the same
    answer as ``rgc moduli --json`` with that seed, ``solver`` and
    ``lsmr_iterations``: 'auto', the sparse QR where it fits in memory and
    LSMR where it does not, or 'qr' or 'lsmr' alone;
    ``conditioning['solver']`` says which ran, and
    ``conditioning['settled']`` whether LSMR converged within its
    ``lsmr_iterations`` per strain, else the moduli are upper bounds): a spring of stiffness
    ``k`` at every contact, the rods rigid, the non-affine relaxation.
    ``tensor`` and ``born`` are 6 x 6 float64 arrays in Voigt's notation
    (xx, yy, zz, yz, xz, xy) in ``k / L_rod``; ``shear`` and ``bulk`` are
    Voigt's averages, ``nonaffinity`` is ``1 - G / G_Born``, ``strain_rank``
    is truth's exact strain rank, at which the tensor is kept; and the
    ``conditioning``. A system whose float tensor shows no gap at the
    strain rank, or whose strain rank is unknown, raises ValueError."""
    out = json.loads(
        _moduli(
            rods,
            k=k,
            seed=seed,
            memory_limit=memory_limit,
            solver=solver,
            lsmr_iterations=lsmr_iterations,
        )
    )
    for key in ("tensor", "born", "eigenvalues"):
        out[key] = np.asarray(out[key], dtype=np.float64)
    return out


def check(graph: Any, seed: int = 1) -> dict:
    """The exact rigidity verdict of a rods-only contact pattern, given as
    graph6 text or a networkx graph: ``class`` ('rigid', 'flexible',
    'component-dependent' or 'undecided'), ``rigid``, ``dof`` and the
    realization components (as ``rgc check --json``)."""
    if isinstance(graph, (bytes, str)):
        text = graph.decode() if isinstance(graph, bytes) else graph
    else:
        import networkx as nx

        g = nx.convert_node_labels_to_integers(nx.Graph(graph))
        text = nx.to_graph6_bytes(g, header=False).decode()
    return json.loads(_check_graph6(text.strip(), seed))


def load_study(path: Union[str, Path]) -> dict:
    """A threshold study directory (``rgc threshold --out DIR``): its
    ``spec``, its ``records`` and, once analysed, its ``summary``. Records
    and the per-box summary are pandas DataFrames when pandas is installed,
    lists of dicts otherwise."""
    d = Path(path)
    spec_path = d / "study.json"
    if not spec_path.is_file():
        raise ValueError(f"{d}: not a study directory (no study.json)")
    spec = json.loads(spec_path.read_text())
    records = []
    for f in sorted(d.glob("records*.jsonl")):
        for n, line in enumerate(f.read_text().splitlines(), 1):
            if not line.strip():
                continue
            try:
                records.append(json.loads(line))
            except json.JSONDecodeError:
                # A run killed mid-line leaves a torn last line; the study resumes past it.
                continue
    summary_path = d / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.is_file() else None
    out = {"spec": spec, "records": records, "summary": summary}
    try:
        import pandas as pd
    except ImportError:
        return out
    out["records"] = pd.DataFrame(records)
    if summary is not None:
        out["boxes"] = pd.DataFrame(summary.get("boxes", []))
    return out
