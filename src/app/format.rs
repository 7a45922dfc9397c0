//! Numbers as the panels print them, where a fixed number of decimals would mislead.

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

#[cfg(test)]
mod tests {
    #[test]
    fn losses_below_a_thousandth_keep_two_digits() {
        let cells = [0.1314, 0.001, 4.23e-4, 0.0].map(|v| super::loss(v, 3));
        assert_eq!(cells, ["0.131", "0.001", "4.2e-4", "0.000"]);
        assert_eq!(super::loss(2.6e-5, 4), "2.6e-5");
        assert_eq!(super::loss(0.14131, 4), "0.1413");
    }
}
