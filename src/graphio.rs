//! graph6 and edge-list input and output.
