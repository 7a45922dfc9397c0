//! The rules every model file keeps, checked once in the core when a file is read (and before one is
//! written) — before any of its numbers is used.
//!
//! Why: a model file is a user's file like a recording. JSON cannot hold a NaN, but it can hold a
//! standard deviation of 0 (every normalised input becomes `inf`), a loss σ of 0 (`inf` in every
//! row of a report), a horizon of 0, a step scale of 0 (online learning silently does nothing) or an
//! `h` outside the range the model keeps it in (silently clamped). Each such file is refused with
//! the JSON path of the field and what was expected, e.g.
//! `combined.normalization.position.std[0]: must be > 0, found 0`.
//!
//! Rules are written per part of the file, so that each kind's data (`combined`), the pure network
//! (`pure_nn`) and the training domain (`training.domain`) are checked by the same few rules:
//! [`finite`], [`positive`], [`non_negative`] and the horizon's and `h`'s ranges.

use crate::domain::Domain;
use crate::model::contact::ContactInputs;
use crate::model::normalization::{InputNormalization, Stats1, Stats2};
use crate::model::{
    COM_OFFSET_MAX, ComMisfit, CombinedModel, ContactModel, H_MAX, H_MIN, LossScale, Network,
    OnlineParams, PaperModel, PureNnModel,
};
use crate::real::Real;

use super::contents::ModelFile;

/// Largest magnitude of a constant in a model file. The model computes in `f32` (largest value
/// 3.4e38) and squares or inverts some constants; nothing a model describes in metres, radians,
/// hertz or frames comes near 1e12, so a larger value can only come from a broken or hand-edited file.
pub const LARGEST: f64 = 1e12;

/// Smallest positive standard deviation, σ or step scale: the floor offline training puts under
/// every standard deviation (`Stats1::of`), so that its reciprocal and square stay finite in `f32`.
pub const SMALLEST_POSITIVE: f64 = 1e-12;

/// A broken rule: the JSON path of the field and what was expected (and found).
pub(crate) type Problem = (String, String);

/// A value as a message shows it: `0`, `-0.3`, and `1e39` or `1e-20` rather than forty digits.
fn shown(value: f64) -> String {
    if value != 0.0 && value.is_finite() && !(1e-5..1e16).contains(&value.abs()) {
        format!("{value:e}")
    } else {
        format!("{value}")
    }
}

/// A field's value must be a finite number no larger in magnitude than [`LARGEST`].
fn finite(field: &str, value: f64) -> Result<(), Problem> {
    if value.is_finite() && value.abs() <= LARGEST {
        Ok(())
    } else {
        Err((
            field.to_owned(),
            format!(
                "must be a finite number between -{LARGEST:e} and {LARGEST:e}, found {}",
                shown(value)
            ),
        ))
    }
}

/// A standard deviation, σ, step scale or range bound: > 0, within [[`SMALLEST_POSITIVE`],
/// [`LARGEST`]].
fn positive(field: &str, value: f64) -> Result<(), Problem> {
    if value.is_nan() || value <= 0.0 {
        return Err((
            field.to_owned(),
            format!("must be > 0, found {}", shown(value)),
        ));
    }
    if !(SMALLEST_POSITIVE..=LARGEST).contains(&value) {
        return Err((
            field.to_owned(),
            format!(
                "must be between {SMALLEST_POSITIVE:e} and {LARGEST:e} (its reciprocal and square are used in single precision), found {}",
                shown(value)
            ),
        ));
    }
    Ok(())
}

/// A tolerance or friction coefficient: ≥ 0 and finite.
fn non_negative(field: &str, value: f64) -> Result<(), Problem> {
    if value.is_nan() || value < 0.0 {
        return Err((
            field.to_owned(),
            format!("must be ≥ 0, found {}", shown(value)),
        ));
    }
    finite(field, value)
}

/// A prediction horizon: at least one frame.
fn horizon(field: &str, frames: usize) -> Result<(), Problem> {
    if frames >= 1 {
        Ok(())
    } else {
        Err((
            field.to_owned(),
            format!("must be at least 1 frame, found {frames}"),
        ))
    }
}

/// Applies `rule` to each element, naming it `field[i]`.
fn each(
    field: &str,
    values: &[f64],
    rule: fn(&str, f64) -> Result<(), Problem>,
) -> Result<(), Problem> {
    values
        .iter()
        .enumerate()
        .try_for_each(|(i, &v)| rule(&format!("{field}[{i}]"), v))
}

/// Every parameter of a network finite (the file's values are checked when parsed; this also
/// covers a model built in memory before it is saved).
fn network<T: Real, const I: usize>(field: &str, network: &Network<T, I>) -> Result<(), Problem> {
    match network
        .parameters()
        .parameters()
        .position(|p| !p.is_finite())
    {
        None => Ok(()),
        Some(k) => Err((
            format!("{field}[{k}]"),
            "must be a finite number".to_owned(),
        )),
    }
}

fn stats2(field: &str, stats: &Stats2) -> Result<(), Problem> {
    each(&format!("{field}.mean"), &stats.mean, finite)?;
    each(&format!("{field}.std"), &stats.std, positive)
}

fn stats1(field: &str, stats: &Stats1) -> Result<(), Problem> {
    finite(&format!("{field}.mean"), stats.mean)?;
    positive(&format!("{field}.std"), stats.std)
}

fn input_normalization(field: &str, n: &InputNormalization) -> Result<(), Problem> {
    stats2(&format!("{field}.position"), &n.position)?;
    stats2(&format!("{field}.motion"), &n.motion)
}

fn loss_scale(field: &str, scale: &LossScale) -> Result<(), Problem> {
    each(&format!("{field}.sigma_pos"), &scale.sigma_pos, positive)?;
    positive(&format!("{field}.sigma_rot"), scale.sigma_rot)
}

/// `θ_online(0)`: the COM offset and `h` inside the ranges online learning keeps them in (a value
/// outside would be clamped silently on first use).
fn theta0(field: &str, theta: &OnlineParams) -> Result<(), Problem> {
    for (i, &c) in theta.com_offset.iter().enumerate() {
        if !(-COM_OFFSET_MAX..=COM_OFFSET_MAX).contains(&c) {
            return Err((
                format!("{field}.com_offset[{i}]"),
                format!(
                    "must be between -{COM_OFFSET_MAX} and {COM_OFFSET_MAX} m (the range the COM offset is kept in), found {}",
                    shown(c)
                ),
            ));
        }
    }
    if (H_MIN..=H_MAX).contains(&theta.h) {
        Ok(())
    } else {
        Err((
            format!("{field}.h"),
            format!(
                "must be between {H_MIN} and {H_MAX} m (the range Lynch's h is kept in), found {}",
                shown(theta.h)
            ),
        ))
    }
}

fn paper(field: &str, m: &PaperModel) -> Result<(), Problem> {
    let at = |name: &str| format!("{field}.{name}");
    network(&at("network"), &m.network)?;
    input_normalization(&at("normalization"), &m.normalization)?;
    theta0(&at("theta0"), &m.theta0)?;
    loss_scale(&at("loss_scale"), &m.loss_scale)?;
    horizon(&at("horizon"), m.horizon)?;
    each(&at("theta_scales"), &m.theta_scales, positive)?;
    com_misfit(&at("com_misfit"), &m.com_misfit)
}

/// Spreads added to the COM's posterior: a negative one would narrow the ellipse below what the
/// frames say.
fn com_misfit(field: &str, m: &ComMisfit) -> Result<(), Problem> {
    non_negative(&format!("{field}.gd_per_h"), m.gd_per_h)?;
    non_negative(&format!("{field}.gauss_newton_per_h"), m.gauss_newton_per_h)
}

fn contact_inputs(field: &str, inputs: &ContactInputs) -> Result<(), Problem> {
    each(&format!("{field}.low"), &inputs.low, finite)?;
    each(&format!("{field}.high"), &inputs.high, finite)?;
    for (i, (low, high)) in inputs.low.iter().zip(&inputs.high).enumerate() {
        if low > high {
            return Err((
                format!("{field}.low[{i}]"),
                format!(
                    "must be ≤ {field}.high[{i}] ({}), found {}",
                    shown(*high),
                    shown(*low)
                ),
            ));
        }
    }
    positive(&format!("{field}.motion_floor"), inputs.motion_floor)
}

fn contact(field: &str, m: &ContactModel) -> Result<(), Problem> {
    let at = |name: &str| format!("{field}.{name}");
    network(&at("network"), &m.network)?;
    contact_inputs(&at("inputs"), &m.inputs)?;
    non_negative(&at("friction"), m.friction)?;
    non_negative(&at("contact_tolerance"), m.contact_tolerance)?;
    loss_scale(&at("loss_scale"), &m.loss_scale)?;
    horizon(&at("horizon"), m.horizon)?;
    each(
        &at("relative_theta_scales"),
        &m.relative_theta_scales,
        positive,
    )?;
    com_misfit(&at("com_misfit"), &m.com_misfit)
}

/// The pure network predicts at the combined model's horizon: a file pairing two horizons would
/// compare the two models on different motions.
fn pure_nn(field: &str, m: &PureNnModel, combined_horizon: usize) -> Result<(), Problem> {
    let at = |name: &str| format!("{field}.{name}");
    network(&at("network"), &m.network)?;
    input_normalization(&at("input"), &m.input)?;
    stats2(&at("output.translation"), &m.output.translation)?;
    stats1(&at("output.rotation"), &m.output.rotation)?;
    loss_scale(&at("loss_scale"), &m.loss_scale)?;
    if m.horizon != combined_horizon {
        return Err((
            at("horizon"),
            format!(
                "must equal combined.horizon ({combined_horizon}), found {}",
                m.horizon
            ),
        ));
    }
    Ok(())
}

/// The training domain: each `[smallest, largest]` positive and in order (the domain check divides
/// by them).
fn domain(field: &str, d: &Domain) -> Result<(), Problem> {
    for (name, range) in [
        ("object_size", Some(d.object_size)),
        ("pusher_radius", Some(d.pusher_radius)),
        ("sample_rate_hz", Some(d.sample_rate_hz)),
        ("pusher_speed", d.pusher_speed),
    ] {
        let Some(range) = range else { continue };
        let at = format!("{field}.{name}");
        each(&at, &range, positive)?;
        if range[0] > range[1] {
            return Err((
                format!("{at}[0]"),
                format!(
                    "must be ≤ {at}[1] ({}), found {}",
                    shown(range[1]),
                    shown(range[0])
                ),
            ));
        }
    }
    horizon(&format!("{field}.horizon"), d.horizon)
}

/// Checks every rule of a model file; the first broken one is returned.
pub(crate) fn check(file: &ModelFile) -> Result<(), Problem> {
    match &file.combined {
        CombinedModel::Paper(m) => paper("combined", m)?,
        CombinedModel::Contact(m) => contact("combined", m)?,
    }
    if let Some(m) = &file.pure_nn {
        pure_nn("pure_nn", m, file.combined.horizon())?;
    }
    if let Some(d) = &file.training.domain {
        domain("training.domain", d)?;
    }
    Ok(())
}
