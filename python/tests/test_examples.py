"""The README's examples run for real where their packages install: a
HOOMD trajectory read with gsd, and the optional graph libraries."""

import numpy as np
import pytest

import rgc
from geometry import quaternions_onto


def test_a_gsd_trajectory_frame_by_frame(tmp_path):
    gsd_hoomd = pytest.importorskip("gsd.hoomd", reason="gsd did not install from PyPI")
    path = tmp_path / "traj.gsd"
    systems = [rgc.generate(rgc.Box(5.0), density=40, gamma=23, seed=s) for s in (1, 2)]
    with gsd_hoomd.open(path, "w") as f:
        for step, sys in enumerate(systems):
            frame = gsd_hoomd.Frame()
            frame.configuration.step = step
            frame.configuration.box = [5.0, 5.0, 5.0, 0, 0, 0]
            frame.particles.N = len(sys)
            frame.particles.position = (sys.centres - 2.5).astype(np.float32)
            frame.particles.orientation = quaternions_onto(sys.directions).astype(np.float32)
            f.append(frame)
    seen = []
    with gsd_hoomd.open(path) as traj:
        for frame in traj:
            box = rgc.Box(frame.configuration.box[:3], centred=True)
            rods = rgc.Rods.from_arrays(box, frame.particles.position.astype(np.float64),
                                        quaternions=frame.particles.orientation.astype(np.float64),
                                        lengths=1.0, radii=1.0 / 46)
            t = rgc.truth(rods)
            seen.append((len(rods), t.method, t.dof))
    assert [s[0] for s in seen] == [5000, 5000]
    assert all(m == "exact" and d is not None for _, m, d in seen)
    # float32 storage moves the rods a little; the systems are still the two drawn.
    assert seen[0][2] != seen[1][2]


def test_contacts_as_a_rustworkx_graph():
    rx = pytest.importorskip("rustworkx", reason="rustworkx is optional")
    sys = rgc.generate(rgc.Box(4.0), density=30, gamma=10, seed=3)
    c = rgc.contacts(sys)
    g = c.to_rustworkx()
    assert isinstance(g, rx.PyGraph)
    assert g.num_nodes() == len(sys) and g.num_edges() == len(c)


def test_load_study_gives_data_frames_with_pandas(root):
    pd = pytest.importorskip("pandas", reason="pandas is optional")
    s = rgc.load_study(root / "results" / "g48-truth")
    assert isinstance(s["records"], pd.DataFrame) and len(s["records"]) == 400
    assert list(s["boxes"]["box"]) == [5.0, 6.0, 7.0, 8.0]
