//! The verified base rules the `sound` engine checks 3D3A, 3D3B and 3D4
//! against (MODEL §5), compiled in from `motifs/base.json`, which
//! `shapes` derives.

use std::sync::OnceLock;

use super::rule::CompiledRule;
use crate::rule_file::{Rule, RuleFile};

/// The verified base rules, as `rgc rules` writes them to `motifs/base.json`:
/// deriving them again costs every process about 50 ms of exact rank, and a
/// test checks that the file is what `shapes::base_rules` derives.
const BASE_RULES: &str = include_str!("../../motifs/base.json");

/// The verified rules the `sound` engine uses for 3D3A, 3D3B and 3D4,
/// read once per process from [`BASE_RULES`].
pub(super) fn sound_rules() -> &'static [CompiledRule] {
    static RULES: OnceLock<Vec<CompiledRule>> = OnceLock::new();
    RULES.get_or_init(|| {
        sound_subset(&committed_base_rules())
            .map(CompiledRule::new)
            .collect()
    })
}

/// The rules of `motifs/base.json`.
pub(super) fn committed_base_rules() -> Vec<Rule> {
    let file: RuleFile = serde_json::from_str(BASE_RULES).expect("motifs/base.json is a rule file");
    file.rules
}

/// The rules of 3D3A, 3D3B and 3D4 among the base rules.
pub(super) fn sound_subset(rules: &[Rule]) -> impl Iterator<Item = &Rule> {
    rules.iter().filter(|r| {
        ["3D3A", "3D3B", "3D4"]
            .iter()
            .any(|m| r.id.starts_with(&format!("base-{m}-")))
    })
}
