//! Whether the engine compresses a pattern to one node: the question the
//! audit, the mined motifs and the derived base rules put to it, asked of
//! the pattern's host (its rods, with its bodies declared rigid) over the
//! motif orders `0..runs`.

use super::compression::Compression;
use super::run::Engine;
use crate::Result;
use crate::body::Body;
use crate::graph::ContactGraph;
use crate::pattern::Pattern;

impl Engine<'_> {
    /// Whether the engine compresses `pattern` to one node in any of `runs` orders.
    pub fn compresses(&self, pattern: &Pattern, runs: u64) -> Result<bool> {
        Ok(self.compressing_run(pattern, runs)?.is_some())
    }

    /// Whether the engine compresses `pattern` to one node in every one of `runs` orders.
    pub fn always_compresses(&self, pattern: &Pattern, runs: u64) -> Result<bool> {
        let (graph, bodies, _) = pattern.to_host()?;
        for seed in 0..runs {
            if self.compress(&graph, &bodies, seed)?.components != 1 {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// The first of `runs` motif orders (seeds `0..runs`) in which the engine
    /// compresses `pattern` to one node: its seed and the compression.
    pub fn compressing_run(
        &self,
        pattern: &Pattern,
        runs: u64,
    ) -> Result<Option<(u64, Compression)>> {
        let (graph, bodies, _) = pattern.to_host()?;
        self.compressing_run_from(&graph, &bodies, runs)
    }

    /// [`Engine::compressing_run`] on a host already built: `graph` with
    /// `bodies` declared rigid (as [`Pattern::to_host`] builds it).
    pub fn compressing_run_from(
        &self,
        graph: &ContactGraph,
        bodies: &[Body],
        runs: u64,
    ) -> Result<Option<(u64, Compression)>> {
        for seed in 0..runs {
            let c = self.compress(graph, bodies, seed)?;
            if c.components == 1 {
                return Ok(Some((seed, c)));
            }
        }
        Ok(None)
    }
}
