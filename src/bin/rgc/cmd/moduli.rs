//! `rgc moduli`: the elastic tensor of a rod system (contact springs, rigid rods).

use clap::Args;

use crate::args::{LsmrArgs, MemoryArgs, RodsArgs};

use rgc::moduli::{self, ModuliOptions, Solver, Voigt};
use rgc::network::Network;
use rgc::sample::Rods;
use rgc::truth::TruthOptions;
use rgc::{Error, Result};

#[derive(Args)]
pub struct ModuliArgs {
    /// The rod system: read with --rods, or generated.
    #[command(flatten)]
    rods: RodsArgs,
    #[command(flatten)]
    memory: MemoryArgs,
    /// Seed of the generated rods (and of truth's realizations).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Spring stiffness k of a contact, in each direction.
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    k: f64,
    /// How the springs' least squares is solved: the sparse QR where it
    /// fits in memory, else LSMR preconditioned by the normal equations'
    /// Cholesky factor (a tenth of the QR's memory), or either alone.
    #[arg(long, value_enum, default_value_t = Solver::Auto)]
    solver: Solver,
    #[command(flatten)]
    lsmr: LsmrArgs,
    /// Print JSON instead of a summary.
    #[arg(long)]
    json: bool,
}

pub fn run(a: ModuliArgs, out: &mut String) -> Result<()> {
    if !a.rods.given() {
        return Err(Error::Parameter(
            "give a rod system: --rods FILE, or generated rods (--gamma, --box, --density)".into(),
        ));
    }
    let rods = a.rods.rods()?;
    rods.check_memory(a.memory.memory_limit)?;
    let system = match rods {
        Rods::Generated(e) => e.generate(a.seed)?,
        Rods::Read { loaded, .. } => loaded.system,
    };
    let network = Network::detect(system);
    let opts = ModuliOptions {
        stiffness: a.k,
        truth: TruthOptions {
            memory_limit: a.memory.memory_limit,
            ..TruthOptions::seeded(a.seed)
        },
        solver: a.solver,
        lsmr_iterations: a.lsmr.iterations(),
    };
    let e = moduli::of_system(network.view(), opts)?;
    if a.json {
        return super::print_json(&e, out);
    }
    say!(
        out,
        "{} rods, {} contacts; 2-core {} rods, {} contacts; realization: {}",
        e.rods,
        e.contacts,
        e.core_rods,
        e.core_contacts,
        e.realization
    );
    if let Some(m) = e.moved {
        say!(
            out,
            "it moved the contact points by {:.3} and the rods' centres by {:.3} rod lengths (root mean square)",
            m.contacts,
            m.centres
        );
    }
    say!(out, "strain rank {} (exact, from truth)", e.strain_rank);
    say!(out, "C (Voigt: xx yy zz yz xz xy), k / L_rod:");
    tensor(&e.tensor, out);
    say!(out, "Born (affine) tensor:");
    tensor(&e.born, out);
    say!(
        out,
        "G {:.6e}  K {:.6e}  (Voigt averages); Born G {:.6e}  K {:.6e}; non-affinity {}",
        e.shear,
        e.bulk,
        e.born_shear,
        e.born_bulk,
        e.nonaffinity.map_or("-".into(), |x| format!("{x:.6}"))
    );
    let c = &e.conditioning;
    let opt = |x: Option<f64>| x.map_or("-".into(), |x| format!("{x:.2e}"));
    let (steps, shift) = match c.solver {
        Solver::Lsmr => ("LSMR iterations", "mu"),
        _ => ("refinements", "lambda"),
    };
    say!(
        out,
        "conditioning: smallest kept eigenvalue {} and largest dropped {} of Born's largest; optimality {:.1e} after {} {steps}{} ({shift} {:.1e})",
        opt(c.kept),
        opt(c.dropped),
        c.optimality,
        c.steps,
        if c.settled {
            ""
        } else {
            ", not settled: the moduli are upper bounds"
        },
        c.regularization
    );
    say!(
        out,
        "seconds: {:.3} (truth {:.3}, relaxation {:.3})",
        e.seconds,
        e.truth_seconds,
        e.relaxation_seconds
    );
    Ok(())
}

fn tensor(c: &Voigt, out: &mut String) {
    for row in &c.0 {
        let cells: Vec<String> = row.iter().map(|x| format!("{x:>12.4e}")).collect();
        say!(out, "  {}", cells.join(" "));
    }
}
