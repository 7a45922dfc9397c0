//! The one pusher-speed rule ([`Trajectory::pusher_speed`]) against simulated pushes of known speed,
//! with tracking noise, at the frame rates of the sample data (10 Hz), cameras (50, 100 Hz) and the
//! MIT Push Dataset (250 Hz).
//!
//! Measured while choosing the rule (9 pushes per row, 0.3 × 0.4 m box, the worst ratio to the true
//! speed; "summed" is the length of the frame-to-frame steps over the duration, the rule the model
//! domain used before; "noise-aware" the mean squared step less the noise's share estimated from
//! second differences; the others net displacement over windows of that many seconds, averaged):
//!
//! | push | summed | noise-aware | 0.5 s | **1 s** | 2 s | whole push |
//! |---|---|---|---|---|---|---|
//! | 0.05 m/s, 10 Hz, 2 mm | 1.20 | 0.97 | 1.009 | **1.004** | 1.003 | 1.011 |
//! | 0.05 m/s, 50 Hz, 2 mm | 3.71 | 0.71 | 1.010 | **1.003** | 1.002 | 0.994 |
//! | 0.05 m/s, 250 Hz, 2 mm | 17.8 | 0.00 | 1.007 | **1.002** | 1.001 | 0.995 |
//! | 0.01 m/s, 10 Hz, 2 mm | 4.00 | 0.00 | 1.247 | **1.063** | 1.022 | 1.055 |
//! | 0.01 m/s, 250 Hz, 2 mm | 89.1 | 7.32 | 1.184 | **1.044** | 1.013 | 0.975 |
//! | 0.15 m/s, 250 Hz, 2 mm, 3 s | 6.10 | 0.37 | 1.002 | **1.001** | 1.001 | 1.013 |
//! | 0.05 m/s, curving 3 /m, 250 Hz, 2 mm | 17.8 | 0.00 | 1.008 | **1.002** | 0.996 | 0.897 |
//! | 0.05 m/s, 1.5 s, 50 Hz, 2 mm | 4.10 | 0.57 | 1.022 | **0.975** | 0.898 | 0.898 |
//!
//! One-second windows stay within 7 % everywhere; shorter ones let the noise back in at slow
//! speeds, longer ones become the whole push on short pushes and cut the corners of curved ones.

use pushlab_core::recording::{ObjectShape, PushSide};
use pushlab_core::sim::{NoiseSpec, PressureModel, PushSpec, SetSpec, generate_set};
use pushlab_core::trajectory::Trajectory;

/// Three pushes (−20°, 0°, 20°) of a 0.3 × 0.4 m box by a 175 mm disc, as `pushlab simulate` makes
/// them, at `speed` m/s and `rate` Hz with `noise_m` of tracking noise.
fn pushes(speed: f64, rate: f64, noise_m: f64, curvature: f64) -> Vec<Trajectory> {
    let spec = SetSpec {
        name: "speed".into(),
        object: ObjectShape::Box {
            width: 0.3,
            length: 0.4,
        },
        com_offset: [0.0, 0.0],
        pressure: PressureModel::Uniform,
        material: None,
        floor_friction: None,
        pusher_friction: 0.3,
        pusher_radius: 0.175,
        push_side: PushSide::Front,
        sample_rate_hz: rate,
        duration_s: 10.0,
        speed,
        approach: 0.01,
        noise: NoiseSpec {
            position_m: noise_m,
            yaw_deg: 0.5,
        },
        start_position_spread_m: 0.0,
        start_yaw_spread_deg: 0.0,
        seed: 11,
        pushes: [-20.0, 0.0, 20.0]
            .map(|push_angle_deg| PushSpec {
                contact_offset: 0.05,
                push_angle_deg,
                curvature,
                split: None,
            })
            .to_vec(),
    };
    generate_set(&spec, &mut |_, _| {})
        .expect("the pushes simulate")
        .trajectories
}

#[test]
fn the_pusher_speed_is_within_ten_percent_at_every_rate_and_noise() {
    for (speed, curvature) in [(0.05, 0.0), (0.01, 0.0), (0.05, 3.0)] {
        for rate in [10.0, 50.0, 100.0, 250.0] {
            for noise_m in [0.0, 0.001, 0.002] {
                for push in pushes(speed, rate, noise_m, curvature) {
                    let measured = push.pusher_speed().expect("a speed");
                    let ratio = measured / speed;
                    // Without noise the windows' chords are the path, to rounding (1 µm, 1 ns).
                    let tolerance = if noise_m == 0.0 && curvature == 0.0 {
                        1e-3
                    } else {
                        0.1
                    };
                    assert!(
                        (ratio - 1.0).abs() < tolerance,
                        "{speed} m/s, curvature {curvature} /m, {rate} Hz, {} mm noise: \
                         measured {measured} m/s",
                        noise_m * 1e3
                    );
                }
            }
        }
    }
}

#[test]
fn a_push_too_short_to_measure_has_no_speed() {
    let push = &pushes(0.05, 10.0, 0.0, 0.0)[0];
    let one_frame = Trajectory::new(push.frames[..1].to_vec());
    assert_eq!(one_frame.pusher_speed(), None);
    // Shorter than a window: the whole push's net displacement.
    let short = Trajectory::new(push.frames[..4].to_vec());
    let measured = short.pusher_speed().expect("a speed");
    assert!((measured - 0.05).abs() < 1e-3, "{measured}");
}
