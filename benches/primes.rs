//! The cost of ranking whole systems in a larger prime (MODEL §10): a dense
//! front eliminated over F_q, `q < 2^24`, by the f64 kernel truth uses,
//! against the same front over F_p, `p = 2^61 - 1`, by the 64-bit
//! elimination the motif verdicts use. Square fronts of random residues,
//! one thread; the ratio of the two medians is the price of a prime for
//! which the Schwartz–Zippel bound would be 2^37 times smaller.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rgc::math::echelon::{Block, Modulus};
use rgc::math::{Fp, Matrix, rank_fp};

fn fronts(c: &mut Criterion) {
    let mut group = c.benchmark_group("dense front");
    group.sample_size(10);
    for n in [256, 512] {
        let mut rng = ChaCha8Rng::seed_from_u64(n as u64);
        let modulus = Modulus::new(16_777_213);
        let small: Vec<f64> = (0..n * n)
            .map(|_| modulus.centre(rng.random_range(0..16_777_213)))
            .collect();
        let mut large = Matrix::zeros(n, n);
        for i in 0..n {
            for j in 0..n {
                large.set(i, j, Fp::random(&mut rng));
            }
        }
        group.bench_function(format!("F_q (q < 2^24, f64 kernel) {n} x {n}"), |b| {
            b.iter(|| {
                let mut data = small.clone();
                let mut block = Block {
                    data: &mut data,
                    rows: n,
                    cols: n,
                    modulus,
                };
                black_box(block.echelon(0, 0, n, &mut Vec::new()))
            })
        });
        group.bench_function(format!("F_p (p = 2^61 - 1) {n} x {n}"), |b| {
            b.iter(|| black_box(rank_fp(&large)))
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    // Criterion's charts need fonts a bare machine lacks.
    config = Criterion::default().without_plots();
    targets = fronts
}
criterion_main!(benches);
