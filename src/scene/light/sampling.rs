//! Lights sampled from a shading point, as every model needs them: a direction toward
//! the light with the light arriving along it and the density with which it was
//! chosen (per unit solid angle), that density for a direction found otherwise (a
//! surface's own sample that met the light), and where a ray meets a light that is
//! not geometry (quads, disks, spheres): what next-event estimation and multiple
//! importance sampling ask of a light.

use super::{Falloff, Light, LightKind};
use crate::math::{Ray, Vec3, concentric_disk, cross, normalize, sin_cos};
use crate::scene::{Scene, Shape, ShapeId, Surface};

/// Light arriving at a point from one sample of a light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Incident {
    /// Unit direction from the point toward the sample.
    pub dir: Vec3,
    /// Distance to the sample; infinite for a directional light.
    pub dist: f32,
    /// The radiance arriving along `dir` from an area light; for a point, spot or
    /// directional light (one direction) the irradiance on a surface facing it.
    pub li: Vec3,
    /// Density of `dir` per unit solid angle; zero for a light of one direction.
    pub pdf: f32,
}

impl Incident {
    /// Whether the light reaches the point along one direction only (no other
    /// strategy can find it).
    pub fn is_delta(&self) -> bool {
        self.pdf == 0.0
    }
}

/// A point drawn on a flat light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmitterPoint {
    /// Where it lies.
    pub y: Vec3,
    /// The light's unit normal there: the side it emits to.
    pub normal: Vec3,
    /// The radiance it emits.
    pub le: Vec3,
}

/// A triangle of an emissive mesh as its light samples it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshTriangle {
    /// Its corners.
    pub v: [Vec3; 3],
    /// Its unit normal: the side it emits to.
    pub normal: Vec3,
    /// The radiance it emits.
    pub le: Vec3,
}

/// A flat light (quad, disk, emissive mesh) ready to draw points from and to meet
/// rays: its frame and area worked out once, by the arithmetic of [`Light::flat`], so
/// a renderer that keeps one gets the bits of one made at every sample.
#[derive(Clone, Copy)]
pub struct FlatEmitter<'a> {
    light: &'a Light,
    /// The emitting area, in squared world units.
    pub area: f32,
    /// The unit normal of a quad or disk.
    normal: Vec3,
    /// A disk's axes in its plane.
    t1: Vec3,
    t2: Vec3,
}

impl FlatEmitter<'_> {
    /// The light's point at `at`, uniform in its area for uniform `at`: a point of the
    /// unit square for a quad or a mesh, of the unit disk for a disk. `None` for an
    /// empty mesh or a mesh shape that is not a triangle. `surfaces` gives a mesh
    /// light's emission.
    #[inline(always)]
    pub fn point(
        &self,
        scene: &Scene,
        surfaces: &[Surface],
        (a, b): (f32, f32),
    ) -> Option<EmitterPoint> {
        let light = self.light;
        let power = light.color * light.intensity;
        match &light.kind {
            LightKind::Quad { u, v } => Some(EmitterPoint {
                y: light.position + *u * (a - 0.5) + *v * (b - 0.5),
                normal: self.normal,
                le: power,
            }),
            LightKind::Disk { radius, .. } => Some(EmitterPoint {
                y: light.position + (self.t1 * a + self.t2 * b) * *radius,
                normal: self.normal,
                le: power,
            }),
            LightKind::Mesh { shapes, cdf, .. } => {
                if shapes.is_empty() {
                    return None;
                }
                let (k, su) = pick_triangle(cdf, shapes.len(), a);
                let tri = light.mesh_triangle(scene, surfaces, shapes[k])?;
                Some(EmitterPoint {
                    y: triangle_point(tri.v, su, b),
                    normal: tri.normal,
                    le: tri.le,
                })
            }
            _ => None,
        }
    }

    /// [`Light::sample_incident`] of this flat light.
    #[inline]
    pub fn sample_incident(
        &self,
        scene: &Scene,
        surfaces: &[Surface],
        p: Vec3,
        (a, b): (f32, f32),
    ) -> Option<Incident> {
        let at = match self.light.kind {
            LightKind::Disk { .. } => concentric_disk((a, b)),
            _ => (a, b),
        };
        let y = self.point(scene, surfaces, at)?;
        planar_sample(p, y.y, y.normal, self.area, y.le)
    }

    /// [`Light::hit`] of this flat light; `None` for an emissive mesh, whose
    /// triangles the intersector meets.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: f32) -> Option<(f32, Vec3)> {
        let light = self.light;
        let normal = self.normal;
        let t = match &light.kind {
            LightKind::Quad { u, v } => {
                let t = plane_hit(ray, light.position, normal)?;
                // Beyond the bound (or not ahead), the quad's point need not be found.
                if !(t > 0.0 && t < t_max) {
                    return None;
                }
                let q = ray.at(t) - light.position;
                // The point's coordinates along the edges, times the area.
                let s = cross(q, *v).dot(normal);
                let r = cross(*u, q).dot(normal);
                if beyond_half(s, self.area) || beyond_half(r, self.area) {
                    return None;
                }
                t
            }
            LightKind::Disk { radius, .. } => {
                let t = plane_hit(ray, light.position, normal)?;
                if (ray.at(t) - light.position).length_squared() > radius * radius {
                    return None;
                }
                t
            }
            _ => return None,
        };
        (t > 0.0 && t < t_max && t.is_finite()).then_some((t, normal))
    }
}

impl Light {
    /// One sample of the light seen from `p`, drawn with `u` uniform in the unit
    /// square; `None` where the light sends nothing toward `p` (behind a one-sided
    /// emitter, inside a sphere light, a light without area). `surfaces` gives a mesh
    /// light's emission.
    pub fn sample_incident(
        &self,
        scene: &Scene,
        surfaces: &[Surface],
        p: Vec3,
        (a, b): (f32, f32),
    ) -> Option<Incident> {
        match &self.kind {
            LightKind::Point | LightKind::Spot { .. } | LightKind::Directional { .. } => {
                let (dir, dist, li) = self.delta_irradiance(p)?;
                Some(Incident {
                    dir,
                    dist,
                    li,
                    pdf: 0.0,
                })
            }
            LightKind::Quad { .. } | LightKind::Mesh { .. } | LightKind::Disk { .. } => {
                self.flat()?.sample_incident(scene, surfaces, p, (a, b))
            }
            LightKind::Sphere { radius } => {
                let cone = SphereCone::new(self.position, *radius, p)?;
                let (dir, cos) = cone.direction((a, b));
                (cone.solid_angle > 0.0).then_some(Incident {
                    dir,
                    dist: cone.near_side(cos),
                    li: self.color * self.intensity,
                    pdf: 1.0 / cone.solid_angle,
                })
            }
        }
    }

    /// The light of a point, spot or directional light reaching `p`: the direction
    /// toward it, its distance and the irradiance on a surface facing it; `None` for
    /// the other kinds and where it is undefined (`p` at the light).
    #[inline]
    pub fn delta_irradiance(&self, p: Vec3) -> Option<(Vec3, f32, Vec3)> {
        let power = self.color * self.intensity;
        match self.kind {
            LightKind::Point | LightKind::Spot { .. } => {
                let to = self.position - p;
                let dist = to.length();
                if dist <= 0.0 || !dist.is_finite() {
                    return None;
                }
                let dir = to / dist;
                let mut e = power;
                match self.falloff {
                    Falloff::None => {}
                    Falloff::InverseSquare => e /= dist * dist,
                    range @ Falloff::Range { .. } => e *= range.at(dist),
                }
                if let LightKind::Spot {
                    direction,
                    cos_inner,
                    cos_outer,
                    edge,
                } = self.kind
                {
                    let cos = (-dir).dot(direction.normalize_or_zero());
                    e *= edge.at(cos_outer, cos_inner, cos);
                }
                Some((dir, dist, e))
            }
            LightKind::Directional { direction } => {
                let dir = -direction.normalize_or_zero();
                (dir != Vec3::ZERO).then_some((dir, f32::INFINITY, power))
            }
            _ => None,
        }
    }

    /// The emitting area of a flat light (quad, disk, emissive mesh), in squared world
    /// units; zero for the other kinds.
    #[inline]
    pub fn flat_area(&self) -> f32 {
        match &self.kind {
            LightKind::Quad { u, v } => cross(*u, *v).length(),
            LightKind::Disk { radius, .. } => std::f32::consts::PI * radius * radius,
            LightKind::Mesh { area, .. } => *area,
            _ => 0.0,
        }
    }

    /// The light made ready to draw points from if it is flat (quad, disk, emissive
    /// mesh): what all its points share, worked out once.
    #[inline]
    pub fn flat(&self) -> Option<FlatEmitter<'_>> {
        let (normal, t1, t2) = match &self.kind {
            LightKind::Quad { u, v } => {
                let normal = cross(*u, *v);
                (normal / normal.length(), Vec3::ZERO, Vec3::ZERO)
            }
            LightKind::Disk { normal, .. } => {
                let normal = normal.normalize_or(Vec3::Y);
                let (t1, t2) = normal.any_orthonormal_pair();
                (normal, t1, t2)
            }
            LightKind::Mesh { .. } => (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO),
            _ => return None,
        };
        Some(FlatEmitter {
            light: self,
            area: self.flat_area(),
            normal,
            t1,
            t2,
        })
    }

    /// Triangle `shape` of a mesh light; `None` if the shape is not a triangle.
    #[inline]
    pub fn mesh_triangle(
        &self,
        scene: &Scene,
        surfaces: &[Surface],
        shape: ShapeId,
    ) -> Option<MeshTriangle> {
        let Shape::Triangle(tri) = scene.shape_at(shape) else {
            return None;
        };
        Some(MeshTriangle {
            v: tri.v,
            normal: tri.normal(),
            le: surfaces[scene.material_index(shape) as usize].emission * self.intensity,
        })
    }

    /// The density per unit solid angle with which [`Light::sample_incident`] from `p`
    /// draws the direction toward point `y` of the light, whose surface normal there
    /// is `normal`; zero for lights of one direction.
    pub fn pdf_incident(&self, p: Vec3, y: Vec3, normal: Vec3) -> f32 {
        let area = match &self.kind {
            LightKind::Point | LightKind::Spot { .. } | LightKind::Directional { .. } => {
                return 0.0;
            }
            LightKind::Sphere { radius } => {
                return SphereCone::new(self.position, *radius, p)
                    .filter(|c| c.solid_angle > 0.0)
                    .map_or(0.0, |c| 1.0 / c.solid_angle);
            }
            LightKind::Quad { .. } | LightKind::Disk { .. } | LightKind::Mesh { .. } => {
                self.flat_area()
            }
        };
        let to = y - p;
        let d2 = to.length_squared();
        let cos_l = normal.dot(to).abs() / d2.sqrt();
        let pdf = d2 / (cos_l * area);
        if pdf.is_finite() { pdf } else { 0.0 }
    }

    /// Where `ray` meets the emitting side of a light that is not geometry (quad,
    /// disk, sphere) before `t_max`: the distance and the light's normal there.
    /// Mesh lights are the scene's own triangles, and the other kinds have no extent.
    pub fn hit(&self, ray: &Ray, t_max: f32) -> Option<(f32, Vec3)> {
        let (t, normal) = match &self.kind {
            LightKind::Quad { .. } | LightKind::Disk { .. } => return self.flat()?.hit(ray, t_max),
            LightKind::Sphere { radius } => {
                let oc = ray.origin - self.position;
                let b = oc.dot(ray.dir);
                let c = oc.length_squared() - radius * radius;
                // From inside, the sphere lights nothing (it emits outward).
                if c <= 0.0 {
                    return None;
                }
                let disc = b * b - c;
                if disc < 0.0 {
                    return None;
                }
                let t = -b - disc.sqrt();
                if !(t > 0.0 && t < t_max) {
                    return None;
                }
                (t, normalize(ray.at(t) - self.position))
            }
            _ => return None,
        };
        (t > 0.0 && t < t_max && t.is_finite()).then_some((t, normal))
    }
}

/// Whether `x / area` rounds to a magnitude above one half, for `area` zero or at least
/// 2^-125, without the division: where `|x| > area / 2`. `area / 2` is exact, and the
/// float next above it is `area / 2 (1 + 2^-23 / m)` for its mantissa `m` in [1, 2),
/// whose quotient `1/2 + 2^-24 / m` is past the midpoint `1/2 + 2^-25` between one
/// half and the float after it, so it rounds up. No float lies where the quotient
/// would round down to one half. NaNs, infinities and a zero area answer as the
/// quotient does.
#[inline(always)]
fn beyond_half(x: f32, area: f32) -> bool {
    x.abs() > 0.5 * area
}

/// Where `ray` meets the plane through `at` with unit `normal` from the side the
/// normal faces.
#[inline]
fn plane_hit(ray: &Ray, at: Vec3, normal: Vec3) -> Option<f32> {
    let facing = ray.dir.dot(normal);
    if facing >= 0.0 {
        return None;
    }
    Some((at - ray.origin).dot(normal) / facing)
}

/// A sample at `y` on a flat emitter of radiance `le`, unit normal `normal` and
/// `area`, chosen uniformly by area, seen from `p`: its solid-angle density is
/// `d^2 / (cos_l area)`. One-sided: nothing from behind.
#[inline]
fn planar_sample(p: Vec3, y: Vec3, normal: Vec3, area: f32, le: Vec3) -> Option<Incident> {
    let seen = Seen::from(p, y, normal)?;
    let pdf = seen.d2 / (seen.cos_l * area);
    (seen.cos_l > 0.0 && pdf.is_finite()).then_some(Incident {
        dir: seen.dir,
        dist: seen.dist,
        li: le,
        pdf,
    })
}

/// A point of a flat emitter as seen from a shading point.
pub struct Seen {
    /// Unit direction from the shading point to it.
    pub dir: Vec3,
    /// Its distance, and that squared.
    pub dist: f32,
    /// See `dist`.
    pub d2: f32,
    /// Cosine between the emitter's normal and the way back to the shading point:
    /// positive where the point sees the emitting side.
    pub cos_l: f32,
}

impl Seen {
    /// Point `y` (emitter normal `normal`) seen from `p`; `None` at `p` itself or too
    /// far for its squared distance.
    #[inline(always)]
    pub fn from(p: Vec3, y: Vec3, normal: Vec3) -> Option<Seen> {
        let to = y - p;
        let d2 = to.length_squared();
        if d2 <= 0.0 || !d2.is_finite() {
            return None;
        }
        let dist = d2.sqrt();
        let dir = to / dist;
        Some(Seen {
            dir,
            dist,
            d2,
            cos_l: -normal.dot(dir),
        })
    }
}

/// The triangle (of `count`) of a mesh light that uniform `a` picks by `cdf`, their
/// cumulative areas, and the square root of `a`'s place within its share: the
/// stratified coordinate reused within the triangle.
#[inline(always)]
pub fn pick_triangle(cdf: &[f32], count: usize, a: f32) -> (usize, f32) {
    let k = cdf.partition_point(|&c| c <= a).min(count - 1);
    let lo = if k == 0 { 0.0 } else { cdf[k - 1] };
    let within = ((a - lo) / (cdf[k] - lo).max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
    (k, within.sqrt())
}

/// The point of triangle `[v0, v1, v2]` at `su` (from [`pick_triangle`]) and `b`: uniform
/// in its area for uniform coordinates.
#[inline(always)]
pub fn triangle_point([v0, v1, v2]: [Vec3; 3], su: f32, b: f32) -> Vec3 {
    v0 * (1.0 - su) + v1 * (su * (1.0 - b)) + v2 * (su * b)
}

/// The cone a sphere light fills seen from a point outside it: its samples' directions
/// are drawn inside it, uniform in solid angle.
pub struct SphereCone {
    /// Squared distance from the point to the centre.
    pub d2: f32,
    /// The squared radius.
    pub r2: f32,
    /// Distance from the point to the centre.
    pub dist_c: f32,
    /// Unit direction to the centre.
    pub axis: Vec3,
    /// A unit vector across the axis.
    pub t1: Vec3,
    /// The unit vector across the axis and `t1`.
    pub t2: Vec3,
    /// Cosine of the cone's half-angle.
    pub cos_max: f32,
    /// The solid angle the sphere subtends.
    pub solid_angle: f32,
}

impl SphereCone {
    /// The cone of the sphere at `center` of `radius` seen from `p`; `None` from inside.
    #[inline]
    pub fn new(center: Vec3, radius: f32, p: Vec3) -> Option<SphereCone> {
        let to = center - p;
        let d2 = to.length_squared();
        let r2 = radius * radius;
        if d2 <= r2 {
            return None;
        }
        let dist_c = d2.sqrt();
        let axis = to / dist_c;
        let cos_max = (1.0 - r2 / d2).max(0.0).sqrt();
        let (t1, t2) = axis.any_orthonormal_pair();
        Some(SphereCone {
            d2,
            r2,
            dist_c,
            axis,
            t1,
            t2,
            cos_max,
            solid_angle: std::f32::consts::TAU * (1.0 - cos_max),
        })
    }

    /// A direction inside the cone drawn with `(a, b)` uniform in the unit square,
    /// uniform in solid angle, and its cosine to the axis.
    #[inline(always)]
    pub fn direction(&self, (a, b): (f32, f32)) -> (Vec3, f32) {
        let cos = self.cos_of(a);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let (sp, cp) = sin_cos(b * std::f32::consts::TAU);
        let dir = normalize(self.axis * cos + self.t1 * (sin * cp) + self.t2 * (sin * sp));
        (dir, cos)
    }

    /// The cosine to the axis of a direction drawn with uniform `a` in [0, 1).
    #[inline(always)]
    pub fn cos_of(&self, a: f32) -> f32 {
        1.0 - a * (1.0 - self.cos_max)
    }

    /// Distance to the near side of the sphere along a direction at cosine `cos` to the
    /// axis.
    #[inline(always)]
    pub fn near_side(&self, cos: f32) -> f32 {
        let along = self.dist_c * cos;
        along - (self.r2 - (self.d2 - along * along)).max(0.0).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::beyond_half;
    use rand_core::Rng;

    /// For areas from 2^-100 to 2^100 and the special ones, every float within 300
    /// steps of plus and minus half the area (where rounding decides, the float next
    /// above half the area among them), and numbers far from it, answered as
    /// `|x / area| > 1/2` answers.
    #[test]
    fn beyond_half_answers_as_the_quotient_does() {
        let mut rng = rand_pcg::Pcg32::new(0xa4ea, 5);
        let mut next = move || rng.next_u64();
        let mut areas = vec![
            0.0,
            1.0,
            3.0,
            0.1,
            12.345,
            f32::MAX,
            f32::INFINITY,
            f32::NAN,
        ];
        for _ in 0..2000 {
            let bits = next();
            let exponent = (bits % 201) as i32 - 100;
            let mantissa = 1.0 + ((bits >> 8) % (1 << 23)) as f32 / (1 << 23) as f32;
            areas.push(mantissa * 2f32.powi(exponent));
        }
        let specials = [
            0.0,
            -0.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            1e-30,
            1e30,
        ];
        let (mut beyond, mut within) = (0, 0);
        for &area in &areas {
            let half = (0.5 * area).abs();
            let near = (-300i32..=300).filter_map(|k| {
                let bits = half.to_bits().checked_add_signed(k)?;
                Some(f32::from_bits(bits))
            });
            let far = (0..20).map(|_| f32::from_bits(next() as u32));
            for x in near.chain(far).chain(specials) {
                for x in [x, -x] {
                    let expected = (x / area).abs() > 0.5;
                    assert_eq!(beyond_half(x, area), expected, "x {x:e}, area {area:e}");
                    if expected {
                        beyond += 1;
                    } else {
                        within += 1;
                    }
                }
            }
        }
        assert!(
            beyond > 100_000 && within > 100_000,
            "{beyond} beyond, {within} within"
        );
    }
}
