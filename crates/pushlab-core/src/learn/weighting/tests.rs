use super::*;
use crate::model::LossScale;

const SCALE: LossScale = LossScale {
    sigma_pos: [0.01, 0.01],
    sigma_rot: 0.1,
};

fn motion(x: f64) -> ObjectMotion {
    ObjectMotion {
        translation: [x, 0.0],
        rotation: 0.0,
    }
}

/// `seconds` of a combined model that predicts exactly and a physics model off by one σ in x, at
/// `hz` frames a second: the weight after each frame.
fn weights(hz: f64, seconds: f64, config: WeightConfig) -> Vec<f64> {
    let mut weight = ModelWeight::new(config);
    let n = (seconds * hz).round() as usize;
    (0..n)
        .map(|k| {
            weight.take(
                k,
                k as f64 / hz,
                &motion(0.0),
                &motion(0.01),
                &motion(0.0),
                &SCALE,
            );
            // Only the translation differs: the rotation's weight stays at the prior.
            assert!((weight.weight().rot - config.prior).abs() < 1e-12);
            weight.weight().pos
        })
        .collect()
}

#[test]
fn the_weight_is_the_posterior_of_the_closed_form_with_forgetting() {
    // Each 10 Hz frame is one unit of evidence: ℓ_physics = 1 (one σ in x: ℓ_pos,x = 1, total 1),
    // ℓ_combined = 0, a log-likelihood ratio of 1/2. Forgotten by λ = 0.5^(0.1 / 1 s) per frame,
    // after n frames the log-odds are ½ (1 − λⁿ) / (1 − λ).
    let config = WeightConfig {
        half_life_s: 1.0,
        prior: 0.5,
    };
    let lambda = 0.5f64.powf(0.1);
    for (i, w) in weights(10.0, 3.0, config).into_iter().enumerate() {
        let n = (i + 1) as i32;
        let log_odds: f64 = (0.5 * (1.0 - lambda.powi(n)) / (1.0 - lambda)).min(MAX_LOG_ODDS);
        let want = 1.0 / (1.0 + (-log_odds).exp());
        assert!((w - want).abs() < 1e-12, "frame {i}: {w} against {want}");
    }
}

#[test]
fn the_weight_does_not_depend_on_the_frame_rate() {
    let config = WeightConfig::default();
    let slow = *weights(10.0, 2.0, config).last().unwrap_or(&0.0);
    let fast = *weights(250.0, 2.0, config).last().unwrap_or(&0.0);
    assert!(slow > 0.9, "the exact model is trusted: {slow}");
    assert!((slow - fast).abs() < 0.02, "10 Hz {slow}, 250 Hz {fast}");
}

#[test]
fn the_blend_is_never_worse_than_the_weighted_mean_of_the_two() {
    let mut weight = ModelWeight::new(WeightConfig::default());
    let mut seed = 12345u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for k in 0..500 {
        let (c, p, t) = (
            ObjectMotion {
                translation: [next() * 0.02, next() * 0.02],
                rotation: next() * 0.2,
            },
            ObjectMotion {
                translation: [next() * 0.02, next() * 0.02],
                rotation: next() * 0.2,
            },
            ObjectMotion {
                translation: [next() * 0.02, next() * 0.02],
                rotation: next() * 0.2,
            },
        );
        let w = weight.weight();
        let taken = weight.take(k, k as f64 * 0.1, &c, &p, &t, &SCALE);
        let (lc, lp) = (Loss::of(&c, &t, &SCALE), Loss::of(&p, &t, &SCALE));
        let pos = |l: &Loss| l.pos_x + l.pos_y;
        let mean =
            w.pos * pos(&lc) + (1.0 - w.pos) * pos(&lp) + w.rot * lc.rot + (1.0 - w.rot) * lp.rot;
        assert!(taken.loss.total() <= mean + 1e-12, "frame {k}");
        assert_eq!(taken.weight, w);
    }
}

/// `frames` at 10 Hz in which the combined model predicts exactly and physics is off by one σ
/// in x.
fn combined_exact(weight: &mut ModelWeight, frames: std::ops::Range<usize>) {
    for k in frames {
        let (exact, off) = (motion(0.0), motion(0.01));
        weight.take(k, k as f64 * 0.1, &exact, &off, &exact, &SCALE);
    }
}

#[test]
fn a_model_that_stops_predicting_well_loses_its_weight_within_seconds() {
    let mut weight = ModelWeight::new(WeightConfig::default());
    combined_exact(&mut weight, 0..30);
    assert!(weight.weight().pos > 0.95);
    // Now the combined model is off by two σ and physics exact.
    let mut k = 30;
    while weight.weight().pos > 0.5 {
        weight.take(
            k,
            k as f64 * 0.1,
            &motion(0.02),
            &motion(0.0),
            &motion(0.0),
            &SCALE,
        );
        k += 1;
        assert!(k < 60, "still trusted after 3 s");
    }
}

#[test]
fn rewinding_forgets_the_frames_from_there_and_taking_them_again_gives_the_same_bits() {
    let mut weight = ModelWeight::new(WeightConfig::default());
    let frame = |weight: &mut ModelWeight, k: usize| {
        let x = (k as f64 * 0.7).sin() * 0.01;
        weight.take(
            k,
            k as f64 * 0.1,
            &motion(x),
            &motion(0.004),
            &motion(0.002),
            &SCALE,
        )
    };
    for k in 0..40 {
        frame(&mut weight, k);
    }
    let before = weight.clone();
    weight.rewind_to(15);
    assert_eq!(weight.frames().len(), 15);
    assert_eq!(weight.weight(), before.frames()[15].weight);
    for k in 15..40 {
        frame(&mut weight, k);
    }
    assert_eq!(weight, before);
    weight.rewind_to(0);
    assert_eq!(
        weight.weight(),
        ModelWeight::new(WeightConfig::default()).weight()
    );
}

/// Frames not taken in (θ held over them: a controller's pusher going round the object, frames
/// labelled bad) leave a gap before the next frame taken in. Nothing was seen over the gap: the
/// evidence before it is carried over, and the next frame counts for its own tenth of a second.
/// Counted for the gap, one frame after 10 s away pinned the weight at its limit.
#[test]
fn a_frame_after_frames_not_taken_in_counts_for_its_own_interval() {
    let mut weight = ModelWeight::new(WeightConfig::default());
    combined_exact(&mut weight, 0..10);
    let before = weight.evidence[0];
    // Frames 10-108 held; frame 109, 10 s on, favours physics by one σ.
    let when = FrameTime {
        time: 10.9,
        previous: Some(10.8),
    };
    weight.take(109, when, &motion(0.01), &motion(0.0), &motion(0.0), &SCALE);
    let forget = 0.5f64.powf(0.1 / WeightConfig::default().half_life_s);
    let expected = forget * before - 0.5;
    assert!(
        (weight.evidence[0] - expected).abs() < 1e-12,
        "{} against {expected}",
        weight.evidence[0]
    );
    assert!(
        weight.weight().pos > 0.5,
        "one frame does not overturn the prior"
    );
}
