//! Benchmarks of flattening (issue 3): exact unfolding, LSCM and ARAP on developable cylinder
//! grids of 1k, 10k and 100k faces (1M with `SHEETFORM_BENCH_LARGE=1`). Run with
//! `cargo bench -p sheetform --bench flatten`; `tools/compare_libigl.py` times libigl's
//! LSCM on the same meshes. Figures in docs/benchmarks-history.md.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use sheetform::flatten::{arap, exact_unfold, lscm, ArapOptions, UnfoldOptions};
use sheetform::mesh::TriangleMesh;
use std::hint::black_box;

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// A developable grid: a half cylinder of radius 100 and height 200, `nu × nv` quads,
/// two triangles each (the mesh `tools/compare_libigl.py` builds).
fn cylinder(nu: usize, nv: usize) -> TriangleMesh {
    TriangleMesh::grid(nu, nv, |u, v| {
        let a = std::f64::consts::PI * u;
        [100.0 * a.cos(), 100.0 * a.sin(), 200.0 * v]
    })
}

fn bench_flatten(c: &mut Criterion) {
    let mut sizes = vec![("1k", 25, 20), ("10k", 100, 50), ("100k", 250, 200)];
    if std::env::var_os("SHEETFORM_BENCH_LARGE").is_some() {
        sizes.push(("1M", 1000, 500));
    }
    let mut group = c.benchmark_group("flatten");
    group.sample_size(10);
    for (label, nu, nv) in sizes {
        let mesh = cylinder(nu, nv);
        group.throughput(Throughput::Elements(mesh.triangles.len() as u64));
        group.bench_with_input(BenchmarkId::new("exact", label), &mesh, |b, m| {
            b.iter(|| exact_unfold(black_box(m), &UnfoldOptions::default()).expect("developable disk"))
        });
        group.bench_with_input(BenchmarkId::new("lscm", label), &mesh, |b, m| {
            b.iter(|| lscm(black_box(m)).expect("disk"))
        });
        group.bench_with_input(BenchmarkId::new("arap", label), &mesh, |b, m| {
            b.iter(|| arap(black_box(m), &ArapOptions::default()).expect("disk"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_flatten);
criterion_main!(benches);
