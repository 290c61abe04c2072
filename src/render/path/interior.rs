//! Light inside a transmissive solid whose medium scatters (`transmission_scatter`:
//! milky glass, murky water, honey): between the solid's surfaces the path flies
//! through the medium ([`Medium::transmission`]) and may scatter on the way, by the
//! phase function, as pbrt-v4's and Mitsuba's volumetric path tracers do inside a
//! dielectric. Which medium a ray crosses is read from the surface it meets from
//! inside, as Beer's absorption is: no stack of media is kept, so solids are taken
//! not to nest.
//!
//! Lights are not sampled from inside: the solid's own surface would stop the shadow
//! ray, so the light a scattered path finds it finds by the phase function's draws.

use super::{Path, PathState};
use crate::math::Ray;
use crate::render::PixelSampler;
use crate::render::bsdf::medium::Medium;
use crate::scene::{ShapeId, Surface};

/// Scatterings inside media after which a path is taken as absorbed: bounds the work
/// of a path in a dense, nearly white medium.
pub const MAX_FLIGHTS: u32 = 1024;

/// The scattering medium inside each surface (by material), or an empty list where
/// none has one.
pub(super) fn interiors(surfaces: &[Surface]) -> Vec<Option<Medium>> {
    let media: Vec<_> = surfaces.iter().map(interior_of).collect();
    if media.iter().any(Option::is_some) {
        media
    } else {
        Vec::new()
    }
}

/// The medium inside a solid of surface `s`: an OpenPBR material that transmits, is
/// not thin-walled, and whose constant `transmission_scatter` is above zero over a
/// `transmission_depth`. (A volume has one colour: a textured colour or scatter gives
/// none, as it gives no Beer absorption.)
fn interior_of(s: &Surface) -> Option<Medium> {
    let m = s.openpbr.as_deref()?;
    let transmits = m.transmission_weight.value > 0.0 || m.transmission_weight.texture.is_some();
    if !transmits
        || m.geometry_thin_walled
        || m.transmission_color.texture.is_some()
        || m.transmission_scatter.texture.is_some()
        || m.transmission_depth.texture.is_some()
    {
        return None;
    }
    Medium::transmission(
        m.transmission_color.value,
        m.transmission_depth.value,
        m.transmission_scatter.value,
        m.transmission_scatter_anisotropy.value,
    )
}

/// How a ray's crossing of a medium ended.
pub(super) enum Crossing {
    /// It reached the surface, the path's throughput weighed for the crossing.
    Reached,
    /// It scattered on the way: the path goes on from there (true) or has ended.
    Scattered(bool),
}

impl Path<'_> {
    /// The scattering medium inside the solid `shape` bounds, if any.
    #[inline]
    pub(super) fn interior(&self, shape: ShapeId) -> Option<&Medium> {
        if self.interiors.is_empty() {
            return None;
        }
        self.interiors
            .get(self.scene.material_index(shape) as usize)?
            .as_ref()
    }

    /// The path's ray crosses `medium` for `t`, to the surface that bounds it: a free
    /// flight drawn, and either the path goes on from where it scattered, in a
    /// direction the phase function draws, or its throughput is weighed for reaching
    /// the surface.
    pub(super) fn cross(
        &self,
        path: &mut PathState,
        medium: &Medium,
        t: f32,
        sampler: &mut PixelSampler,
    ) -> Crossing {
        let (u, v) = (sampler.next_f32(), sampler.next_f32());
        let Some(flight) = medium.flight(path.beta, u, v) else {
            return Crossing::Scattered(false);
        };
        let scattered = flight < t;
        let Some(beta) = medium.weigh(path.beta, if scattered { flight } else { t }, scattered)
        else {
            return Crossing::Scattered(false);
        };
        path.beta = beta;
        if !scattered {
            return Crossing::Reached;
        }
        path.flights += 1;
        if path.flights > MAX_FLIGHTS {
            return Crossing::Scattered(false);
        }
        let dir = medium.scatter(path.ray.dir, sampler.next_2d());
        path.ray = Ray::new(path.ray.at(flight), dir);
        // No light was sampled from here: what the new ray meets counts in full.
        path.last = None;
        Crossing::Scattered(true)
    }
}
