"""Contacts, compression, truth and pattern checks: the same answers as the
command line for the same seed, arrays typed and shaped as documented."""

import json
import threading
import time

import numpy as np
import pytest

import rgc
from geometry import quaternions_onto


@pytest.fixture(scope="module")
def system():
    return rgc.generate(rgc.Box(5.0), density=40, gamma=23, seed=1)


def groups(labels):
    """Sets of indices per non-negative label."""
    out = {}
    for i, k in enumerate(labels):
        if k >= 0:
            out.setdefault(int(k), set()).add(i)
    return sorted((frozenset(v) for v in out.values()), key=lambda s: (-len(s), min(s)))


def test_contacts_match_the_command_line(system, cli, tmp_path):
    c = rgc.contacts(system)
    assert c.pairs.dtype == np.int64 and c.pairs.shape == (len(c), 2)
    assert c.points.shape == (len(c), 3) and c.params.shape == (len(c), 2)
    assert c.shifts.dtype == np.int64 and c.shifts.shape == (len(c), 3)
    assert np.all(c.pairs[:, 0] < c.pairs[:, 1])
    edges = tmp_path / "edges.txt"
    cli("sample", "--gamma", 23, "--box", 5, "--density", 40, "--seed", 1, "--save-contacts", edges)
    theirs = sorted(tuple(map(int, l.split())) for l in edges.read_text().splitlines() if l and not l.startswith("#"))
    assert sorted(map(tuple, c.pairs.tolist())) == theirs
    g = c.to_networkx()
    assert g.number_of_nodes() == len(system) and g.number_of_edges() == len(c)
    a, b = c.pairs[0]
    assert np.array_equal(g.edges[int(a), int(b)]["point"], c.points[0])
    assert np.array_equal(g.edges[int(a), int(b)]["shift"], c.shifts[0])


def test_compression_matches_the_command_line(system, cli, tmp_path):
    k = rgc.compress(system, rules="sound", runs=2, seed=1)
    assert k.body_idx.dtype == np.int64 and k.body_idx.shape == (len(system),)
    bodies = tmp_path / "bodies.json"
    report = json.loads(
        cli("sample", "--gamma", 23, "--box", 5, "--density", 40, "--seed", 1, "--runs", 2, "--save-bodies", bodies, "--json")
    )
    theirs = json.loads(bodies.read_text())
    assert theirs["run"] == k.run
    ours = groups(k.body_idx)
    assert ours == sorted((frozenset(b["rods"]) for b in theirs["bodies"]), key=lambda s: (-len(s), min(s)))
    assert k.spans.tolist() == [b["spans"] for b in theirs["bodies"]]
    assert k.spanning == report["rigid_spanning"]
    assert k.motifs == report["motifs"] and sum(k.motifs.values()) > 0


def test_truth_matches_the_command_line(system, cli):
    t = rgc.truth(system, seed=1)
    theirs = json.loads(cli("truth", "--gamma", 23, "--box", 5, "--density", 40, "--seed", 1, "--json"))
    assert t.method == theirs["method"] == "exact" and not t.undecided
    assert t.dof == theirs["dof"]
    assert t.spanning == theirs["spanning"]
    assert [c.tolist() for c in t.clusters] == [c["rods"] for c in theirs["clusters"]]
    # A spanning cluster at rho 40 resists every strain of the box.
    assert t.strain_rank == theirs["strains"]["rank"] == 6
    assert t.strains_resisted == theirs["strains"]["resisted"] == ["xx", "yy", "zz", "yz", "xz", "xy"]
    assert t.strains_considered == t.strains_resisted and t.strain_reason is None
    # Every rod's label is the largest cluster holding it.
    assert t.cluster_idx.dtype == np.int64 and t.cluster_idx.shape == (len(system),)
    for k, c in enumerate(t.clusters):
        assert np.all(t.cluster_idx[c] <= k)


def test_solid_truth_asks_for_all_six_strains(system, cli):
    # At rho 40 the rods resist all six strains; at rho 20 they wrap no
    # rigid cluster and resist fewer, so the system is not a solid.
    for density, solid in ((40, True), (20, False)):
        rods = system if density == 40 else rgc.generate(rgc.Box(5.0), density=density, gamma=23, seed=1)
        t = rgc.truth(rods, criterion="solid", seed=1)
        theirs = json.loads(
            cli("truth", "--gamma", 23, "--box", 5, "--density", density, "--seed", 1, "--criterion", "solid", "--json")
        )
        assert t.spanning is theirs["spanning"] is solid
        assert (t.strain_rank == 6) is solid and t.strain_rank == theirs["strains"]["rank"]


def test_rods_from_a_csv_equivalent_give_the_same_truth(system, cli, tmp_path):
    csv = tmp_path / "rods.csv"
    rows = np.column_stack([system.centres, system.directions, system.lengths, system.radii])
    np.savetxt(csv, rows, delimiter=",", header="x,y,z,dx,dy,dz,length,radius", comments="", fmt="%.17g")
    theirs = json.loads(cli("truth", "--rods", csv, "--box", 5, "--json"))
    again = rgc.Rods.from_arrays(rgc.Box(5.0), rows[:, :3], directions=rows[:, 3:6], lengths=rows[:, 6], radii=rows[:, 7])
    t = rgc.truth(again)
    assert t.dof == theirs["dof"] and [c.tolist() for c in t.clusters] == [c["rods"] for c in theirs["clusters"]]


def test_centred_quaternion_input_gives_the_contacts_of_the_equivalent_csv(system, cli, tmp_path):
    csv = tmp_path / "rods.csv"
    rows = np.column_stack([system.centres, system.directions, system.lengths, system.radii])
    np.savetxt(csv, rows, delimiter=",", header="x,y,z,dx,dy,dz,length,radius", comments="", fmt="%.17g")
    edges = tmp_path / "edges.txt"
    cli("sample", "--rods", csv, "--box", 5, "--save-contacts", edges)
    theirs = sorted(tuple(map(int, l.split())) for l in edges.read_text().splitlines() if l and not l.startswith("#"))
    hoomd = rgc.Rods.from_arrays(rgc.Box(5.0, centred=True), system.centres - 2.5,
                                 quaternions=quaternions_onto(system.directions),
                                 lengths=system.lengths, radii=system.radii)
    assert sorted(map(tuple, rgc.contacts(hoomd).pairs.tolist())) == theirs


def test_check_takes_graph6_and_networkx():
    nx = pytest.importorskip("networkx")
    # The triangular prism: rigid only where its two triangles' planes allow.
    assert rgc.check("E{Sw")["class"] == "component-dependent"
    # K_{3,3} without forced planes is flexible; two triangles sharing an edge are not rods-only Maxwell.
    v = rgc.check(nx.complete_bipartite_graph(3, 3))
    assert v["class"] in ("flexible", "component-dependent") and v["rigid"] is not True
    with pytest.raises(ValueError):
        rgc.check("not graph6 at all!")


def test_bad_names_are_value_errors(system):
    with pytest.raises(ValueError, match="rules must be 'sound', 'paper' or 'certified'"):
        rgc.compress(system, rules="fast")
    with pytest.raises(ValueError, match="criterion must be 'wrap', 'faces' or 'solid', got \"corners\""):
        rgc.truth(system, criterion="corners")
    with pytest.raises(ValueError, match="criterion must be 'wrap' or 'faces', got \"corners\""):
        rgc.compress(system, criterion="corners")
    with pytest.raises(ValueError, match="criterion 'solid' needs the exact truth"):
        rgc.compress(system, criterion="solid")
    with pytest.raises(ValueError, match="runs must be an integer from 1 to 100000, got 0"):
        rgc.compress(system, runs=0)


def test_the_interpreter_runs_on_during_truth():
    big = rgc.generate(rgc.Box(8.0), density=36, gamma=23, seed=2)
    ticks = 0
    worker = threading.Thread(target=rgc.truth, args=(big,))
    worker.start()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    assert ticks > 20, f"the main thread ran {ticks} times while truth worked"


def test_load_study_reads_a_committed_study(root):
    s = rgc.load_study(root / "results" / "g48-truth")
    assert s["spec"]["kind"] == "truth" and s["spec"]["gamma"] == 48.0
    assert len(s["records"]) == 400
    assert s["summary"]["study"]["boxes"] == [5.0, 6.0, 7.0, 8.0]
    with pytest.raises(ValueError, match="not a study directory"):
        rgc.load_study(root / "results")


def test_moduli_match_the_command_line(cli):
    rods = rgc.generate(rgc.Box(3.0), density=38, gamma=23, seed=1)
    m = rgc.moduli(rods, k=2.0, seed=1)
    theirs = json.loads(cli("moduli", "--gamma", 23, "--box", 3, "--density", 38, "--seed", 1, "--k", 2, "--json"))
    assert m["strain_rank"] == theirs["strain_rank"] == 6
    assert m["tensor"].shape == (6, 6) and m["tensor"].dtype == np.float64
    assert np.allclose(m["tensor"], np.asarray(theirs["tensor"]), rtol=1e-9, atol=0)
    # Symmetric, positive definite at rank 6, under the Born tensor.
    assert np.array_equal(m["tensor"], m["tensor"].T)
    assert np.linalg.eigvalsh(m["tensor"]).min() > 0
    assert np.linalg.eigvalsh(m["born"] - m["tensor"]).min() > -1e-9 * m["born"].max()
    assert 0 < m["shear"] < m["born_shear"]
    with pytest.raises(ValueError, match="stiffness k must be positive"):
        rgc.moduli(rods, k=-1.0)
    # LSMR gives the QR's tensor, and says it ran.
    by_lsmr = rgc.moduli(rods, k=2.0, seed=1, solver="lsmr")
    assert (m["conditioning"]["solver"], by_lsmr["conditioning"]["solver"]) == ("qr", "lsmr")
    assert np.allclose(by_lsmr["tensor"], m["tensor"], rtol=1e-8, atol=1e-12 * m["born"].max())
    with pytest.raises(ValueError, match="solver must be 'auto', 'qr' or 'lsmr'"):
        rgc.moduli(rods, solver="cg")
    # Cut short, LSMR says so, and its energies (so G) stand above the
    # settled ones: an upper bound.
    short = rgc.moduli(rods, k=2.0, seed=1, solver="lsmr", lsmr_iterations=1)
    assert by_lsmr["conditioning"]["settled"] and not short["conditioning"]["settled"]
    assert short["conditioning"]["steps"] == 6
    assert short["shear"] > by_lsmr["shear"] * (1 + 1e-6)
    with pytest.raises(ValueError, match="lsmr_iterations must be an integer from 1"):
        rgc.moduli(rods, solver="lsmr", lsmr_iterations=0)
