//! The classic shading model: how the 2014 program coloured a ray (SPEC 3.2, 3.3).
//!
//! Every contribution along a camera ray's tree is a (colour, weight) pair added to one
//! accumulator; the pixel is the weighted mean. Surface colour enters only through the
//! ambient term; diffuse and highlights are white, shadows black, and the weights shrink
//! with the ray's intensity, which each reflection or refraction scales by the material's
//! ratio. Light colours are not used.

use super::shadows::{KnownShadows, from_light, trace_ahead};
use super::{Integrator, NO_RAY, PACKET_RAYS, PixelSampler, RayCount, WeightedColor, slot};
use crate::accel::{Accel, Hit};
use crate::math::{Ray, Vec3, highlight_pow, normalize, offset_origin, reflect};
use crate::scene::shape::{Rectangle, SurfaceCoords};
use crate::scene::{Material, Scene, Shape};

/// Rays weaker than this are not traced.
pub const MIN_INTENSITY: f32 = 0.1;
/// Child rays deeper than this are not traced (camera rays have depth 0).
pub const MAX_DEPTH: u32 = 4;
/// Weight of the black of a shadow, per light, relative to the ray's intensity.
pub const SHADOW_WEIGHT: f32 = 3.0;
/// Floor of |N.L| in the highlight weight, which divides by it: a light grazing the
/// surface must not give an infinite weight.
const MIN_COS: f32 = 1e-6;

/// The classic integrator: traces each camera ray's tree as the 2014 program did, adding
/// (colour, weight) pairs whose weighted mean is the pixel.
pub struct Classic<'a> {
    scene: &'a Scene,
    accel: &'a Accel<'a>,
    /// Refractive index of the medium camera rays start in.
    camera_ior: f32,
    /// What every hit on a rectangle would recompute from its corners, for each
    /// shape that is not a triangle (`Shapes::other_index`; `None` for a sphere):
    /// rectangles are few and their hits many (scene0 renders 1.14x faster).
    rectangles: Vec<Option<RectangleFrame>>,
}

/// A rectangle's normal and texture frame, computed once with the very expressions
/// [`Rectangle::normal`] and [`Rectangle::surface_coords`] use, so the same bits.
#[derive(Clone, Copy)]
struct RectangleFrame {
    normal: Vec3,
    origin: Vec3,
    x_axis: Vec3,
    y_axis: Vec3,
    len_x: f32,
    len_y: f32,
}

impl RectangleFrame {
    fn of(r: &Rectangle) -> RectangleFrame {
        let [a, b, _, d] = r.v;
        let (ex, ey) = (b - a, d - a);
        RectangleFrame {
            normal: r.normal(),
            origin: a,
            x_axis: ex.normalize_or_zero(),
            y_axis: ey.normalize_or_zero(),
            len_x: ex.length(),
            len_y: ey.length(),
        }
    }

    #[inline]
    fn coords(&self, p: Vec3) -> SurfaceCoords {
        SurfaceCoords {
            x: (p - self.origin).dot(self.x_axis),
            y: (p - self.origin).dot(self.y_axis),
            x0: 0.0,
            y0: 0.0,
            len_x: self.len_x,
            len_y: self.len_y,
        }
    }
}

/// A ray of the classic model: geometry plus what R3 of the report adds.
#[derive(Clone, Copy, Debug)]
pub struct ClassicRay {
    /// Origin and unit direction.
    pub ray: Ray,
    /// Product of the reflect and refract ratios along the path, 1 for camera rays; it
    /// scales every weight the ray adds, and the ray is dropped below [`MIN_INTENSITY`].
    pub intensity: f32,
    /// Refractive index of the medium the ray travels in.
    pub ior: f32,
}

impl<'a> Classic<'a> {
    /// The integrator for `scene` with intersector `accel` over its shapes; camera rays
    /// start in a medium of index `camera_ior`.
    pub fn new(scene: &'a Scene, accel: &'a Accel<'a>, camera_ior: f32) -> Classic<'a> {
        let rectangles = (scene.shapes.others().iter())
            .map(|shape| match shape {
                Shape::Rectangle(r) => Some(RectangleFrame::of(r)),
                _ => None,
            })
            .collect();
        Classic {
            scene,
            accel,
            camera_ior,
            rectangles,
        }
    }

    /// Adds the contributions of `r` and its children to `acc`.
    pub fn trace(&self, r: ClassicRay, depth: u32, acc: &mut WeightedColor, count: &mut RayCount) {
        if depth > MAX_DEPTH || r.intensity < MIN_INTENSITY {
            return;
        }
        count.rays += 1;
        let hit = self.accel.closest(&r.ray, f32::INFINITY);
        let found = Found {
            hit,
            shadows: KnownShadows::NONE,
        };
        self.shade(r, found, depth, acc, count);
    }

    /// [`Classic::trace`] for a ray whose hit was found ahead.
    fn trace_found(
        &self,
        r: ClassicRay,
        found: Found,
        depth: u32,
        acc: &mut WeightedColor,
        count: &mut RayCount,
    ) {
        if depth > MAX_DEPTH || r.intensity < MIN_INTENSITY {
            return;
        }
        count.rays += 1;
        self.shade(r, found, depth, acc, count);
    }

    /// Adds the contributions of `r`, whose closest hit and shadow answers are
    /// `found`, and its children.
    fn shade(
        &self,
        r: ClassicRay,
        found: Found,
        depth: u32,
        acc: &mut WeightedColor,
        count: &mut RayCount,
    ) {
        let Some(hit) = found.hit else {
            return;
        };
        let p = r.ray.at(hit.t);
        let n = self.normal(hit.shape, p);
        let m = self.scene.material(hit.shape);
        self.shade_surface(&r, hit.shape, p, n, found.shadows, acc, count);
        for child in child_rays(&r, p, n, m).into_iter().flatten() {
            self.trace(child, depth + 1, acc, count);
        }
    }

    /// The terms of `r`'s hit on `shape` at `p` (normal `n`) besides its children:
    /// ambient, diffuse and each light's shadow or highlight.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn shade_surface(
        &self,
        r: &ClassicRay,
        shape: u32,
        p: Vec3,
        n: Vec3,
        shadows: KnownShadows,
        acc: &mut WeightedColor,
        count: &mut RayCount,
    ) {
        let m = self.scene.material(shape);
        let i = r.intensity;
        acc.add(self.surface_color(shape, p), i * m.ambient);
        acc.add(Vec3::ONE, i * m.diffuse);
        let shading = Highlight {
            view_dir: r.ray.dir,
            n,
            specular: m.specular,
            shininess: m.shininess,
        };
        self.add_lights(p, &shading, i, shadows, acc, count);
    }

    /// The point, normal and traced children of camera ray `r`'s hit (the rays
    /// [`Classic::shade`] would go on to at depth 1), or `None` where it hits nothing.
    #[allow(clippy::type_complexity)]
    fn children_of(
        &self,
        r: &ClassicRay,
        hit: Option<Hit>,
    ) -> Option<(Vec3, Vec3, [Option<ClassicRay>; 2])> {
        let hit = hit?;
        let p = r.ray.at(hit.t);
        let n = self.normal(hit.shape, p);
        let m = self.scene.material(hit.shape);
        let rays = child_rays(r, p, n, m);
        Some((
            p,
            n,
            rays.map(|c| c.filter(|c| 1 <= MAX_DEPTH && c.intensity >= MIN_INTENSITY)),
        ))
    }

    /// The rays' hits, given, with their shadow rays toward each light traced ahead
    /// as one packet per light.
    fn found_ahead(&self, rays: &[Ray], hits: &[Option<Hit>]) -> [Found; PACKET_RAYS] {
        let mut shadows = [KnownShadows::NONE; PACKET_RAYS];
        trace_ahead(
            self.accel,
            self.scene.lights.len(),
            &mut shadows[..rays.len()],
            |i, j| {
                let hit = hits[i]?;
                from_light(self.scene.lights[j].position, rays[i].at(hit.t))
            },
            |s| self.blocks(s),
        );
        std::array::from_fn(|i| Found {
            hit: hits.get(i).copied().flatten(),
            shadows: shadows[i],
        })
    }

    /// Shadow (black, weight 3 I) or highlight (white) of each light at `p`.
    fn add_lights(
        &self,
        p: Vec3,
        h: &Highlight,
        i: f32,
        known: KnownShadows,
        acc: &mut WeightedColor,
        count: &mut RayCount,
    ) {
        for (j, light) in self.scene.lights.iter().enumerate() {
            // An answer found ahead means the ray exists (`from_light` gave one), and
            // a blocked one needs nothing else of it.
            let known = known.blocked(j);
            if known == Some(true) {
                count.rays += 1;
                acc.add(Vec3::ZERO, SHADOW_WEIGHT * i);
                continue;
            }
            let Some((shadow, t_max)) = from_light(light.position, p) else {
                continue;
            };
            count.rays += 1;
            let blocked = match known {
                Some(blocked) => blocked,
                None => self
                    .accel
                    .occluded(&shadow, t_max, |s| self.blocks(s.shape)),
            };
            if blocked {
                acc.add(Vec3::ZERO, SHADOW_WEIGHT * i);
                continue;
            }
            let l = shadow.dir;
            let r = reflect(l, h.n);
            let r_dot_v = -r.dot(h.view_dir);
            if r_dot_v >= 0.0 && h.specular != 0.0 {
                let w = h.specular * highlight_pow(r_dot_v, h.shininess)
                    / h.n.dot(l).abs().max(MIN_COS);
                acc.add(Vec3::ONE, i * w);
            }
        }
    }

    #[inline]
    fn rectangle(&self, s: u32) -> Option<&RectangleFrame> {
        self.rectangles[self.scene.shapes.other_index(s as usize)?].as_ref()
    }

    /// [`Shape::normal`] of shape `s` at `p`.
    #[inline]
    fn normal(&self, s: u32, p: Vec3) -> Vec3 {
        match self.rectangle(s) {
            Some(frame) => frame.normal,
            None => self.scene.shapes.get(s as usize).normal(p),
        }
    }

    /// [`Scene::surface_color`] of shape `s` at `p`.
    #[inline]
    fn surface_color(&self, s: u32, p: Vec3) -> Vec3 {
        match self.rectangle(s) {
            Some(frame) => self.scene.surface_color_with(s, || frame.coords(p)),
            None => self.scene.surface_color(s, p),
        }
    }

    /// Whether shape `s` stops light: transparent shapes let it through.
    #[inline]
    fn blocks(&self, s: u32) -> bool {
        !self.scene.material(s).transparent
    }
}

/// A ray's closest hit and the answers of its shadow rays, found ahead in packets.
#[derive(Clone, Copy)]
struct Found {
    hit: Option<Hit>,
    shadows: KnownShadows,
}

/// The reflected and refracted rays of `r`'s hit at `p` (normal `n`, material `m`), in
/// the order they are traced; `None` where the material has no such share.
#[inline]
fn child_rays(r: &ClassicRay, p: Vec3, n: Vec3, m: &Material) -> [Option<ClassicRay>; 2] {
    let (d, i) = (r.ray.dir, r.intensity);
    let reflected = (m.reflect != 0.0).then(|| {
        let dir = reflect(d, n);
        ClassicRay {
            ray: Ray::new(offset_origin(p, n, dir), dir),
            intensity: i * m.reflect,
            ior: r.ior,
        }
    });
    let refracted = (m.refract != 0.0).then(|| match refract(d, n, r.ior, m.ior) {
        Some((dir, ior)) => ClassicRay {
            ray: Ray::new(offset_origin(p, n, dir), dir),
            intensity: i * m.refract,
            ior,
        },
        // Total internal reflection: the refracted share is reflected instead.
        None => {
            let dir = reflect(d, n);
            ClassicRay {
                ray: Ray::new(offset_origin(p, n, dir), dir),
                intensity: i * m.refract,
                ior: r.ior,
            }
        }
    });
    [reflected, refracted]
}

/// What the highlight of a light at a hit depends on besides the light.
struct Highlight {
    view_dir: Vec3,
    n: Vec3,
    specular: f32,
    shininess: f32,
}

/// Refraction across a surface with geometric normal `n` (SPEC 3.3). A ray going along
/// the normal (`d.n > 0`) enters the material, whose index is `material_ior`; against it,
/// it leaves into index 1. Returns the new direction and medium index, or `None` on total
/// internal reflection.
pub fn refract(d: Vec3, n: Vec3, ray_ior: f32, material_ior: f32) -> Option<(Vec3, f32)> {
    let mut cos_i = n.dot(d);
    let (n, target) = if cos_i < 0.0 {
        cos_i = -cos_i;
        (-n, 1.0)
    } else {
        (n, material_ior)
    };
    let eta = target / ray_ior;
    let cos_t2 = 1.0 - (1.0 - cos_i * cos_i) / (eta * eta);
    if cos_t2 < 0.0 {
        return None;
    }
    let dir = d / eta - (cos_i / eta - cos_t2.sqrt()) * n;
    Some((normalize(dir), target))
}

impl Integrator for Classic<'_> {
    /// Shading draws nothing from the sampler: camera rays may be traced ahead.
    fn lens_packets(&self) -> bool {
        true
    }

    /// The hits' shadow rays go toward each light as one packet (they share the light
    /// as origin, and their directions differ little); so do their reflected rays and
    /// their refracted rays, and the shadow rays of those rays' hits.
    fn trace_camera_packet(
        &self,
        rays: &[Ray],
        hits: &[Option<Hit>],
        _samplers: &mut [PixelSampler],
        accs: &mut [WeightedColor],
        count: &mut RayCount,
    ) {
        let n = rays.len();
        let camera_ray = |i: usize| ClassicRay {
            ray: rays[i],
            intensity: 1.0,
            ior: self.camera_ior,
        };
        let found = self.found_ahead(rays, hits);
        let mut at = [(Vec3::ZERO, Vec3::ZERO); PACKET_RAYS];
        let mut kids = [[None; 2]; PACKET_RAYS];
        for i in 0..n {
            if let Some((p, n, rays)) = self.children_of(&camera_ray(i), hits[i]) {
                at[i] = (p, n);
                kids[i] = rays;
            }
        }
        let mut children = [[None; 2]; PACKET_RAYS];
        for k in 0..2 {
            let mut batch = [NO_RAY; PACKET_RAYS];
            let mut owner = [0usize; PACKET_RAYS];
            let mut m = 0;
            for (i, kid) in kids[..n].iter().enumerate() {
                if let Some(child) = kid[k] {
                    batch[m] = child.ray;
                    owner[m] = i;
                    m += 1;
                }
            }
            if m == 0 {
                continue;
            }
            let mut child_hits = [None; PACKET_RAYS];
            self.accel
                .closest_packet(&batch[..m], f32::INFINITY, &mut child_hits[..m]);
            let child_found = self.found_ahead(&batch[..m], &child_hits[..m]);
            for (j, &i) in owner[..m].iter().enumerate() {
                children[i][k] = Some(child_found[j]);
            }
        }
        for i in 0..n {
            // What `trace` does at depth 0, with the closest hit already found.
            count.rays += 1;
            let Some(hit) = found[i].hit else {
                continue;
            };
            let k = slot(accs, i);
            let (p, normal) = at[i];
            let r = camera_ray(i);
            self.shade_surface(
                &r,
                hit.shape,
                p,
                normal,
                found[i].shadows,
                &mut accs[k],
                count,
            );
            for c in 0..2 {
                if let (Some(child), Some(found)) = (kids[i][c], children[i][c]) {
                    self.trace_found(child, found, 1, &mut accs[k], count);
                }
            }
        }
    }

    #[inline]
    fn trace_camera_ray(
        &self,
        ray: Ray,
        _sampler: &mut PixelSampler,
        acc: &mut WeightedColor,
        count: &mut RayCount,
    ) {
        let r = ClassicRay {
            ray,
            intensity: 1.0,
            ior: self.camera_ior,
        };
        self.trace(r, 0, acc, count);
    }
}

#[cfg(test)]
mod tests;
