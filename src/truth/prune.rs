//! The 2-core: what can be rigid at all (MODEL §10).
//!
//! A rod with one contact turns about it, and a rod with none is free, so
//! neither is rigid with anything, and removing it leaves the rigidity of
//! the rest unchanged. Removing such rods until none is left gives the
//! 2-core. Each removed rod adds its own motions: 5 when it is free, 2 when
//! one contact (3 independent conditions) holds it.

use crate::graph::ContactGraph;

/// The 2-core of a contact graph and the motions of what was removed.
#[derive(Clone, Debug)]
pub struct Core {
    /// Whether each rod is in the 2-core.
    pub active: Vec<bool>,
    /// For each removed rod, its contacts when it was removed (0 or 1).
    pub removed: Vec<(u32, u8)>,
}

impl Core {
    pub fn rods(&self) -> usize {
        self.active.iter().filter(|&&a| a).count()
    }

    /// Contacts with both rods in the core.
    pub fn contacts(&self, graph: &ContactGraph) -> usize {
        graph
            .edges()
            .iter()
            .filter(|&&[a, b]| self.active[a as usize] && self.active[b as usize])
            .count()
    }

    /// The motions the removed rods add: `5 - 3 * contacts` each.
    pub fn pruned_motions(&self) -> usize {
        self.removed.iter().map(|&(_, d)| 5 - 3 * d as usize).sum()
    }
}

/// Removes rods with fewer than two contacts until none is left.
pub fn two_core(graph: &ContactGraph) -> Core {
    let (active, removed) = graph.two_core();
    Core { active, removed }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_triangle_with_a_tail_keeps_the_triangle() {
        // Triangle 0-1-2, path 2-3-4, isolated rod 5.
        let g = ContactGraph::new(6, vec![[0, 1], [1, 2], [0, 2], [2, 3], [3, 4]]).unwrap();
        let core = two_core(&g);
        assert_eq!(core.active, vec![true, true, true, false, false, false]);
        // Rod 5: 5 motions; rods 4 then 3: 2 each.
        assert_eq!(core.pruned_motions(), 9);
        assert_eq!(core.contacts(&g), 3);
    }
}
