//! Contact detection per rod at the working points of gamma 23 (density 40)
//! and gamma 98 (density 190) in a box of side 10, and on unequal, aligned
//! rods (lognormal lengths, uniform radii, order 0.7) at density 40, reported
//! as rods per second so that they compare directly. Uses rayon's global
//! pool; set RAYON_NUM_THREADS=1 for single-thread figures.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use rgc::contacts::detect;
use rgc::rods::ensemble::{Dist, Ensemble, Orientation};
use rgc::rods::{Domain, RodParams, RodSystem};

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
    let unequal = Ensemble {
        domain: Domain::cube(10.0),
        density: 40.0,
        length: Dist::Lognormal { mean: 1.0, sd: 0.3 },
        radius: Dist::Uniform { lo: 0.01, hi: 0.03 },
        orientation: Orientation::Aligned {
            order: 0.7,
            director: [0.0, 0.0, 1.0],
        },
    };
    let system = unequal.generate(0).expect("valid system");
    group.throughput(Throughput::Elements(system.len() as u64));
    group.bench_function("unequal aligned L 10", |b| {
        b.iter(|| detect(black_box(&system)))
    });
    group.finish();
}

criterion_group! {
    name = benches;
    // Plots need system fonts that a bare machine lacks.
    config = Criterion::default().without_plots();
    targets = detection
}
criterion_main!(benches);
