//! One GPU frame per rasterizer mode (scene uploaded once). Skips loudly without an adapter.

mod common;

use criterion::{Criterion, criterion_group, criterion_main};
use indicatif::ProgressBar;
use omnicloud::bench::BenchMode;
use omnicloud::raster::Rasterizer;

fn bench(c: &mut Criterion) {
    let raster = match Rasterizer::new() {
        Ok(r) => r,
        Err(e) => {
            eprintln!("\n*** SKIPPING GPU benches: {e} ***\n");
            return;
        }
    };
    eprintln!("GPU benches on {}", raster.adapter_name());
    let (scene, settings) = common::street(512);
    let uploaded = raster.upload(&scene, &settings).expect("upload");
    let mut g = c.benchmark_group("raster_frame");
    for mode in BenchMode::all() {
        let mut s = settings;
        s.proxy = mode.proxy;
        s.imposter = mode.imposter;
        g.bench_function(mode.label(), |b| {
            b.iter(|| {
                raster
                    .render_uploaded(&uploaded, &s, &ProgressBar::hidden())
                    .expect("frame")
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).measurement_time(std::time::Duration::from_secs(2)).warm_up_time(std::time::Duration::from_millis(500));
    targets = bench
}
criterion_main!(benches);
