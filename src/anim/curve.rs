//! Keyframes and interpolation: a value that changes over time.
//!
//! A curve holds keys `(time, value)` with strictly increasing times. Before the first key
//! it holds the first value, after the last the last. Between two keys it blends them with
//! the curve's [`Interpolation`]: `linear`, or `smooth` (ease in and out: the blend weight
//! follows `3u² − 2u³`, so the motion starts and stops at zero speed at every key).

use glam::DVec3;

/// How a curve moves between two keys.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Interpolation {
    /// Constant speed from key to key: weight `u`.
    #[default]
    Linear,
    /// Ease in and out, weight `3u² − 2u³`: zero speed at every key.
    Smooth,
}

impl Interpolation {
    /// Blend weight at fraction `u` in `[0, 1]` of the way from one key to the next.
    pub fn weight(self, u: f64) -> f64 {
        match self {
            Interpolation::Linear => u,
            Interpolation::Smooth => u * u * (3.0 - 2.0 * u),
        }
    }
}

impl std::str::FromStr for Interpolation {
    type Err = String;
    fn from_str(s: &str) -> Result<Interpolation, String> {
        match s {
            "linear" => Ok(Interpolation::Linear),
            "smooth" => Ok(Interpolation::Smooth),
            _ => Err(format!(
                "unknown interpolation {}: expected linear or smooth",
                crate::util::text::shown(s)
            )),
        }
    }
}

/// A value that keys can hold: blended linearly, component by component.
pub trait Blend: Copy {
    /// `a + (b − a) w`, exactly `a` at `w = 0` and exactly `b` at `w = 1`.
    fn blend(a: Self, b: Self, w: f64) -> Self;
}

impl Blend for f64 {
    fn blend(a: f64, b: f64, w: f64) -> f64 {
        // Exact at both ends: w = 0 gives a, w = 1 gives b.
        if w == 1.0 { b } else { a + (b - a) * w }
    }
}

impl Blend for DVec3 {
    fn blend(a: DVec3, b: DVec3, w: f64) -> DVec3 {
        DVec3::new(
            f64::blend(a.x, b.x, w),
            f64::blend(a.y, b.y, w),
            f64::blend(a.z, b.z, w),
        )
    }
}

/// Keys in time order and how to move between them.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve<T> {
    keys: Vec<(f64, T)>,
    interpolation: Interpolation,
}

impl<T: Blend> Curve<T> {
    /// A curve over `keys`. The caller has checked that there is at least one key and
    /// that times are finite and strictly increasing (the file parser reports where not).
    pub fn new(keys: Vec<(f64, T)>, interpolation: Interpolation) -> Curve<T> {
        assert!(!keys.is_empty(), "a curve needs a key");
        debug_assert!(keys.windows(2).all(|w| w[0].0 < w[1].0));
        Curve {
            keys,
            interpolation,
        }
    }

    /// A curve that holds `value` for ever.
    pub fn constant(value: T) -> Curve<T> {
        Curve::new(vec![(0.0, value)], Interpolation::Linear)
    }

    /// The value at time `t` (seconds).
    pub fn at(&self, t: f64) -> T {
        let keys = &self.keys;
        let after = keys.partition_point(|k| k.0 <= t);
        if after == 0 {
            return keys[0].1;
        }
        if after == keys.len() {
            return keys[after - 1].1;
        }
        let (t0, a) = keys[after - 1];
        let (t1, b) = keys[after];
        let u = (t - t0) / (t1 - t0);
        T::blend(a, b, self.interpolation.weight(u))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_values_at_known_times_are_exact() {
        let c = Curve::new(
            vec![(1.0, 10.0), (2.0, 30.0), (4.0, -10.0)],
            Interpolation::Linear,
        );
        assert_eq!(c.at(0.0), 10.0, "held before the first key");
        assert_eq!(c.at(1.0), 10.0);
        assert_eq!(c.at(1.5), 20.0);
        assert_eq!(c.at(1.25), 15.0);
        assert_eq!(c.at(2.0), 30.0);
        assert_eq!(c.at(3.0), 10.0);
        assert_eq!(c.at(3.5), 0.0);
        assert_eq!(c.at(4.0), -10.0);
        assert_eq!(c.at(9.0), -10.0, "held after the last key");
    }

    #[test]
    fn smooth_values_at_known_times_are_exact() {
        let c = Curve::new(vec![(0.0, 0.0), (4.0, 64.0)], Interpolation::Smooth);
        // w(u) = 3u^2 - 2u^3: w(1/4) = 5/32, w(1/2) = 1/2, w(3/4) = 27/32.
        assert_eq!(c.at(1.0), 10.0);
        assert_eq!(c.at(2.0), 32.0);
        assert_eq!(c.at(3.0), 54.0);
        assert_eq!(c.at(4.0), 64.0);
        // Zero speed at the keys: the first step moves less than a linear one would.
        assert!(c.at(0.1) < 64.0 * 0.1 / 4.0 / 10.0);
    }

    #[test]
    fn vectors_blend_per_component_and_a_single_key_holds() {
        let c = Curve::new(
            vec![
                (0.0, DVec3::new(0.0, 8.0, -4.0)),
                (2.0, DVec3::new(4.0, 0.0, 4.0)),
            ],
            Interpolation::Linear,
        );
        assert_eq!(c.at(0.5), DVec3::new(1.0, 6.0, -2.0));
        assert_eq!(Curve::constant(7.5).at(-3.0), 7.5);
        assert_eq!(Curve::constant(7.5).at(1e9), 7.5);
    }

    #[test]
    fn interpolation_names() {
        assert_eq!("smooth".parse(), Ok(Interpolation::Smooth));
        assert_eq!("linear".parse(), Ok(Interpolation::Linear));
        assert!("cubic".parse::<Interpolation>().is_err());
    }
}
