use super::PathMoments;
use crate::rng::SplitMix64;

/// The moments after `path` with `keep` applied before each point but the first, as
/// `Posterior::take_in` does.
fn moments(path: &[[f64; 2]], keep: f64) -> PathMoments {
    let mut m = PathMoments::default();
    for (i, x) in path.iter().enumerate() {
        if i > 0 {
            m.scale(keep);
        }
        m.add(*x);
    }
    m
}

#[test]
fn a_steady_slide_drifts_by_a_twelfth_of_its_length_squared() {
    let d = 0.03;
    let path: Vec<[f64; 2]> = (0..=300).map(|i| [d * i as f64 / 300.0, 0.0]).collect();
    let m = moments(&path, 1.0);
    assert!(
        (m.drift() / (d * d / 12.0) - 1.0).abs() < 0.01,
        "{}",
        m.drift()
    );
    assert!(m.jitter() < 0.01 * m.scatter());
}

#[test]
fn steps_in_random_directions_drift_by_nothing_on_average() {
    let mut rng = SplitMix64::new(5);
    let (mut scatter, mut excess) = (0.0, 0.0);
    for _ in 0..400 {
        let mut x = [0.0, 0.0];
        let path: Vec<[f64; 2]> = (0..100)
            .map(|_| {
                x = [x[0] + rng.normal() * 1e-3, x[1] + rng.normal() * 1e-3];
                x
            })
            .collect();
        let m = moments(&path, 1.0);
        scatter += m.scatter();
        excess += m.scatter() - m.jitter();
    }
    assert!(excess.abs() < 0.05 * scatter, "{excess} of {scatter}");
}

#[test]
fn forgetting_weighs_the_path_like_its_frames() {
    let mut rng = SplitMix64::new(9);
    let path: Vec<[f64; 2]> = (0..60).map(|_| [rng.normal(), rng.normal()]).collect();
    let keep: f64 = 0.9;
    let n = path.len();
    let w = |i: usize| keep.powi((n - 1 - i) as i32);
    let total: f64 = (0..n).map(w).sum();
    let mean = [0, 1].map(|c| (0..n).map(|i| w(i) * path[i][c]).sum::<f64>() / total);
    let sq = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
    let scatter = (0..n).map(|i| w(i) * sq(path[i], mean)).sum::<f64>() / total;
    let jitter: f64 = (1..n)
        .map(|k| {
            let after = (k..n).map(w).sum::<f64>() / total;
            sq(path[k], path[k - 1]) * after * (1.0 - after)
        })
        .sum();
    let m = moments(&path, keep);
    assert!((m.scatter() - scatter).abs() < 1e-12 * scatter);
    assert!((m.jitter() - jitter).abs() < 1e-12 * scatter);
}
