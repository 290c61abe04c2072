//! Small geometric vocabulary shared by every stage: vectors, rays, boxes.

pub use glam::Vec3A as Vec3;

/// A geometric ray. `dir` is always unit length so hit distances are world distances,
/// which the classic shading model relies on (intensity cut-offs, shadow tests).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start point in world space.
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
}

impl Ray {
    /// Builds a ray, normalising `dir`.
    #[inline]
    pub fn new(origin: Vec3, dir: Vec3) -> Ray {
        Ray {
            origin,
            dir: normalize(dir),
        }
    }

    /// The point at distance `t` along the ray.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// The cross product `a x b`, each component one product minus another, rounded
/// separately. glam's own fuses the subtraction into the second product on aarch64, so
/// its bits would differ by machine (and from the leaf test's lanes, which spell the
/// same expressions out).
#[inline]
pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::new(
        a.y * b.z - a.z * b.y,
        a.z * b.x - a.x * b.z,
        a.x * b.y - a.y * b.x,
    )
}

/// `v` scaled to unit length: each component divided by the length. glam's own
/// multiplies by the length's reciprocal on aarch64 instead, which rounds differently.
#[inline]
pub fn normalize(v: Vec3) -> Vec3 {
    v / v.length()
}

/// Relative size of the offset that lifts a secondary ray's origin off the surface it
/// leaves. f32 hit points carry an error of a few ulps of their largest coordinate; the
/// offset is well above that and far below any feature of a real scene.
pub const SURFACE_EPSILON: f32 = 2e-5;

/// The largest float below 1: where a number drawn in [0, 1) is clamped after arithmetic
/// that may round it up to 1.
pub const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;

/// Distance a secondary ray's origin is moved off a surface at `p`.
#[inline]
pub fn surface_epsilon(p: Vec3) -> f32 {
    SURFACE_EPSILON * (1.0 + p.abs().max_element())
}

/// Moves `p` off the surface with normal `n` (either orientation), to the side that
/// `toward` points into, so that a ray leaving in direction `toward` cannot hit the
/// surface it starts on.
#[inline]
pub fn offset_origin(p: Vec3, n: Vec3, toward: Vec3) -> Vec3 {
    let n = if n.dot(toward) >= 0.0 { n } else { -n };
    p + n * surface_epsilon(p)
}

/// The cofactor matrix of `m`: `det(m) m⁻ᵀ` where `m` is invertible. It takes a
/// triangle's normal (the cross product of its edges) to the normal of the triangle
/// `m` places, so it serves where the inverse does not exist: a transform that
/// flattens a solid onto a plane still has a plane's normal.
pub fn cofactor(m: glam::DMat3) -> glam::DMat3 {
    glam::DMat3::from_cols(
        m.y_axis.cross(m.z_axis),
        m.z_axis.cross(m.x_axis),
        m.x_axis.cross(m.y_axis),
    )
}

/// Mirror direction of `d` about the plane with normal `n` (either orientation).
#[inline]
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// Shirley and Chiu's map of the unit square onto the unit disk: uniform by area, and
/// neighbouring points stay neighbours.
#[inline]
pub fn concentric_disk((u, v): (f32, f32)) -> (f32, f32) {
    let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    // The angle is a/b or b/a of an eighth turn; past the diagonal, sine and cosine
    // swap (cos(pi/2 - x) = sin x), so only angles within an eighth turn are needed.
    if a.abs() > b.abs() {
        let (s, c) = sin_cos_eighth(std::f32::consts::FRAC_PI_4 * (b / a));
        (a * c, a * s)
    } else {
        let (s, c) = sin_cos_eighth(std::f32::consts::FRAC_PI_4 * (a / b));
        (b * s, b * c)
    }
}

/// Sine and cosine of `x` within an eighth turn (|x| <= pi/4) by their Taylor series
/// to within 2e-9: plain multiplications and additions, so the same bits on every
/// machine, and a tenth of `sin_cos`'s cost where samplers draw many directions.
#[inline]
pub fn sin_cos_eighth(x: f32) -> (f32, f32) {
    let x2 = x * x;
    let s = x
        * (1.0
            + x2 * (-1.0 / 6.0
                + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0)))));
    let c = 1.0
        + x2 * (-0.5
            + x2 * (1.0 / 24.0
                + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40_320.0 + x2 * (-1.0 / 3_628_800.0)))));
    (s, c)
}

/// Sine and cosine of `x` for `|x|` below 2^20, worked out in f64 and rounded once. So
/// they are the f32s nearest the true values (every one over a turn, [0, 2 pi), the
/// samplers' range), the same on every machine; only a value within about 1e-16,
/// relative, of halfway between two f32s can round the other way (of all inputs below
/// 2^20, just ±9830.3984375). The C library's `sincosf` differs from them in one input
/// of forty, and from one library to another. Without branches or calls, a loop of them
/// over lanes vectorises. At and beyond 2^20 the reduction loses the angle: callers
/// keep below it (a debug build checks).
#[inline]
pub(crate) fn sin_cos(x: f32) -> (f32, f32) {
    // fdlibm's split of pi/2 (its first 33 bits, exact times any quadrant below 2^20,
    // and the rest) and its kernels' coefficients for |r| <= pi/4.
    const PIO2_HI: f64 = 1.570_796_326_734_125_6;
    const PIO2_LO: f64 = 6.077_100_506_506_192e-11;
    const S: [f64; 6] = [
        -1.666_666_666_666_663_2e-1,
        8.333_333_333_322_49e-3,
        -1.984_126_982_985_795e-4,
        2.755_731_370_707_006_8e-6,
        -2.505_076_025_340_686_3e-8,
        1.589_690_995_211_55e-10,
    ];
    const C: [f64; 6] = [
        4.166_666_666_666_66e-2,
        -1.388_888_888_887_411e-3,
        2.480_158_728_947_673e-5,
        -2.755_731_435_139_066_3e-7,
        2.087_572_321_298_175e-9,
        -1.135_964_755_778_819_5e-11,
    ];
    // Adding 1.5 * 2^52 rounds to a whole number, which the low bits then hold.
    const ROUND: f64 = 6_755_399_441_055_744.0;
    debug_assert!(
        x.abs() < 1_048_576.0 || x.is_nan(),
        "sin_cos({x}) is out of its range"
    );
    let x = f64::from(x);
    let shifted = x * std::f64::consts::FRAC_2_PI + ROUND;
    let quadrant = shifted.to_bits() & 3;
    let k = shifted - ROUND;
    let r = (x - k * PIO2_HI) - k * PIO2_LO;
    let z = r * r;
    let sin = r + r * z * (S[0] + z * (S[1] + z * (S[2] + z * (S[3] + z * (S[4] + z * S[5])))));
    let cos = 1.0 - 0.5 * z
        + z * z * (C[0] + z * (C[1] + z * (C[2] + z * (C[3] + z * (C[4] + z * C[5])))));
    let (a, b) = if quadrant & 1 == 0 {
        (sin, cos)
    } else {
        (cos, sin)
    };
    let sin = if quadrant & 2 == 0 { a } else { -a };
    // The polynomial turns -0 into +0.
    let sin = if x == 0.0 { x } else { sin };
    let cos = if (quadrant + 1) & 2 == 0 { b } else { -b };
    (sin as f32, cos as f32)
}

/// `x.powf(y)` for a cosine `x` and a highlight exponent `y`, without the C library's
/// slow path for results that round to zero (with exponents in the hundreds, most
/// highlights vanish): where `x^y` is surely below 2^-151, the answer is +0, which is
/// what `powf` returns there, correctly rounded. Any other case is `powf`'s.
#[inline]
pub fn highlight_pow(x: f32, y: f32) -> f32 {
    /// log2(1 + (k + 1) / 16), rounded up: bounds log2 of a mantissa whose top four
    /// bits are k.
    const LOG2_MANTISSA_ABOVE: [f64; 16] = [
        0.08746284125133941,
        0.16992500144331238,
        0.2479275134445855,
        0.3219280948883623,
        0.3923174227797603,
        0.45943161863829723,
        0.5235619560580128,
        0.5849625007221562,
        0.6438561897757247,
        0.7004397181420922,
        0.7548875021644685,
        0.807354922058604,
        0.8579809951285721,
        0.9068905956095185,
        0.9541963103878752,
        1.000000000001,
    ];
    if (f32::MIN_POSITIVE..1.0).contains(&x) && y > 0.0 && y.is_finite() {
        let bits = x.to_bits();
        let exponent = f64::from((bits >> 23) as i32 - 127);
        let log2_above = exponent + LOG2_MANTISSA_ABOVE[(bits >> 19 & 0xf) as usize];
        // log2(x) < log2_above <= 0, so y log2(x) < y log2_above.
        if f64::from(y) * log2_above <= -152.0 {
            return 0.0;
        }
    }
    x.powf(y)
}

/// Axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Corner with the smallest coordinate on every axis.
    pub min: Vec3,
    /// Corner with the largest coordinate on every axis.
    pub max: Vec3,
}

impl Aabb {
    /// The box around nothing (`min` at +inf, `max` at -inf): the identity of
    /// [`Aabb::union`] and [`Aabb::grow`].
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// The smallest box holding every point; [`Aabb::EMPTY`] for none.
    pub fn from_points(points: &[Vec3]) -> Aabb {
        points.iter().fold(Aabb::EMPTY, |b, &p| b.grow(p))
    }

    /// The smallest box holding `self` and `p`.
    pub fn grow(self, p: Vec3) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// The smallest box holding both boxes.
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// Whether `min` exceeds `max` on some axis, as for [`Aabb::EMPTY`]; flat boxes are
    /// not empty.
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// Size along each axis, `max - min`.
    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    /// Halves first: the sum of two coordinates near ±f32::MAX would overflow.
    pub fn center(&self) -> Vec3 {
        self.min * 0.5 + self.max * 0.5
    }

    /// Closed-interval overlap: boxes that only touch overlap, and so do flat boxes
    /// (a rectangle lying in a cell face belongs to that cell).
    pub fn overlaps(&self, o: &Aabb) -> bool {
        self.min.cmple(o.max).all() && o.min.cmple(self.max).all()
    }

    /// Slab test: the parametric interval `[t0, t1]` of `ray` inside the box, clipped
    /// to `[0, t_max]`, or `None`. `inv_dir` is `1 / ray.dir` component-wise.
    #[inline]
    pub fn hit_interval(&self, origin: Vec3, inv_dir: Vec3, t_max: f32) -> Option<(f32, f32)> {
        let t_a = (self.min - origin) * inv_dir;
        let t_b = (self.max - origin) * inv_dir;
        // NaN (0 * inf, a ray lying in a slab plane) must not reject the box: min/max
        // of glam ignore a NaN operand on x86, and the fallback below keeps it so.
        let t_near = t_a.min(t_b);
        let t_far = t_a.max(t_b);
        let t0 = nan_to(t_near.max_element(), f32::NEG_INFINITY).max(0.0);
        let t1 = nan_to(t_far.min_element(), f32::INFINITY).min(t_max);
        // Slack of a few ulps so that flat boxes and grazing rays are kept.
        (t0 <= t1 * (1.0 + 4.0 * f32::EPSILON)).then_some((t0, t1))
    }
}

#[inline]
fn nan_to(x: f32, fallback: f32) -> f32 {
    if x.is_nan() { fallback } else { x }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sin_cos_within_an_eighth_turn_is_within_two_ulps_of_the_true_values() {
        for i in -1000..=1000 {
            let x = std::f32::consts::FRAC_PI_4 * i as f32 / 1000.0;
            let (s, c) = sin_cos_eighth(x);
            let (ts, tc) = (f64::from(x).sin(), f64::from(x).cos());
            assert!(
                (f64::from(s) - ts).abs() <= 2.0 * f64::from(f32::EPSILON) * ts.abs().max(1e-3),
                "sin {x}"
            );
            assert!(
                (f64::from(c) - tc).abs() <= 2.0 * f64::from(f32::EPSILON),
                "cos {x}"
            );
        }
    }

    /// The cofactor matrix takes a triangle's edge cross product to its placed
    /// triangle's, for invertible transforms (where it is det · m⁻ᵀ) and singular ones.
    #[test]
    fn the_cofactor_matrix_places_a_triangle_s_normal() {
        use glam::{DMat3, DVec3};
        use rand_core::Rng;
        let mut rng = rand_pcg::Pcg32::new(17, 0x0a02_bdbf_7bb3_c0a7);
        let mut unit = || f64::from(rng.next_u32()) / f64::from(u32::MAX) * 2.0 - 1.0;
        for k in 0..200 {
            let mut m = DMat3::from_cols_array(&std::array::from_fn(|_| unit()));
            if k % 2 == 1 {
                // Flattened onto a plane: the third column is a mix of the others.
                m.z_axis = m.x_axis * unit() + m.y_axis * unit();
            }
            let [a, b, c] = [(); 3].map(|_| DVec3::new(unit(), unit(), unit()));
            let placed = (m * b - m * a).cross(m * c - m * a);
            let n = cofactor(m) * (b - a).cross(c - a);
            assert!(
                (placed - n).length() <= 1e-12 * (1.0 + placed.length()),
                "{m}"
            );
            if k % 2 == 0 {
                let expected = m.inverse().transpose() * m.determinant();
                assert!(cofactor(m).abs_diff_eq(expected, 1e-12), "{m}");
            }
        }
        // Squashed flat along z, a box's top keeps its normal and its sides have none.
        let flat = cofactor(DMat3::from_diagonal(DVec3::new(2.0, 3.0, 0.0)));
        assert_eq!(flat * DVec3::Z, DVec3::new(0.0, 0.0, 6.0));
        assert_eq!(flat * DVec3::X, DVec3::ZERO);
    }

    #[test]
    fn the_concentric_map_turns_the_square_s_diagonals_to_the_disk_s() {
        let (x, y) = concentric_disk((1.0, 1.0));
        let h = std::f32::consts::FRAC_1_SQRT_2;
        assert!((x - h).abs() < 1e-6 && (y - h).abs() < 1e-6);
        assert_eq!(concentric_disk((0.5, 0.5)), (0.0, 0.0));
        let (x, y) = concentric_disk((0.5, 1.0));
        assert!(x.abs() < 1e-7 && (y - 1.0).abs() < 1e-7);
    }

    #[test]
    fn highlight_pow_is_powf_bit_for_bit() {
        use rand_core::Rng;
        let mut rng = rand_pcg::Pcg32::new(9, 0x0a02_bdbf_7bb3_c0a7);
        let exponents = [
            0.5, 1.0, 2.0, 7.5, 20.0, 60.0, 128.0, 200.0, 1000.0, 1e4, 1e6,
        ];
        let mut zeros = 0;
        for _ in 0..20_000 {
            // Any float in [0, 1], and the range where x^200 crosses 2^-150.
            let x = f32::from_bits(rng.next_u32() % (1.0f32.to_bits() + 1));
            let near = 0.55 + 0.07 * (rng.next_u32() >> 8) as f32 / (1 << 24) as f32;
            for x in [x, near] {
                for &y in &exponents {
                    let (ours, libm) = (highlight_pow(x, y), x.powf(y));
                    assert_eq!(ours.to_bits(), libm.to_bits(), "{x}^{y}");
                    zeros += usize::from(ours == 0.0);
                }
            }
        }
        assert!(zeros > 10_000, "{zeros}");
        for (x, y) in [
            (1.0, 3.0),
            (0.0, 5.0),
            (-0.5, 3.0),
            (f32::NAN, 2.0),
            (0.5, f32::INFINITY),
        ] {
            assert_eq!(
                highlight_pow(x, y).to_bits(),
                x.powf(y).to_bits(),
                "{x}^{y}"
            );
        }
    }

    #[test]
    fn ray_direction_is_normalised() {
        let r = Ray::new(Vec3::ZERO, Vec3::new(3.0, 0.0, 4.0));
        assert_eq!(r.dir, Vec3::new(0.6, 0.0, 0.8));
        assert_eq!(r.at(5.0), Vec3::new(3.0, 0.0, 4.0));
    }

    #[test]
    fn reflection_mirrors_about_normal() {
        let d = Vec3::new(1.0, -1.0, 0.0);
        assert_eq!(reflect(d, Vec3::Y), Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(reflect(d, -Vec3::Y), Vec3::new(1.0, 1.0, 0.0));
    }

    #[test]
    fn sin_cos_matches_f64_sine_and_cosine_rounded() {
        let nearest = |x: f32| {
            let x = f64::from(x);
            (x.sin() as f32, x.cos() as f32)
        };
        let bits = |(s, c): (f32, f32)| (s.to_bits(), c.to_bits());
        // Every 257th f32 of the turn a sampler draws, both signs, and a few turns on.
        let mut inputs = vec![0.0, -0.0, f32::MIN_POSITIVE, 1e-30, 1e5, -1e5, 1_048_575.9];
        let mut b = 0u32;
        while b <= std::f32::consts::TAU.to_bits() {
            inputs.push(f32::from_bits(b));
            inputs.push(-f32::from_bits(b));
            b += 257;
        }
        for k in 0..4000 {
            inputs.push(k as f32 * 0.0137 + 7.0);
        }
        // Many quadrants: every 4099th f32 from 62 to 2^20.
        let mut b = 62f32.to_bits();
        while b < 1_048_576f32.to_bits() {
            inputs.push(f32::from_bits(b));
            b += 4099;
        }
        for x in inputs {
            assert_eq!(bits(sin_cos(x)), bits(nearest(x)), "sin_cos({x:e})");
        }
        // Exact where the rounding leaves nothing to chance.
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        assert_eq!(sin_cos(-0.0).0.to_bits(), (-0.0f32).to_bits());
        let (s, c) = sin_cos(std::f32::consts::FRAC_PI_2);
        assert_eq!((s, c), (1.0, -4.371_139e-8));
        let (s, c) = sin_cos(f32::NAN);
        assert!(s.is_nan() && c.is_nan());
    }

    /// Every f32 of a turn, in a release build: `cargo test --release --lib
    /// sin_cos_over_a_whole_turn -- --ignored` (15 s).
    #[test]
    #[ignore]
    fn sin_cos_over_a_whole_turn() {
        for b in 0..=std::f32::consts::TAU.to_bits() {
            let x = f32::from_bits(b);
            let (s, c) = sin_cos(x);
            let x = f64::from(x);
            assert_eq!((s, c), (x.sin() as f32, x.cos() as f32), "sin_cos({x:e})");
        }
    }

    #[test]
    fn offset_goes_to_the_side_of_the_new_ray() {
        let p = Vec3::new(0.0, 0.0, 0.0);
        let up = offset_origin(p, Vec3::Z, Vec3::new(0.3, 0.0, 1.0));
        let down = offset_origin(p, Vec3::Z, Vec3::new(0.3, 0.0, -1.0));
        assert!(up.z > 0.0 && down.z < 0.0);
        assert_eq!(up.z, SURFACE_EPSILON);
    }

    #[test]
    fn slab_test_handles_flat_boxes_and_axis_parallel_rays() {
        let flat = Aabb {
            min: Vec3::new(-1.0, -1.0, 0.0),
            max: Vec3::new(1.0, 1.0, 0.0),
        };
        let r = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        let (t0, t1) = flat
            .hit_interval(r.origin, r.dir.recip(), f32::INFINITY)
            .unwrap();
        assert_eq!((t0, t1), (5.0, 5.0));
        let miss = Ray::new(Vec3::new(2.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        assert!(
            flat.hit_interval(miss.origin, miss.dir.recip(), f32::INFINITY)
                .is_none()
        );
        assert!(flat.hit_interval(r.origin, r.dir.recip(), 4.0).is_none());
    }
}
