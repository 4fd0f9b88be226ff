//! What a bias study measures: truth first, then every variant paired with
//! it, all in the nested protocol.

use std::path::PathBuf;

use crate::engine::RuleSet;
use crate::threshold::fss::Protocol;
use crate::threshold::sequence::Kind;
use crate::threshold::variants::{Design, Pairing, Variant};
use crate::{Error, Result};

/// Truth first, then every variant it measures, each paired with truth:
/// the paper's and the sound base motifs, certified compression, 10 and
/// 40 runs per system, the sound base motifs with the `extended` rule files
/// (enumerated), and with the `mined` ones (found in real systems, where
/// truth saw rigidity the engine missed).
pub fn truth_design(sequences: u64, extended: &[PathBuf], mined: &[PathBuf]) -> Design {
    let v = |label: &str, family: &str| Variant::sound_base(label, family, sequences);
    Design {
        variants: vec![
            Variant {
                kind: Kind::Truth,
                ..v("truth", "truth")
            },
            Variant {
                rules: RuleSet::Paper,
                ..v("paper", "rules")
            },
            v("sound", "rules"),
            Variant {
                rules: RuleSet::Certified,
                ..v("certified", "rules")
            },
            Variant {
                runs: 10,
                ..v("sound K=10", "runs")
            },
            Variant {
                runs: 40,
                ..v("sound K=40", "runs")
            },
            Variant {
                motifs: extended.to_vec(),
                ..v("sound + extended", "motifs")
            },
            Variant {
                motifs: mined.to_vec(),
                ..v("sound + mined", "motifs")
            },
        ],
        pairing: Pairing::First,
    }
}

/// The design must measure against truth: truth first, the nested
/// protocol everywhere (a paired critical density needs one per sequence).
pub fn check_design(design: &Design) -> Result<()> {
    match design.variants.first() {
        Some(v) if v.kind == Kind::Truth => {}
        _ => {
            return Err(Error::Parameter(
                "a bias design measures against truth: its first variant must be of kind truth"
                    .into(),
            ));
        }
    }
    if let Some(v) = design
        .variants
        .iter()
        .find(|v| v.method != Protocol::Nested)
    {
        return Err(Error::Parameter(format!(
            "variant {:?}: paired critical densities need the nested protocol",
            v.label
        )));
    }
    Ok(())
}
