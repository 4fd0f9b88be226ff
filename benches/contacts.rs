//! Contact detection per rod at the working points of gamma 23 (density 40)
//! and gamma 98 (density 190) in a box of side 10, reported as rods per
//! second so that the two compare directly. Uses rayon's global pool; set
//! RAYON_NUM_THREADS=1 for single-thread figures.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use rgc::contacts::detect;
use rgc::rods::{RodParams, RodSystem};

fn detection(c: &mut Criterion) {
    let mut group = c.benchmark_group("detect");
    group.sample_size(10);
    for (gamma, density) in [(23.0, 40.0), (98.0, 190.0)] {
        let params = RodParams::new(gamma, 10.0, density).expect("valid system");
        let system = RodSystem::generate(params, 0);
        group.throughput(Throughput::Elements(system.len() as u64));
        group.bench_function(format!("gamma {gamma} L 10"), |b| {
            b.iter(|| detect(black_box(&system)))
        });
    }
    group.finish();
}

criterion_group!(benches, detection);
criterion_main!(benches);
