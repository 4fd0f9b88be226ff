//! Rigid bodies: unions of rods that move as one, with the geometric class
//! that decides how they may join others (MODEL §5).

use serde::{Deserialize, Serialize};

/// Geometric class of a body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BodyClass {
    /// All rods in one plane: a 3-clique community, grown by rods touching it twice.
    Planar,
    /// Anything else.
    Spatial,
}

/// A rigid body found by compression: two or more rods.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Body {
    /// Member rods, sorted.
    pub rods: Vec<u32>,
    pub class: BodyClass,
    /// For a spatial body, the rods of each planar body it absorbed: they
    /// still lie in one plane, so their contacts with another plane are collinear.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub planes: Vec<Vec<u32>>,
}

impl Body {
    /// A body with no planar parts recorded.
    pub fn new(rods: Vec<u32>, class: BodyClass) -> Self {
        Body {
            rods,
            class,
            planes: Vec::new(),
        }
    }
}
