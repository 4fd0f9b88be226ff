"""rgc: rigidity percolation in random 3-D rod systems, from Python.

Rods go in as numpy arrays (or are generated), and results come out as
numpy arrays: contacts as (M, 2) pairs with their points and image
offsets, 3D-RGC bodies and exact rigid clusters as per-rod labels of shape
(N,). The work runs in Rust with the interpreter released; the answers are
those of the ``rgc`` command line for the same seed.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Union

import numpy as np

from ._rgc import Box, Compression, Contacts, Rods, Truth
from ._rgc import check_graph6 as _check_graph6
from ._rgc import compress, contacts, generate, truth

__all__ = [
    "Box",
    "Rods",
    "Contacts",
    "Compression",
    "Truth",
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


_from_arrays = Rods.from_arrays


def _float64(a: Any) -> Any:
    """Any array-like (float32 from OVITO or gsd, lists) as contiguous float64;
    numbers and None as they are."""
    if a is None or isinstance(a, (int, float)):
        return a
    return np.ascontiguousarray(a, dtype=np.float64)


def from_arrays(box, centres, directions=None, quaternions=None, lengths=None, radii=None, axis=(1.0, 0.0, 0.0)):
    return _from_arrays(
        box,
        _float64(centres),
        _float64(directions),
        _float64(quaternions),
        _float64(lengths),
        _float64(radii),
        tuple(float(x) for x in axis),
    )


from_arrays.__doc__ = _from_arrays.__doc__
Rods.from_arrays = staticmethod(from_arrays)  # type: ignore[method-assign]
Contacts.to_networkx = to_networkx  # type: ignore[attr-defined]
Contacts.to_rustworkx = to_rustworkx  # type: ignore[attr-defined]
Compression.motifs = property(  # type: ignore[attr-defined]
    lambda self: json.loads(self.report)["motifs"],
    doc="Motif instances compressed in the reported run, by motif.",
)


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
