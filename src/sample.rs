//! One Monte Carlo sample: rods, contacts, statistics, compression, spanning.
