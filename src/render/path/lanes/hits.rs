//! What the lanes read of the surface at each path's hit: the hits themselves as
//! arrays, a table of what a hit on each flat shape of a small scene needs, and the
//! surface at any other hit, found one path at a time.

use super::super::Path;
use super::{LANES, LaneScene, Lanes, each, lanes_where};
use crate::accel::Hit;
use crate::math::{Ray, Vec3};
use crate::scene::{Albedo, NO_INSTANCE, Scene, Shape, Surface, SurfacePoint};

/// Each lane's closest hit, as arrays: what a hit on a plain flat shape needs is then
/// read for all the lanes at once.
pub(super) struct LaneHits {
    pub(super) t: Lanes,
    /// The shape met, `u32::MAX` where none was.
    pub(super) shape: [u32; LANES],
    instance: [u32; LANES],
}

impl LaneHits {
    pub(super) const NONE: LaneHits = LaneHits {
        t: [0.0; LANES],
        shape: [u32::MAX; LANES],
        instance: [NO_INSTANCE; LANES],
    };

    #[inline(always)]
    pub(super) fn set(&mut self, i: usize, hit: Option<Hit>) {
        let hit = hit.unwrap_or(Hit {
            t: 0.0,
            shape: u32::MAX,
            instance: NO_INSTANCE,
        });
        self.t[i] = hit.t;
        self.shape[i] = hit.shape;
        self.instance[i] = hit.instance;
    }

    /// Lane `i`'s hit, which it has.
    #[inline(always)]
    pub(super) fn get(&self, i: usize) -> Hit {
        Hit {
            t: self.t[i],
            shape: self.shape[i],
            instance: self.instance[i],
        }
    }

    /// The lanes with a hit. A shape's index is below `u32::MAX`: the shapes of a
    /// scene are counted in `u32`.
    #[inline(always)]
    pub(super) fn met(&self) -> u32 {
        lanes_where(|i| self.shape[i] != u32::MAX)
    }

    /// Of `lanes`, those whose hit is on one of the scene's own shapes with a plain row
    /// in `rows`.
    #[inline(always)]
    pub(super) fn plain(&self, lanes: u32, rows: &[FlatHit]) -> u32 {
        let mut bits = 0;
        for i in each(lanes) {
            let row = rows.get(self.shape[i] as usize);
            let plain = self.instance[i] == NO_INSTANCE && row.is_some_and(|row| row.plain);
            bits |= u32::from(plain) << i;
        }
        bits
    }
}

/// What a lane's step needs of the surface at its hit, found one path at a time.
pub(super) struct LaneSurface {
    /// The radiance the surface sends back along the ray, if it glows toward it, and
    /// the density the light's own samples would have drawn the hit with (none on a
    /// camera ray or a surface that is no light).
    pub(super) emitted: Option<(Vec3, Option<f32>)>,
    pub(super) diffuse: Vec3,
    pub(super) p: Vec3,
    /// The normals on the side the path arrives from.
    pub(super) ng: Vec3,
    pub(super) ns: Vec3,
    /// Where the shadow rays leave from.
    pub(super) from: Vec3,
}

/// A flat shape as its hits see it.
#[derive(Clone, Copy)]
pub(super) struct FlatHit {
    /// The unit normal, as [`Scene::flat_point`] finds it.
    pub(super) ng: [f32; 3],
    /// The reflectance `albedo * diffuse` of a surface of one colour that neither
    /// glows nor reads texture coordinates (`plain`); zero for the others, whose hits
    /// ask their surface.
    pub(super) diffuse: [f32; 3],
    pub(super) plain: bool,
}

/// Scenes of at most this many shapes keep their [`FlatHit`]s for the lanes: 28 bytes
/// each.
const FLAT_HITS_UP_TO: usize = 1 << 16;

/// The [`FlatHit`] of each of `scene`'s own shapes, if every one is flat (a triangle or
/// a rectangle, whose normal is the same at every point) and there are at most
/// [`FLAT_HITS_UP_TO`].
pub(super) fn flat_hits(scene: &Scene, surfaces: &[Surface]) -> Vec<FlatHit> {
    let shapes = &scene.shapes;
    if shapes.len() > FLAT_HITS_UP_TO {
        return Vec::new();
    }
    (0..shapes.len())
        .map(|i| {
            let ng = match shapes.get(i) {
                Shape::Triangle(t) => t.normal(),
                Shape::Rectangle(r) => r.normal(),
                Shape::Sphere(_) => return None,
            };
            let s = &surfaces[scene.material_of[i] as usize];
            let plain = match s.albedo {
                Albedo::Color(c) if s.emission == Vec3::ZERO && !s.reads_texture_coords() => {
                    // As a hit finds it: the albedo times the flat point's white.
                    Some(c * Vec3::ONE * s.diffuse)
                }
                _ => None,
            };
            Some(FlatHit {
                ng: ng.to_array(),
                diffuse: plain.unwrap_or(Vec3::ZERO).to_array(),
                plain: plain.is_some(),
            })
        })
        .collect::<Option<Vec<_>>>()
        .unwrap_or_default()
}

impl Path<'_> {
    /// The surface at `hit` for a lane, one path at a time: a hit that is not on a plain
    /// flat shape (a light, a texture, vertex normals or colours, an instance). Kept out
    /// of line, away from the lanes' own loop.
    #[inline(never)]
    pub(super) fn surface_lane(
        &self,
        prepared: &LaneScene,
        ray: &Ray,
        hit: Hit,
        depth: u32,
        last_p: Vec3,
    ) -> LaneSurface {
        let id = hit.id();
        let row = match prepared.flat_hits.get(id.shape as usize) {
            Some(row) if id.is_world() => Some(row),
            _ => None,
        };
        let s = self.surface(id);
        let texture_coords = !prepared.untextured && s.reads_texture_coords();
        let sp = if prepared.flat && !texture_coords {
            match row {
                Some(row) => SurfacePoint::flat(ray.at(hit.t), Vec3::from_array(row.ng)),
                None => self.scene.flat_point(id, ray, hit.t),
            }
        } else {
            self.scene.surface_point(id, ray, hit.t, texture_coords)
        };
        let entering = ray.dir.dot(sp.ng) < 0.0;
        let (g, sn) = if entering {
            (sp.ng, sp.n)
        } else {
            (-sp.ng, -sp.n)
        };
        let emitted = (entering && s.emission != Vec3::ZERO).then(|| {
            let light = self.light_of(id).map(|(_, light)| light);
            let le = s.emission
                * self.scene.map(&s.emission_map, &sp)
                * light.map_or(1.0, |light| light.intensity);
            let pdf = match light {
                Some(light) if depth > 0 => Some(light.pdf_incident(last_p, sp.p, sp.ng)),
                _ => None,
            };
            (le, pdf)
        });
        let albedo = self.scene.albedo(s, &sp, id) * sp.color;
        LaneSurface {
            emitted,
            diffuse: albedo * s.diffuse,
            p: sp.p,
            ng: g,
            ns: sn,
            from: sp.shadow_origin(g),
        }
    }
}
