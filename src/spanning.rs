//! Whether a cluster of rods spans the periodic box (DESIGN §1).
