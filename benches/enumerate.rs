//! Enumeration speed: counting and graph6 writing of connected graphs (the
//! figures to set against nauty's `geng -cu n` and `geng -c n > /dev/null`),
//! canonical forms, and typed patterns. Uses rayon's global pool; set
//! RAYON_NUM_THREADS=1 for single-thread figures.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use rgc::enumerate::{
    GraphFilter, TypedFilter, canonical_graph6, connected_graphs, count_connected, typed_patterns,
    write_connected_graph6,
};

fn graphs(c: &mut Criterion) {
    let mut group = c.benchmark_group("connected");
    group.sample_size(10);
    for n in [8, 9] {
        group.bench_function(format!("count n={n}"), |b| {
            b.iter(|| count_connected(black_box(n), &GraphFilter::all()).unwrap())
        });
        group.bench_function(format!("graph6 n={n}"), |b| {
            b.iter(|| {
                write_connected_graph6(black_box(n), &GraphFilter::all(), &mut std::io::sink())
                    .unwrap()
            })
        });
    }
    let audit = GraphFilter::maxwell_rods(9).with_min_degree(2);
    group.bench_function("count n=9 maxwell min-degree 2", |b| {
        b.iter(|| count_connected(black_box(9), &audit).unwrap())
    });
    group.finish();
}

fn canonical(c: &mut Criterion) {
    let seven = connected_graphs(7, &GraphFilter::all()).unwrap();
    c.bench_function("canonical_graph6 of the 853 graphs on 7 vertices", |b| {
        b.iter(|| seven.iter().map(canonical_graph6).count())
    });
}

fn typed(c: &mut Criterion) {
    let mut group = c.benchmark_group("typed");
    group.sample_size(10);
    group.bench_function("4 nodes", |b| {
        b.iter(|| typed_patterns(&TypedFilter::new(4)).unwrap().len())
    });
    let mut sharing = TypedFilter::new(3);
    sharing.rod_sharing = true;
    sharing.max_mult_body_body = 2;
    group.bench_function("3 nodes, rod sharing, body-body <= 2", |b| {
        b.iter(|| typed_patterns(&sharing).unwrap().len())
    });
    group.finish();
}

criterion_group! {
    name = benches;
    // Plots need system fonts that a bare machine lacks.
    config = Criterion::default().without_plots();
    targets = graphs, canonical, typed
}
criterion_main!(benches);
