//! The value types of the scene file, checked as they are read: a number that is
//! infinite, NaN or beyond [`MAX_VALUE`], or a colour with a negative channel, is a
//! TOML type error, so it carries the line and column of the value.

use crate::math::Vec3;
use crate::scene::material::srgb_to_linear;
use glam::DVec3;
use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use std::fmt;

/// Largest magnitude accepted for any number: beyond it f32 geometry overflows.
pub const MAX_VALUE: f64 = 1e30;

fn checked<E: de::Error>(v: f64) -> Result<f64, E> {
    if v.is_finite() && v.abs() <= MAX_VALUE {
        Ok(v)
    } else {
        Err(E::custom(format!(
            "expected a finite number of magnitude at most 1e30, found {v}"
        )))
    }
}

/// A finite number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Num(pub f64);

impl Num {
    pub fn f32(self) -> f32 {
        self.0 as f32
    }
}

impl<'de> Deserialize<'de> for Num {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Num, D::Error> {
        checked(f64::deserialize(d)?).map(Num)
    }
}

/// `[x, y, z]` of finite numbers: a point, direction or offset.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vector(pub DVec3);

impl Vector {
    pub fn vec3(self) -> Vec3 {
        Vec3::new(self.0.x as f32, self.0.y as f32, self.0.z as f32)
    }
}

impl<'de> Deserialize<'de> for Vector {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Vector, D::Error> {
        let [x, y, z] = <[Num; 3]>::deserialize(d)?;
        Ok(Vector(DVec3::new(x.0, y.0, z.0)))
    }
}

/// A number or `[x, y, z]`: a uniform or per-axis value (`scale`, `specular`...).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triple {
    pub value: DVec3,
    /// Whether it was written as one number.
    pub uniform: bool,
}

/// A colour, linear RGB, no channel negative: `[r, g, b]`, a grey level, or
/// `"#rrggbb"` (sRGB, as colour pickers give it, decoded to linear).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Color {
    pub rgb: Vec3,
    /// Written as one number: some terms read a number as a factor of another colour.
    pub number: bool,
}

struct TripleVisitor {
    color: bool,
}

impl<'de> Visitor<'de> for TripleVisitor {
    type Value = (DVec3, bool);

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        if self.color {
            f.write_str("a colour: [r, g, b], a number or \"#rrggbb\"")
        } else {
            f.write_str("a number or [x, y, z]")
        }
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
        self.visit_f64(v as f64)
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
        self.visit_f64(v as f64)
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Self::Value, E> {
        Ok((DVec3::splat(checked(v)?), true))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
        if !self.color {
            return Err(E::invalid_type(de::Unexpected::Str(v), &self));
        }
        let hex = v
            .strip_prefix('#')
            .filter(|h| h.len() == 6 && h.bytes().all(|b| b.is_ascii_hexdigit()))
            .ok_or_else(|| E::custom(format!("expected a colour \"#rrggbb\", found \"{v}\"")))?;
        let channel = |i: usize| f32::from(u8::from_str_radix(&hex[i..i + 2], 16).unwrap_or(0));
        let c = srgb_to_linear(Vec3::new(channel(0), channel(2), channel(4)) / 255.0);
        Ok((DVec3::new(c.x as f64, c.y as f64, c.z as f64), false))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut v = [0.0; 3];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = seq
                .next_element::<Num>()?
                .ok_or_else(|| de::Error::invalid_length(i, &self))?
                .0;
        }
        if seq.next_element::<de::IgnoredAny>()?.is_some() {
            return Err(de::Error::invalid_length(4, &self));
        }
        Ok((DVec3::from_array(v), false))
    }
}

impl<'de> Deserialize<'de> for Triple {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Triple, D::Error> {
        let (value, uniform) = d.deserialize_any(TripleVisitor { color: false })?;
        Ok(Triple { value, uniform })
    }
}

impl<'de> Deserialize<'de> for Color {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Color, D::Error> {
        let (c, number) = d.deserialize_any(TripleVisitor { color: true })?;
        if c.min_element() < 0.0 {
            return Err(de::Error::custom(format!(
                "expected colour channels >= 0, found [{}, {}, {}]",
                c.x, c.y, c.z
            )));
        }
        Ok(Color {
            rgb: Vec3::new(c.x as f32, c.y as f32, c.z as f32),
            number,
        })
    }
}
