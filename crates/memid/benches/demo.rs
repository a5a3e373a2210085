//! The whole demo (`memid demo`: two fits, ERA, figures, report), as a user runs it.

use criterion::{Criterion, criterion_group, criterion_main};
use std::process::Command;

fn bench_demo(c: &mut Criterion) {
    let dir = std::env::temp_dir().join(format!("memid-bench-demo-{}", std::process::id()));
    let dir_text = dir.to_str().expect("a UTF-8 temporary path").to_string();
    let mut group = c.benchmark_group("demo");
    group.sample_size(10);
    group.bench_function("whole", |b| {
        b.iter(|| {
            let status = Command::new(env!("CARGO_BIN_EXE_memid"))
                .args(["demo", "--report", &dir_text, "--json"])
                .output()
                .expect("memid runs");
            assert!(status.status.success());
        })
    });
    group.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench_demo);
criterion_main!(benches);
