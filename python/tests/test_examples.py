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


def readme_ovito_modifier(frame, data):
    """The README's OVITO modifier, verbatim but for its name."""
    cell = data.cell
    box = rgc.Box(np.diag(cell.matrix[:, :3]), periodic="xyz")
    rods = rgc.Rods.from_arrays(box, data.particles.positions - cell.matrix[:, 3],
                                quaternions=data.particles.orientations[:, [3, 0, 1, 2]],
                                lengths=1.0, radii=np.asarray(data.particles["Radius"]))
    data.particles_.create_property("body", data=rgc.compress(rods).body_idx)
    data.particles_.create_property("true_cluster", data=rgc.truth(rods).cluster_idx)


def test_the_readme_ovito_modifier_in_a_pipeline():
    pytest.importorskip("ovito", reason="ovito (a large download with Qt) is optional: .ci/run does not install it")
    from ovito.data import DataCollection
    from ovito.pipeline import Pipeline, PythonSource

    sys = rgc.generate(rgc.Box(5.0), density=40, gamma=23, seed=1)

    def source(frame, data):
        cell = np.zeros((3, 4))
        cell[:, :3] = np.diag([5.0, 5.0, 5.0])
        cell[:, 3] = -2.5
        data.create_cell(cell, pbc=(True, True, True))
        p = data.create_particles(count=len(sys))
        p.create_property("Position", data=sys.centres - 2.5)
        # OVITO keeps quaternions as (x, y, z, w).
        p.create_property("Orientation", data=quaternions_onto(sys.directions)[:, [1, 2, 3, 0]])
        p.create_property("Radius", data=sys.radii)

    pipeline = Pipeline(source=PythonSource(function=source))
    pipeline.modifiers.append(readme_ovito_modifier)
    out = pipeline.compute()
    assert np.array_equal(np.asarray(out.particles["body"]), rgc.compress(sys).body_idx)
    assert np.array_equal(np.asarray(out.particles["true_cluster"]), rgc.truth(sys).cluster_idx)
