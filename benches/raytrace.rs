//! The ray tracer: BVH build over the spheres, and rendering rows of a panorama.

mod common;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use indicatif::ProgressBar;
use omnicloud::raytrace::{Tracer, render_with_tracer};

fn bench(c: &mut Criterion) {
    let scene = common::mixed();
    let mut g = c.benchmark_group("raytrace");
    g.throughput(Throughput::Elements(scene.len() as u64));
    g.bench_function(format!("bvh_build/{}_spheres", scene.len()), |b| {
        b.iter(|| Tracer::new(&scene).expect("BVH builds"))
    });
    let (street, settings) = common::street(256);
    let tracer = Tracer::new(&street).expect("BVH builds");
    g.throughput(Throughput::Elements(
        settings.image.width as u64 * settings.image.height as u64,
    ));
    g.bench_function("rows/street_256x128_mono", |b| {
        b.iter(|| render_with_tracer(&tracer, &street, &settings, &ProgressBar::hidden()).unwrap())
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).measurement_time(std::time::Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
