//! One GPU frame per rasterizer mode (scene uploaded once). Without an adapter it skips
//! loudly, or fails when `OMNICLOUD_REQUIRE_GPU` is set; any other GPU error fails.

mod common;
#[path = "../tests/raster_common/gpu.rs"]
mod gpu;

use criterion::{Criterion, criterion_group, criterion_main};
use indicatif::ProgressBar;
use omnicloud::bench::BenchMode;

fn bench(c: &mut Criterion) {
    let Some(raster) = gpu::rasterizer() else {
        return;
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
