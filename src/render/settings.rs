//! What a user may override from the camera file, checked before anything is traced.

use crate::accel::AccelKind;
use crate::error::{Error, Result};
use crate::options::{Filter, IntegratorKind, LightSampling, Region};
use crate::scene::Camera;
use crate::util::limits::{
    MAX_AA, MAX_CAMERA_RAYS, MAX_SIDE, MAX_SPP, MAX_THREADS_PER_CORE, max_threads,
};

/// Render options. `None` keeps the camera file's value.
#[derive(Clone, Debug)]
pub struct RenderSettings {
    /// Output width; alone, the height follows the camera's aspect ratio. The
    /// horizontal field of view is kept: the retina scale follows the width.
    pub width: Option<u32>,
    /// Output height; alone, the width follows the camera's aspect ratio.
    pub height: Option<u32>,
    /// Supersampling factor per axis.
    pub aa: Option<u32>,
    /// Filter that shrinks the supersampled frame to the output pixels.
    pub filter: Filter,
    /// Camera rays per pixel (1 = pinhole, more = depth of field).
    pub spp: Option<u32>,
    /// Render only this window of the frame.
    pub region: Option<Region>,
    /// Seed of every random sample (lens, area lights): same seed, same image.
    pub seed: u64,
    /// Worker threads; `None` uses every core.
    pub threads: Option<usize>,
    /// The intersector to build over the scene's shapes.
    pub accel: AccelKind,
    /// The shading model.
    pub integrator: IntegratorKind,
    /// Limits of the whitted model's recursion.
    pub max_depth: u32,
    /// Rays whose weight falls below this, in 0..1, are not traced (whitted model).
    pub min_weight: f32,
    /// The shadow rays a path vertex traces (path model).
    pub light_sampling: LightSampling,
    /// Memory budget in bytes for the render's big allocations; `None` uses
    /// [`super::memory::default_budget`].
    pub max_memory: Option<u64>,
}

impl Default for RenderSettings {
    fn default() -> RenderSettings {
        RenderSettings {
            width: None,
            height: None,
            aa: None,
            filter: Filter::default(),
            spp: None,
            region: None,
            seed: 0,
            threads: None,
            accel: AccelKind::default(),
            integrator: IntegratorKind::default(),
            max_depth: DEFAULT_MAX_DEPTH,
            min_weight: DEFAULT_MIN_WEIGHT,
            light_sampling: LightSampling::default(),
            max_memory: None,
        }
    }
}

pub use crate::options::DEFAULT_MAX_DEPTH;
/// A ray whose contribution can change no 8-bit value is not traced (POV-Ray's
/// `adc_bailout`).
pub const DEFAULT_MIN_WEIGHT: f32 = 1.0 / 255.0;

/// Refuses a thread count of 0 or above [`max_threads`]: to be asked before any
/// thread is started (a pool of 100 000 threads fails only after starting them).
pub fn check_threads(threads: Option<usize>) -> Result<()> {
    if let Some(0) = threads {
        return Err(Error::Settings("thread count must be at least 1".into()));
    }
    if let Some(n) = threads
        && n > max_threads()
    {
        return Err(Error::Settings(format!(
            "thread count must be at most {} ({MAX_THREADS_PER_CORE} per core on this \
             machine), found {n}",
            max_threads()
        )));
    }
    Ok(())
}

/// Settings merged with the camera: everything concrete.
#[derive(Clone, Debug)]
pub(crate) struct Plan {
    pub camera: Camera,
    pub aa: u32,
    pub spp: u32,
    pub region: Region,
    pub filter: Filter,
    pub seed: u64,
    pub threads: Option<usize>,
    pub accel: AccelKind,
    pub integrator: IntegratorKind,
    pub max_depth: u32,
    pub min_weight: f32,
    pub light_sampling: LightSampling,
    pub max_memory: u64,
}

impl RenderSettings {
    pub(crate) fn resolve(&self, camera: &Camera) -> Result<Plan> {
        let (width, height) = match (self.width, self.height) {
            (None, None) => (camera.width, camera.height),
            (Some(w), Some(h)) => (w, h),
            (Some(w), None) => (w, scaled(camera.height, w, camera.width)),
            (None, Some(h)) => (scaled(camera.width, h, camera.height), h),
        };
        for (name, v) in [("width", width), ("height", height)] {
            if v == 0 || v > MAX_SIDE {
                return Err(Error::Settings(format!(
                    "image {name} must be between 1 and {MAX_SIDE}, found {v}"
                )));
            }
        }
        let aa = self.aa.unwrap_or(camera.aa);
        if aa == 0 || aa > MAX_AA {
            return Err(Error::Settings(format!(
                "anti-aliasing factor must be between 1 and {MAX_AA}, found {aa}"
            )));
        }
        let spp = self.spp.unwrap_or(camera.spp);
        if spp == 0 || spp > MAX_SPP {
            return Err(Error::Settings(format!(
                "rays per pixel must be between 1 and {MAX_SPP}, found {spp}"
            )));
        }
        let region = self.region.unwrap_or(Region {
            x: 0,
            y: 0,
            width,
            height,
        });
        let inside = region.width > 0
            && region.height > 0
            && u64::from(region.x) + u64::from(region.width) <= u64::from(width)
            && u64::from(region.y) + u64::from(region.height) <= u64::from(height);
        if !inside {
            return Err(Error::Settings(format!(
                "region {},{},{},{} is empty or leaves the {width}x{height} frame",
                region.x, region.y, region.width, region.height
            )));
        }
        let camera_rays = u64::from(region.width)
            * u64::from(region.height)
            * u64::from(aa * aa)
            * u64::from(spp);
        if camera_rays > MAX_CAMERA_RAYS {
            return Err(Error::Settings(format!(
                "{camera_rays} camera rays ({}x{} pixels, anti-aliasing {aa}, {spp} rays per pixel) exceed the limit of {MAX_CAMERA_RAYS}",
                region.width, region.height
            )));
        }
        check_threads(self.threads)?;
        let depth_limit = self.integrator.max_depth_limit();
        if self.max_depth > depth_limit {
            return Err(Error::Settings(format!(
                "max depth of the {} model must be at most {depth_limit}, found {}",
                self.integrator.name(),
                self.max_depth
            )));
        }
        if !(0.0..=1.0).contains(&self.min_weight) {
            return Err(Error::Settings(format!(
                "min weight must be between 0 and 1, found {}",
                self.min_weight
            )));
        }
        let mut camera = camera.with_resolution(width, height);
        camera.aa = aa;
        camera.spp = spp;
        Ok(Plan {
            camera,
            aa,
            spp,
            region,
            filter: self.filter,
            seed: self.seed,
            threads: self.threads,
            accel: self.accel,
            integrator: self.integrator,
            max_depth: self.max_depth,
            min_weight: self.min_weight,
            light_sampling: self.light_sampling,
            max_memory: self
                .max_memory
                .unwrap_or_else(super::memory::default_budget),
        })
    }
}

/// `a * num / den`, rounded, at least 1.
fn scaled(a: u32, num: u32, den: u32) -> u32 {
    ((u64::from(a) * u64::from(num) + u64::from(den) / 2) / u64::from(den).max(1)).max(1) as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;
    use crate::util::limits::MAX_DEPTH;

    fn camera() -> Camera {
        Camera {
            eye: Vec3::ZERO,
            theta_deg: 90.0,
            phi_deg: 0.0,
            medium_ior: 1.0,
            screen_distance: 15.0,
            width: 3840,
            height: 2160,
            retina_scale: 0.00125,
            focal_length: 900.0,
            aperture: 5.0,
            spp: 128,
            aa: 4,
            up: None,
            projection: crate::scene::Projection::Perspective,
            shift: [0.0, 0.0],
        }
    }

    #[test]
    fn width_alone_keeps_aspect_and_field_of_view() {
        let s = RenderSettings {
            width: Some(960),
            ..Default::default()
        };
        let plan = s.resolve(&camera()).unwrap();
        assert_eq!((plan.camera.width, plan.camera.height), (960, 540));
        assert_eq!(plan.camera.retina_scale, 0.005);
        assert_eq!((plan.aa, plan.spp), (4, 128));
    }

    #[test]
    fn region_is_parsed_and_checked() {
        assert_eq!(
            "1,2,3,4".parse::<Region>(),
            Ok(Region {
                x: 1,
                y: 2,
                width: 3,
                height: 4
            })
        );
        assert!("1,2,3".parse::<Region>().is_err());
        let s = RenderSettings {
            region: Some(Region {
                x: 3800,
                y: 0,
                width: 100,
                height: 10,
            }),
            ..Default::default()
        };
        let e = s.resolve(&camera()).unwrap_err().to_string();
        assert!(e.contains("leaves the 3840x2160 frame"), "{e}");
    }

    #[test]
    fn absurd_requests_are_refused_with_the_numbers() {
        let s = RenderSettings {
            aa: Some(16),
            spp: Some(60000),
            ..Default::default()
        };
        let e = s.resolve(&camera()).unwrap_err().to_string();
        assert!(e.contains("exceed the limit"), "{e}");
        let zero = RenderSettings {
            width: Some(0),
            ..Default::default()
        };
        assert!(
            zero.resolve(&camera())
                .unwrap_err()
                .to_string()
                .contains("width")
        );
        let many = RenderSettings {
            threads: Some(100_000),
            ..Default::default()
        };
        let e = many.resolve(&camera()).unwrap_err().to_string();
        assert!(e.contains("at most") && e.contains("100000"), "{e}");
        let most = RenderSettings {
            threads: Some(max_threads()),
            ..Default::default()
        };
        assert!(most.resolve(&camera()).is_ok());
        let deep = RenderSettings {
            max_depth: MAX_DEPTH + 1,
            ..Default::default()
        };
        assert!(deep.resolve(&camera()).is_err());
    }
}
