//! `rgc enumerate`: non-isomorphic connected graphs, streamed as graph6.

use std::io::Write;

use clap::Args;
use rgc::enumerate::GraphFilter;
use rgc::{Error, Result};

#[derive(Args)]
pub struct EnumerateArgs {
    /// Number of nodes.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=12))]
    nodes: u64,
    /// Smallest degree.
    #[arg(long, default_value_t = 0)]
    min_degree: usize,
    /// Maxwell's count for rods: at least ceil((5n - 6) / 3) edges.
    #[arg(long)]
    maxwell: bool,
    /// Fewest edges.
    #[arg(long)]
    min_edges: Option<usize>,
    /// Most edges.
    #[arg(long)]
    max_edges: Option<usize>,
    /// Print only the count.
    #[arg(long)]
    count: bool,
}

/// Writes straight to stdout: there can be millions of lines.
pub fn run(a: EnumerateArgs) -> Result<()> {
    let n = a.nodes as usize;
    let mut filter = if a.maxwell {
        GraphFilter::maxwell_rods(n)
    } else {
        GraphFilter::all()
    };
    filter = filter.with_min_degree(a.min_degree);
    if let Some(m) = a.min_edges {
        filter.min_edges = filter.min_edges.max(m);
    }
    if let Some(m) = a.max_edges {
        filter.max_edges = m;
    }
    if a.count {
        println!("{}", rgc::enumerate::count_connected(n, &filter)?);
        return Ok(());
    }
    let stdout = std::io::stdout();
    let mut w = std::io::BufWriter::new(stdout.lock());
    match rgc::enumerate::write_connected_graph6(n, &filter, &mut w).and_then(|_| w.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(Error::io("stdout", e)),
        _ => Ok(()),
    }
}
