//! Plot axes with tick marks at round numbers (1, 2 or 5 × 10ᵏ, the
//! usual choice of plotting programs) and labels that share one number of
//! decimals; large or small numbers share a power of ten shown once in
//! the axis title. A logarithmic axis works in log₁₀ of the value and
//! marks whole decades.

use std::ops::Range;

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, KeyPointWeight, Ranged};

/// Values beyond this magnitude are drawn as if at it (keeps every sum
/// finite).
pub(crate) const HUGE: f64 = 1e300;

/// Magnitudes below this are drawn as zero.
const TINY: f64 = 1e-200;

/// Fraction of the data's span left free above and below it.
const PAD: f64 = 0.04;

/// One axis of a chart: the range shown and the labelled ticks, in plot
/// coordinates (the value on a linear axis, its log₁₀ on a log axis).
#[derive(Debug, Clone)]
pub(crate) struct Axis {
    lo: f64,
    hi: f64,
    ticks: Vec<(f64, String)>,
    /// The power of ten the labels are divided by ("×10³"), for the title.
    pub(crate) factor: Option<String>,
}

impl Axis {
    /// A linear axis showing `min..=max` with about `target` ticks; `pad`
    /// leaves a margin around the data; the span shown is at least
    /// `min_span`.
    pub(crate) fn linear(min: f64, max: f64, target: usize, pad: bool, min_span: f64) -> Axis {
        let (mut lo, mut hi) = sane_range(min, max);
        if hi - lo < min_span && min_span.is_finite() {
            let (centre, half) = (0.5 * (lo + hi), 0.5 * min_span.min(HUGE));
            (lo, hi) = (centre - half, centre + half);
        }
        let magnitude = lo.abs().max(hi.abs());
        let span = hi - lo;
        if span <= magnitude * 1e-9 {
            let half = if magnitude > 0.0 {
                0.1 * magnitude
            } else {
                1.0
            };
            (lo, hi) = (lo - half, hi + half);
        } else if span < magnitude * 1e-6 {
            let centre = 0.5 * (lo + hi);
            (lo, hi) = (centre - 5e-7 * magnitude, centre + 5e-7 * magnitude);
        } else if pad {
            (lo, hi) = (lo - PAD * span, hi + PAD * span);
        }
        let (mantissa, power) = nice_step((hi - lo) / target.max(2) as f64);
        let step = mantissa * 10f64.powi(power);
        let magnitude = lo.abs().max(hi.abs());
        let exponent = if magnitude > 0.0 && !(1e-2..1e4).contains(&magnitude) {
            3 * (magnitude.log10().floor() as i32).div_euclid(3)
        } else {
            0
        };
        let decimals = (exponent - power).max(0) as usize;
        let first = (lo / step).ceil() as i64;
        let last = (hi / step).floor() as i64;
        let ticks = (first..=last)
            .take(100)
            .map(|i| {
                let value = i as f64 * step;
                let shown = i as f64 * mantissa * 10f64.powi(power - exponent);
                (value, minus(format!("{shown:.decimals$}")))
            })
            .collect();
        let factor = (exponent != 0).then(|| format!("×10{}", superscript(exponent)));
        Axis {
            lo,
            hi,
            ticks,
            factor,
        }
    }

    /// A log₁₀ axis for the positive values `min..=max` (m > 0), about
    /// `target` ticks; the data to draw on it are log₁₀ of the values.
    pub(crate) fn log(min: f64, max: f64, target: usize) -> Axis {
        let (min, max) = sane_range(min.max(TINY), max.max(TINY));
        let (mut lo, mut hi) = (min.log10(), max.log10());
        if hi - lo < 0.02 {
            (lo, hi) = (lo - 0.01, hi + 0.01);
        }
        let span = hi - lo;
        (lo, hi) = (lo - PAD * span, hi + PAD * span);
        let (first, last) = (lo.ceil() as i32, hi.floor() as i32);
        let decades = (last - first + 1).max(0) as usize;
        let plain = -3 < first && last <= 4;
        let ticks: Vec<(f64, String)> = if decades >= 2 {
            let stride = [1, 2, 3, 5, 10, 20, 50, 100]
                .into_iter()
                .find(|s| decades.div_ceil(*s) <= target.max(2))
                .unwrap_or(100) as i32;
            (first..=last)
                .filter(|k| k.rem_euclid(stride) == 0)
                .map(|k| (f64::from(k), power_label(1, k, plain)))
                .collect()
        } else {
            (first - 1..=last)
                .flat_map(|k| [1, 2, 5].map(|m| (m, k)))
                .map(|(m, k)| {
                    let position = f64::from(m).log10() + f64::from(k);
                    (position, power_label(m, k, plain))
                })
                .filter(|&(p, _)| lo <= p && p <= hi)
                .collect()
        };
        if ticks.len() < 2 {
            // Less than a factor 2 shown: round numbers in value space.
            let linear = Axis::linear(10f64.powf(lo), 10f64.powf(hi), target, false, 0.0);
            let ticks = linear
                .ticks
                .into_iter()
                .filter(|&(v, _)| v > 0.0)
                .map(|(v, label)| (v.log10(), label))
                .collect();
            return Axis {
                lo,
                hi,
                ticks,
                factor: linear.factor,
            };
        }
        Axis {
            lo,
            hi,
            ticks,
            factor: None,
        }
    }

    /// The label of the tick at `value` (a value from this axis's ticks).
    pub(crate) fn label(&self, value: f64) -> String {
        self.ticks
            .iter()
            .find(|(v, _)| *v == value)
            .map(|(_, l)| l.clone())
            .unwrap_or_default()
    }

    /// All tick labels, in order.
    pub(crate) fn labels(&self) -> impl Iterator<Item = &str> {
        self.ticks.iter().map(|(_, l)| l.as_str())
    }
}

impl Ranged for Axis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let fraction = (value - self.lo) / (self.hi - self.lo);
        let pixel = f64::from(limit.0) + fraction * f64::from(limit.1 - limit.0);
        pixel.clamp(-1e6, 1e6).round() as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        match hint.weight() {
            KeyPointWeight::Bold => self.ticks.iter().map(|(v, _)| *v).collect(),
            KeyPointWeight::Any => Vec::new(),
        }
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

/// Clamp to finite magnitudes and order; a range with nothing in it
/// (no finite values) becomes 0..1.
fn sane_range(min: f64, max: f64) -> (f64, f64) {
    if !(min.is_finite() && max.is_finite()) {
        return (0.0, 1.0);
    }
    let clean = |v: f64| {
        if v.abs() < TINY {
            0.0
        } else {
            v.clamp(-HUGE, HUGE)
        }
    };
    let (a, b) = (clean(min), clean(max));
    (a.min(b), a.max(b))
}

/// The smallest of 1, 2 or 5 × 10ᵏ at least `raw`, as (mantissa, k).
fn nice_step(raw: f64) -> (f64, i32) {
    let raw = if raw.is_finite() && raw > 0.0 {
        raw
    } else {
        1.0
    };
    let power = raw.log10().floor() as i32;
    let scaled = raw / 10f64.powi(power);
    match [1.0, 2.0, 5.0]
        .into_iter()
        .find(|&m| m >= scaled * (1.0 - 1e-9))
    {
        Some(m) => (m, power),
        None => (1.0, power + 1),
    }
}

/// `m × 10ᵏ` as a label: `plain` decimals (for axes within 10⁻³ to 10⁴),
/// else with a superscript power.
fn power_label(m: i32, k: i32, plain: bool) -> String {
    if plain {
        let value = f64::from(m) * 10f64.powi(k);
        format!("{value:.*}", (-k).max(0) as usize)
    } else if m == 1 {
        format!("10{}", superscript(k))
    } else {
        format!("{m}×10{}", superscript(k))
    }
}

/// `k` in superscript digits (and the superscript minus).
pub(crate) fn superscript(k: i32) -> String {
    k.to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            _ => '⁹',
        })
        .collect()
}

/// A typographic minus sign in place of the hyphen.
fn minus(label: String) -> String {
    label.replace('-', "−")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(axis: &Axis) -> Vec<&str> {
        axis.labels().collect()
    }

    #[test]
    fn round_steps() {
        assert_eq!(nice_step(0.13), (2.0, -1));
        assert_eq!(nice_step(3.0), (5.0, 0));
        assert_eq!(nice_step(6.0), (1.0, 1));
        assert_eq!(nice_step(1.0), (1.0, 0));
    }

    #[test]
    fn linear_labels_share_decimals() {
        let axis = Axis::linear(0.0, 1.0, 5, false, 0.0);
        assert_eq!(labels(&axis), ["0.0", "0.2", "0.4", "0.6", "0.8", "1.0"]);
        let axis = Axis::linear(-2.0, 2.0, 4, false, 0.0);
        assert_eq!(labels(&axis), ["−2", "−1", "0", "1", "2"]);
    }

    #[test]
    fn large_and_small_numbers_share_a_power_of_ten() {
        let axis = Axis::linear(0.0, 25_000.0, 5, false, 0.0);
        assert_eq!(axis.factor.as_deref(), Some("×10³"));
        assert_eq!(labels(&axis), ["0", "5", "10", "15", "20", "25"]);
        let axis = Axis::linear(0.0, 0.003, 3, false, 0.0);
        assert_eq!(axis.factor.as_deref(), Some("×10⁻³"));
        assert_eq!(labels(&axis), ["0", "1", "2", "3"]);
    }

    #[test]
    fn constant_and_pathological_data_still_give_ticks() {
        for (min, max) in [
            (0.79, 0.79),
            (0.0, 0.0),
            (-1e308, 1e308),
            (f64::NAN, 1.0),
            (1e-310, 2e-310),
        ] {
            let axis = Axis::linear(min, max, 6, true, 0.0);
            assert!(axis.ticks.len() >= 2, "{min}..{max}: {:?}", axis.ticks);
            assert!(axis.lo < axis.hi && axis.lo.is_finite() && axis.hi.is_finite());
        }
    }

    #[test]
    fn log_axes_mark_decades() {
        let axis = Axis::log(1e-6, 2600.0, 8);
        assert_eq!(labels(&axis), ["10⁻⁶", "10⁻⁴", "10⁻²", "10⁰", "10²"]);
        let axis = Axis::log(1.0, 2600.0, 8);
        assert_eq!(labels(&axis), ["1", "10", "100", "1000"]);
        let axis = Axis::log(1e-12, 1e4, 5);
        assert!(labels(&axis).len() <= 6, "{:?}", labels(&axis));
        let axis = Axis::log(0.9, 1.2, 5);
        assert!(labels(&axis).len() >= 2, "{:?}", labels(&axis));
    }

    #[test]
    fn map_runs_from_one_end_to_the_other() {
        let axis = Axis::linear(0.0, 10.0, 5, false, 0.0);
        assert_eq!(axis.map(&0.0, (100, 0)), 100);
        assert_eq!(axis.map(&10.0, (100, 0)), 0);
        assert_eq!(axis.map(&5.0, (0, 100)), 50);
    }
}
