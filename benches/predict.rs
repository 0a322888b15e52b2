//! Criterion benchmark of batch prediction (`ccrkit predict`): every row of the FTDCR v4
//! training file (1620 rows) with the energy model, warm-started row to row, chunks of 64 in
//! parallel; throughput in rows per second.
//!
//! `cargo bench --bench predict`

use ccrkit::calibrate::data::{DataOptions, Dataset};
use ccrkit::calibrate::predict::{predict, PredictOptions, DEFAULT_CHUNK};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::Model;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;

fn ftdcr(c: &mut Criterion) {
    let model = Model::from_file("models/hardware/ftdcr_v4.toml").expect("model");
    let data = Dataset::from_file(
        "models/hardware/data/v4/tdcr_sysid_20260511-183002_train.csv",
        &DataOptions::default(),
    )
    .expect("data");
    let mut g = c.benchmark_group("predict-ftdcr-v4-train");
    g.throughput(Throughput::Elements(data.len() as u64));
    g.sample_size(10);
    for sub_arcs in ["1", "4"] {
        let mut s = Settings::new();
        s.push("sub-arcs", sub_arcs);
        let opts = PredictOptions {
            request: SolveRequest::new(MethodKind::Energy).with_settings(s),
            chunk: DEFAULT_CHUNK,
            progress: ccrkit::progress::ProgressHandle::none(),
        };
        g.bench_function(format!("energy-sub-arcs-{sub_arcs}"), |b| {
            b.iter(|| predict(black_box(&model), black_box(&data), &opts).expect("predict"))
        });
    }
    g.finish();
}

criterion_group!(benches, ftdcr);
criterion_main!(benches);
