//! Times the batch engine alone (no Python) on N random direction pairs:
//! `cargo run --release --example eval_kernel -- [model] [n] [reps] [f32|f64]`
//! (`PRECISION=fast` for the fast tier, `P=` for the exponent of models that take `p`,
//! `BRDF_RS_NUM_THREADS=` for the thread count: the engine's own pool, which does not read
//! rayon's `RAYON_NUM_THREADS`).
//!
//! By default the inputs are unit vectors passed with `normalized=True` and `n` is left out
//! (`+z` for every row): the kernel alone. `NORMALIZED=0` has the engine normalize them, as
//! `brdf_rs.eval` does by default: the work of `benches/eval_throughput.py`'s default
//! columns, which leave `n` out too. `NORMALS=rows` passes `n` as an array of rows, a
//! random unit vector each, which adds its loads and normalization.

use brdf_rs::ModelKind;
use brdf_rs::eval::{EvalInputs, EvalOptions, plan};
use ndarray::{ArrayD, ArrayViewMutD, IxDyn};
use std::time::Instant;

fn directions(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed;
    let mut next = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 11) as f64) / (1u64 << 53) as f64
    };
    let mut v = Vec::with_capacity(3 * n);
    for _ in 0..n {
        let z = next();
        let phi = 2.0 * std::f64::consts::PI * next();
        let r = (1.0 - z * z).sqrt();
        v.extend_from_slice(&[r * phi.cos(), r * phi.sin(), z]);
    }
    v
}

fn run<F: brdf_rs::math::Real>(model: ModelKind, n: usize, reps: usize) {
    let wi: Vec<F> = directions(n, 1).into_iter().map(F::from_f64).collect();
    let wo: Vec<F> = directions(n, 2).into_iter().map(F::from_f64).collect();
    let wi = ArrayD::from_shape_vec(IxDyn(&[n, 3]), wi).unwrap();
    let wo = ArrayD::from_shape_vec(IxDyn(&[n, 3]), wo).unwrap();
    let normals = std::env::var("NORMALS")
        .is_ok_and(|s| s == "rows")
        .then(|| {
            let v: Vec<F> = directions(n, 3).into_iter().map(F::from_f64).collect();
            ArrayD::from_shape_vec(IxDyn(&[n, 3]), v).unwrap()
        });
    let p = ArrayD::from_elem(
        IxDyn(&[]),
        F::from_f64(
            std::env::var("P")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(50.0),
        ),
    );
    let takes_p = model.spec().param("p").is_some();
    let mut out = vec![F::ZERO; 3 * n];
    let options = EvalOptions {
        normalized: std::env::var("NORMALIZED").map_or(true, |s| s != "0"),
        precision: brdf_rs::eval::Precision::from_name(
            &std::env::var("PRECISION").unwrap_or_else(|_| "accurate".into()),
        )
        .unwrap(),
        ..Default::default()
    };
    let mut best = f64::INFINITY;
    for _ in 0..reps {
        let inputs = EvalInputs {
            wi: wi.view(),
            wo: wo.view(),
            n: normals.as_ref().map(|a| a.view()),
            tangent: None,
            params: if takes_p {
                vec![("p", p.view())]
            } else {
                vec![]
            },
        };
        let plan = plan(model, inputs, options).unwrap();
        let view = ArrayViewMutD::from_shape(IxDyn(&[n, 3]), &mut out).unwrap();
        let t = Instant::now();
        plan.execute(view).unwrap();
        best = best.min(t.elapsed().as_secs_f64());
    }
    println!(
        "{} {}: {:.1} M evals/s",
        model.name(),
        F::DTYPE,
        n as f64 / best / 1e6
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let model = ModelKind::from_name(args.get(1).map_or("torrance_sparrow", |s| s)).unwrap();
    let n = args.get(2).map_or(4_000_000, |s| s.parse().unwrap());
    let reps = args.get(3).map_or(10, |s| s.parse().unwrap());
    match args.get(4).map_or("f32", |s| s) {
        "f64" => run::<f64>(model, n, reps),
        _ => run::<f32>(model, n, reps),
    }
}
