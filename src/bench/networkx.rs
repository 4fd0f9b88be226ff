//! The networkx reference: the whole `rgc sample` process against
//! networkx's first RGC step (3-clique communities merged into bodies) on
//! the same system, interleaved, and the foundation benchmark's figures
//! with that comparison.

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use serde::Serialize;

use super::foundation::{BenchReport, RULES_SYSTEM};
use super::measure::{failed, run_child};
use crate::math::stats::median;
use crate::{Error, Result};

/// The foundation benchmark's figures, with the networkx comparison when
/// asked: what `rgc bench` prints and writes.
#[derive(Serialize)]
pub struct Foundation {
    #[serde(flatten)]
    pub report: BenchReport,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub networkx: Option<Networkx>,
}

/// The whole `rgc sample` process against networkx, interleaved, medians.
#[derive(Clone, Debug, Serialize)]
pub struct Networkx {
    pub networkx_version: String,
    /// Wall time of the whole `rgc sample` process (generation, contacts,
    /// statistics, compression, JSON), median.
    pub rgc_sample_seconds: f64,
    /// networkx's first step on the saved contact graph, median: 3-clique
    /// communities, communities sharing a rod merged, and the quotient graph.
    pub networkx_seconds: f64,
    /// The median of networkx's time over ours, each pair measured in the
    /// same repetition, so a change of load biases both alike.
    pub ratio: f64,
    pub repeat: usize,
}

/// networkx's first RGC step, timed inside Python (reading the graph and
/// importing networkx are not counted): the edge list is `argv[1]`.
pub const NETWORKX_STEP: &str = r#"
import sys, time
import networkx as nx
from networkx.algorithms.community import k_clique_communities
lines = open(sys.argv[1]).read().splitlines()
n = int(lines[0].split()[2])
G = nx.Graph()
G.add_nodes_from(range(n))
G.add_edges_from(tuple(map(int, l.split())) for l in lines[1:] if l and not l.startswith('#'))
t = time.perf_counter()
parent = list(range(n))
def find(x):
    while parent[x] != x:
        parent[x] = parent[parent[x]]
        x = parent[x]
    return x
for c in k_clique_communities(G, 3):
    c = list(c)
    for v in c[1:]:
        a, b = find(c[0]), find(v)
        if a != b:
            parent[a] = b
H = nx.Graph()
H.add_nodes_from(find(v) for v in range(n))
H.add_edges_from((find(a), find(b)) for a, b in G.edges() if find(a) != find(b))
print(time.perf_counter() - t)
"#;

/// The version of networkx under `python`; an error saying how to get it
/// where there is none, so `--networkx` fails before the benchmark runs.
pub fn networkx_version(python: &Path) -> Result<String> {
    let child = Command::new(python)
        .args(["-c", "import networkx; print(networkx.__version__)"])
        .output();
    let why = match &child {
        Ok(c) if c.status.success() => None,
        Ok(c) => Some(String::from_utf8_lossy(&c.stderr).trim().to_string()),
        Err(e) => Some(e.to_string()),
    };
    if let Some(why) = why {
        return Err(Error::Parameter(format!(
            "--networkx needs {} with networkx (pip install networkx): {why}",
            python.display()
        )));
    }
    let child = child.map_err(|e| Error::io(python, e))?;
    Ok(String::from_utf8_lossy(&child.stdout).trim().to_string())
}

/// Times the whole `rgc sample` process of the executable `rgc` on
/// [`RULES_SYSTEM`] against networkx's first step (under `python`) on that
/// system's contact graph, `repeat` times interleaved.
pub fn against_networkx(rgc: &Path, python: &Path, repeat: usize) -> Result<Networkx> {
    let networkx_version = networkx_version(python)?;
    let dir = std::env::temp_dir().join(format!("rgc-bench-networkx-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    let graph = dir.join("contacts.txt");
    let (gamma, density, l) = RULES_SYSTEM;
    let sample = [
        "sample".to_string(),
        format!("--gamma={gamma}"),
        format!("--box={l}"),
        format!("--density={density}"),
        "--json".to_string(),
    ];
    run_child(
        Command::new(rgc)
            .args(&sample)
            .arg("--save-contacts")
            .arg(&graph),
        rgc,
        "rgc sample",
    )?;
    let (mut ours, mut theirs) = (Vec::new(), Vec::new());
    for _ in 0..repeat.max(1) {
        let t = Instant::now();
        let child = Command::new(rgc)
            .args(&sample)
            .output()
            .map_err(|e| Error::io(rgc, e))?;
        ours.push(t.elapsed().as_secs_f64());
        if !child.status.success() {
            return Err(failed("rgc sample", &child));
        }
        let child = run_child(
            Command::new(python).args(["-c", NETWORKX_STEP]).arg(&graph),
            python,
            "python3 (networkx)",
        )?;
        let seconds: f64 = String::from_utf8_lossy(&child.stdout)
            .trim()
            .parse()
            .map_err(|_| failed("python3 (networkx): no time printed", &child))?;
        theirs.push(seconds);
    }
    std::fs::remove_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    let mut ratios: Vec<f64> = theirs.iter().zip(&ours).map(|(t, o)| t / o).collect();
    Ok(Networkx {
        networkx_version,
        rgc_sample_seconds: median(&mut ours),
        networkx_seconds: median(&mut theirs),
        ratio: median(&mut ratios),
        repeat: repeat.max(1),
    })
}
