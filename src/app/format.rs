//! Numbers as the panels and the browser print them, where a plain fixed number of decimals would
//! mislead.

/// A loss with `decimals` decimals, or two digits and an exponent below a thousandth, where the
/// decimals would read 0.000: the MIT files run under a model trained on the sample data's pushes,
/// whose loss scale is far larger, have losses of 1e-4 and less.
pub fn loss(value: f64, decimals: usize) -> String {
    if value == 0.0 || value.abs() >= 1e-3 {
        format!("{value:.decimals$}")
    } else {
        format!("{value:.1e}")
    }
}

/// `value` to two decimals, without the minus of a value that rounds to zero: an MIT shape's true
/// COM is its centroid, whose offset from itself is a rounding error like −1e-18 m, shown as
/// "-0.00" before.
pub fn hundredths(value: f64) -> String {
    let text = format!("{value:.2}");
    match text.strip_prefix('-') {
        Some(magnitude) if magnitude == "0.00" => magnitude.to_owned(),
        _ => text,
    }
}

/// `n` and the noun for it: "1 step", "20 steps" (a sentence in a panel, where "1 steps" reads as a
/// slip; the CLI's tables keep "step(s)").
pub fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// How much the prediction trusts the combined model or physics alone for one `part` of the motion
/// ("translation", "rotation"), given the combined model's weight and its evidence's half-life, and
/// why where physics is trusted: the Steer tab's words and the demo narration's. The words speak of
/// twice the half-life, the seconds the evidence mostly covers.
pub fn trust(part: &str, combined_weight: f64, half_life_s: f64) -> String {
    let window_s = 2.0 * half_life_s;
    if combined_weight >= 0.5 {
        format!("Trusting the combined model {combined_weight:.2} for the {part}")
    } else {
        format!(
            "Trusting physics {:.2} for the {part}: the network has predicted this object's {part} \
             worse than Lynch's model alone over the last {window_s:.0} s",
            1.0 - combined_weight
        )
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_count_of_one_takes_the_singular() {
        assert_eq!(super::count(1, "step", "steps"), "1 step");
        assert_eq!(super::count(0, "step", "steps"), "0 steps");
        assert_eq!(super::count(20, "step", "steps"), "20 steps");
    }

    #[test]
    fn losses_below_a_thousandth_keep_two_digits() {
        let cells = [0.1314, 0.001, 4.23e-4, 0.0].map(|v| super::loss(v, 3));
        assert_eq!(cells, ["0.131", "0.001", "4.2e-4", "0.000"]);
        assert_eq!(super::loss(2.6e-5, 4), "2.6e-5");
        assert_eq!(super::loss(0.14131, 4), "0.1413");
    }

    #[test]
    fn hundredths_drop_the_sign_of_a_zero() {
        assert_eq!(super::hundredths(-1e-15), "0.00");
        assert_eq!(super::hundredths(-0.0), "0.00");
        assert_eq!(super::hundredths(-0.004), "0.00");
        assert_eq!(super::hundredths(-0.006), "-0.01");
        assert_eq!(super::hundredths(12.345), "12.35");
    }
}
