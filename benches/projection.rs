//! Throughput of the exact f64 camera math: `View::ray` and `View::project` (mono and ODS
//! with pole merging, where `project` solves the fixed point).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use omnicloud::projection::{
    Camera, Equirect, Eye, OdsOffset, PoleMerge, PoleMerging, Stereo, View,
};
use omnicloud::rng::SplitMix64;
use std::hint::black_box;

fn views() -> [(&'static str, View); 2] {
    let cam = Camera::new(DVec3::new(1.0, 2.0, 1.6), 30.0);
    let ods = Stereo::Ods {
        ipd: 0.064,
        merging: PoleMerging::both(PoleMerge::COMFORTABLE),
        offset: OdsOffset::Exact,
    };
    [
        ("mono", View::mono(cam)),
        ("ods_merge", View::eye(cam, &ods, Eye::Right)),
    ]
}

fn bench(c: &mut Criterion) {
    let mut rng = SplitMix64::new(5);
    let points: Vec<DVec3> = (0..4096)
        .map(|_| {
            DVec3::new(
                rng.range(-50.0, 50.0),
                rng.range(-50.0, 50.0),
                rng.range(-10.0, 30.0),
            )
        })
        .collect();
    let image = Equirect::from_width(1024);
    let mut g = c.benchmark_group("projection");
    g.throughput(Throughput::Elements(points.len() as u64));
    for (name, view) in views() {
        g.bench_function(format!("project/{name}"), |b| {
            b.iter(|| {
                points
                    .iter()
                    .map(|&p| view.project(black_box(p)).map_or(0.0, |(l, _)| l))
                    .sum::<f64>()
            })
        });
        g.bench_function(format!("pixel_ray/{name}"), |b| {
            b.iter(|| {
                (0..4096u32)
                    .map(|k| {
                        view.pixel_ray(&image, black_box(k % 1024), k / 1024 * 100)
                            .1
                            .z
                    })
                    .sum::<f64>()
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(2));
    targets = bench
}
criterion_main!(benches);
