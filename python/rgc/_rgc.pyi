"""Type stubs of the compiled core (see ``rgc`` for the documented API)."""

from typing import Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

Float64Array = npt.NDArray[np.float64]
Int64Array = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]

MAX_RUNS: int

class Box:
    """A box [0, L_x) x [0, L_y) x [0, L_z) and its periodic axes ('xyz', 'xy' or 'none');
    ``centred`` boxes ([-L/2, L/2), HOOMD's and freud's) take points in that frame and give
    them back in it. Pickles."""

    def __init__(
        self, *sides: Union[float, Sequence[float]], periodic: str = "xyz", centred: bool = False
    ) -> None:
        """``Box(L)``, ``Box([Lx, Ly, Lz])`` or ``Box(Lx, Ly, Lz)``."""
    @property
    def sides(self) -> Float64Array:
        """Side lengths, shape (3,)."""
    @property
    def periodic(self) -> str: ...
    @property
    def centred(self) -> bool: ...
    @property
    def volume(self) -> float: ...
    def wrap(self, points: npt.ArrayLike) -> Float64Array:
        """Points (N, 3) wrapped into the box along periodic axes, in its own frame."""

class Rods:
    """A checked rod system in a box, shown in the frame of the box it was given in. Pickles."""

    @staticmethod
    def from_arrays(
        box: Box,
        centres: npt.ArrayLike,
        directions: Optional[npt.ArrayLike] = None,
        quaternions: Optional[npt.ArrayLike] = None,
        lengths: Union[float, npt.ArrayLike, None] = None,
        radii: Union[float, npt.ArrayLike, None] = None,
        axis: Tuple[float, float, float] = (1.0, 0.0, 0.0),
    ) -> "Rods":
        """Rods from centres (N, 3) in the box's frame and directions (N, 3) or quaternions
        (N, 4), (w, x, y, z) rotating ``axis``; lengths and radii are numbers (numpy scalars
        too) or (N,) arrays, of any real dtype. ValueError for complex or text input, wrong
        shapes and refused rods; MemoryError before allocating rods too many for memory."""
    @staticmethod
    def _from_arrays(
        box: Box,
        centres: Float64Array,
        directions: Optional[Float64Array],
        quaternions: Optional[Float64Array],
        length: Optional[float],
        lengths: Optional[Float64Array],
        radius: Optional[float],
        radii: Optional[Float64Array],
        axis: Tuple[float, float, float],
    ) -> "Rods":
        """``from_arrays`` after the Python layer's conversion: float64 arrays, each size a number or an array."""
    def __len__(self) -> int: ...
    @property
    def box(self) -> Box:
        """The box the rods were given in (centred if it was)."""
    @property
    def centres(self) -> Float64Array:
        """Centres in the box's frame ([-L/2, L/2) along periodic axes if centred), shape (N, 3)."""
    @property
    def directions(self) -> Float64Array:
        """Unit directions, shape (N, 3)."""
    @property
    def lengths(self) -> Float64Array:
        """Core lengths, shape (N,)."""
    @property
    def radii(self) -> Float64Array:
        """Radii, shape (N,)."""
    @property
    def cut(self) -> int:
        """Rods whose cores were cut at a wall."""
    @property
    def density(self) -> float: ...

class Contacts:
    """Contacts of a rod system, one row each. Pickles."""

    def __len__(self) -> int: ...
    @property
    def pairs(self) -> Int64Array:
        """The two rods of each contact, first < second, shape (M, 2)."""
    @property
    def points(self) -> Float64Array:
        """Contact points wrapped into the box, in its frame, shape (M, 3)."""
    @property
    def params(self) -> Float64Array:
        """Arc length from each rod's centre to its closest point, shape (M, 2)."""
    @property
    def shifts(self) -> Int64Array:
        """Image of the second rod touching the first, in box sides, shape (M, 3)."""
    @property
    def n_rods(self) -> int: ...
    def to_networkx(self) -> object: ...
    def to_rustworkx(self) -> object: ...

class Compression:
    """The bodies of one 3D-RGC run (the first that spans, else the one with the largest body).
    Pickles."""

    @property
    def body_idx(self) -> Int64Array:
        """Per rod its body (largest first) or -1, shape (N,)."""
    @property
    def spans(self) -> BoolArray:
        """Per body whether it spans, shape (B,)."""
    @property
    def motifs(self) -> dict[str, int]:
        """Motif instances compressed in the reported run, by motif."""
    spanning: bool
    runs_spanning: int
    run: int
    report: str

class Truth:
    """Rigid clusters of the exact truth and the degrees of freedom. Pickles."""

    @property
    def cluster_idx(self) -> Int64Array:
        """Per rod the largest rigid cluster holding it or -1, shape (N,)."""
    @property
    def clusters(self) -> list[Int64Array]:
        """Each cluster's rods, largest first."""
    @property
    def undecided(self) -> bool: ...
    dof: Optional[int]
    spanning: Optional[bool]
    method: str
    reason: Optional[str]
    memory_refused: bool
    report: str
    strain_rank: Optional[int]
    """Strains of the box resisted (6: a solid), over ``strains_considered``; None where unknown."""
    strains_resisted: list[str]
    """The coordinate strains resisted alone: 'xx', 'yy', 'zz', 'yz', 'xz', 'xy'."""
    strains_considered: list[str]
    """The strains of the periodic axes."""
    strain_reason: Optional[str]

def generate(
    box: Box,
    density: float,
    gamma: Optional[float] = None,
    radius: Union[float, str, None] = None,
    length: Union[float, str, None] = None,
    order: Optional[float] = None,
    director: Optional[Tuple[float, float, float]] = None,
    seed: int = 1,
) -> Rods: ...
def contacts(rods: Rods) -> Contacts: ...
def compress(rods: Rods, rules: str = "sound", runs: int = 1, seed: int = 1, criterion: str = "wrap") -> Compression:
    """runs from 1 to MAX_RUNS (100,000, the command line's cap), else ValueError."""
def moduli(rods: Rods, k: float = 1.0, seed: int = 1, memory_limit: Optional[int] = None, solver: str = "auto", lsmr_iterations: int = 10000) -> str:
    """The moduli as the JSON text of ``rgc moduli --json`` (``rgc.moduli`` reads it into arrays)."""

def truth(rods: Rods, criterion: str = "wrap", seed: int = 1, memory_limit: Optional[int] = None) -> Truth:
    """The answer as it is, undecided too (``rgc.truth`` raises ``UndecidedError`` for that)."""
def check_graph6(graph6: str, seed: int = 1) -> str: ...
