//! One still image, from what a front end was told: a scene file, maybe a camera file
//! or a look-at, and option overrides. The CLI, Python and the cluster runner all go
//! through here, so a scene renders the same whichever way it is asked for.
//!
//! Precedence, highest first: the caller's options, the scene file's `[render]` and
//! `[camera]`, the camera file, then defaults (for a model with no camera: a
//! three-quarter view of its bounds with a key and a fill light).

use crate::film::resample::Filter;
use crate::format::{self, SceneDialect, SceneFile};
use crate::math::Vec3;
use crate::render::{IntegratorKind, Region, RenderSettings};
use crate::scene::framing::{self, DEFAULT_SIZE};
use crate::scene::{Camera, Scene};
use crate::{Error, Result};
use std::path::PathBuf;

/// A look-at camera given on the command line (or from Python).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LookAt {
    pub from: Option<Vec3>,
    pub at: Option<Vec3>,
    pub up: Option<Vec3>,
    pub fov: Option<f32>,
}

impl LookAt {
    pub fn is_empty(&self) -> bool {
        *self == LookAt::default()
    }
}

/// Everything a caller may say about a still. `None` defers to the file.
#[derive(Clone, Debug, Default)]
pub struct StillOptions {
    pub dialect: Option<SceneDialect>,
    /// A 2014 `.cmr` camera, over the scene file's own.
    pub camera_file: Option<PathBuf>,
    /// The file's camera of this name (glTF camera nodes), instead of its first.
    pub camera_name: Option<String>,
    /// The file's camera at this place among its cameras, from 0.
    pub camera_index: Option<usize>,
    pub look: LookAt,
    pub integrator: Option<IntegratorKind>,
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub aa: Option<u32>,
    pub filter: Option<Filter>,
    pub dof_rays: Option<u32>,
    pub region: Option<Region>,
    pub seed: Option<u64>,
    pub threads: Option<usize>,
    pub accel: crate::accel::AccelKind,
    pub max_depth: Option<u32>,
    pub min_weight: Option<f32>,
    /// Memory budget in bytes (`--max-memory`); `None`: half the machine's memory.
    pub max_memory: Option<u64>,
    /// Smooth vertex normals for the triangles that have none (`--smooth`).
    pub smooth: bool,
    /// The scene's vertical for the default view and look-at (`--up-axis z` for
    /// Blender's +z up exports); `None`: the dialect's (+y, +z for the 2014 files).
    pub up_axis: Option<Vec3>,
}

/// A scene ready to render: the scene (with default lights added if it needed them),
/// the camera and the settings.
#[derive(Clone, Debug)]
pub struct Still {
    pub scene: Scene,
    pub camera: Camera,
    pub settings: RenderSettings,
    pub dialect: SceneDialect,
    /// The scene file's exposure and tone map, for the output stage.
    pub exposure: Option<f32>,
    pub tonemap: Option<String>,
    pub warnings: Vec<String>,
}

/// Loads `scene_path` and resolves the camera and settings.
pub fn prepare(scene_path: &std::path::Path, options: &StillOptions) -> Result<Still> {
    let file = match options.dialect {
        Some(d) => format::load_as(scene_path, d)?,
        None => format::load(scene_path)?,
    };
    resolve(file, options)
}

/// Resolves the camera and settings of a loaded scene file.
pub fn resolve(file: SceneFile, options: &StillOptions) -> Result<Still> {
    let SceneFile {
        dialect,
        mut scene,
        camera: file_camera,
        cameras,
        settings: fs,
        warnings,
        ..
    } = file;
    // A side the caller gives replaces the file's size: alone, the other side follows
    // the camera's aspect ratio rather than the file's other side.
    let (width, height) = match (options.width, options.height) {
        (None, None) => (fs.width, fs.height),
        given => given,
    };
    // The vertical the files mean: z for the 2014 dialect, y for the rest, unless told.
    let default_up = options.up_axis.unwrap_or(match dialect {
        SceneDialect::Objx2014 => Vec3::Z,
        _ => Vec3::Y,
    });
    if options.smooth {
        crate::scene::mesh::smooth_all(&mut scene);
    }
    let file_camera = match chosen_camera(&cameras, options)? {
        Some(c) => Some(c),
        None => file_camera,
    };
    let mut camera = match (&options.camera_file, file_camera) {
        (Some(path), _) => format::load_camera(path)?,
        (None, Some(c)) => {
            // A model with a camera of its own but no lights (glTF) is lit as one
            // without: the key and fill, from that camera.
            if dialect == SceneDialect::Gltf && scene.lights.is_empty() && !has_emission(&scene) {
                framing::add_default_lighting(&mut scene, &c);
            }
            c
        }
        (None, None) => {
            let (w, h) = default_size(width, height);
            let up = options.look.up.unwrap_or(default_up);
            let c = framing::three_quarter_view(scene.bounds(), up, w, h);
            if scene.lights.is_empty() && !has_emission(&scene) {
                framing::add_default_lighting(&mut scene, &c);
            }
            c
        }
    };
    if !options.look.is_empty() {
        camera = look_at_over(&camera, &options.look, default_up)?;
    }
    let settings = RenderSettings {
        width,
        height,
        aa: options.aa.or(fs.aa),
        filter: options.filter.or(fs.filter).unwrap_or_default(),
        dof_rays: options.dof_rays.or(fs.spp),
        region: options.region,
        seed: options.seed.or(fs.seed).unwrap_or(0),
        threads: options.threads,
        accel: options.accel,
        integrator: options
            .integrator
            .or(fs.integrator)
            .unwrap_or(dialect.default_integrator()),
        max_depth: options
            .max_depth
            .or(fs.max_depth)
            .unwrap_or(crate::render::DEFAULT_MAX_DEPTH),
        min_weight: options
            .min_weight
            .or(fs.min_weight)
            .unwrap_or(crate::render::DEFAULT_MIN_WEIGHT),
        max_memory: options.max_memory,
    };
    Ok(Still {
        scene,
        camera,
        settings,
        dialect,
        exposure: fs.exposure,
        tonemap: fs.tonemap,
        warnings,
    })
}

/// The camera `--camera-name` or `--camera-index` picks among the file's, if either
/// is given.
fn chosen_camera(
    cameras: &[format::NamedCamera],
    options: &StillOptions,
) -> Result<Option<Camera>> {
    let listed = || {
        if cameras.is_empty() {
            "the scene has no cameras".to_string()
        } else {
            let names: Vec<String> = cameras
                .iter()
                .enumerate()
                .map(|(i, c)| match &c.name {
                    Some(n) => format!("{i}: {}", format::text::shown(n)),
                    None => format!("{i}: (unnamed)"),
                })
                .collect();
            format!("the scene's cameras are {}", names.join(", "))
        }
    };
    match (&options.camera_name, options.camera_index) {
        (Some(_), Some(_)) => Err(Error::Settings(
            "give --camera-name or --camera-index, not both".into(),
        )),
        (Some(name), None) => cameras
            .iter()
            .find(|c| c.name.as_deref() == Some(name.as_str()))
            .map(|c| Some(c.camera.clone()))
            .ok_or_else(|| {
                Error::Settings(format!(
                    "no camera is named {}: {}",
                    format::text::shown(name),
                    listed()
                ))
            }),
        (None, Some(i)) => cameras
            .get(i)
            .map(|c| Some(c.camera.clone()))
            .ok_or_else(|| Error::Settings(format!("no camera has index {i}: {}", listed()))),
        (None, None) => Ok(None),
    }
}

fn default_size(width: Option<u32>, height: Option<u32>) -> (u32, u32) {
    let (dw, dh) = DEFAULT_SIZE;
    match (width, height) {
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (w, ((u64::from(w) * 9 + 8) / 16).max(1) as u32),
        (None, Some(h)) => (((u64::from(h) * 16 + 4) / 9).max(1) as u32, h),
        (None, None) => (dw, dh),
    }
}

fn has_emission(scene: &Scene) -> bool {
    scene
        .surfaces
        .iter()
        .any(|s| s.emission.max_element() > 0.0)
}

/// The camera with the look-at options applied over it: a new position or target
/// keeps the other; the field of view replaces the horizontal one.
fn look_at_over(camera: &Camera, look: &LookAt, default_up: Vec3) -> Result<Camera> {
    let f = camera.frame();
    let from = look.from.unwrap_or(camera.eye);
    let at = look.at.unwrap_or(from + f.forward);
    if (at - from).length_squared() == 0.0 || !(at - from).is_finite() {
        return Err(Error::Settings(
            "--look-from and --look-at must be different finite points".into(),
        ));
    }
    let up = look.up.or(camera.up).unwrap_or(default_up);
    let fov = match look.fov {
        Some(fov) if fov > 0.0 && fov < 180.0 => fov,
        Some(fov) => {
            return Err(Error::Settings(format!(
                "field of view must be between 0 and 180 degrees, found {fov}"
            )));
        }
        None => {
            let half = camera.retina_scale * camera.width as f32 / camera.screen_distance;
            2.0 * half.atan().to_degrees()
        }
    };
    let mut c = Camera::look_at(from, at, up, fov, camera.width, camera.height);
    c.aa = camera.aa;
    c.rays_per_pixel = camera.rays_per_pixel;
    c.medium_ior = camera.medium_ior;
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::FileSettings;
    use crate::scene::{Material, Shape, Sphere};

    fn ball_file(dialect: SceneDialect) -> SceneFile {
        let mut scene = Scene {
            materials: vec![Material::default_white()],
            ..Scene::default()
        };
        scene.push_shape(
            Shape::Sphere(Sphere {
                center: Vec3::new(0.0, 1.0, 0.0),
                radius: 1.0,
            }),
            0,
        );
        SceneFile {
            dialect,
            scene,
            camera: None,
            cameras: Vec::new(),
            settings: FileSettings::default(),
            warnings: vec![],
            counts: Default::default(),
        }
    }

    #[test]
    fn a_model_without_camera_gets_the_default_view_and_lights() {
        let still = resolve(
            ball_file(SceneDialect::WavefrontObj),
            &StillOptions::default(),
        )
        .unwrap();
        assert_eq!((still.camera.width, still.camera.height), DEFAULT_SIZE);
        assert_eq!(still.camera.up, Some(Vec3::Y));
        assert_eq!(still.scene.lights.len(), 2);
        assert_eq!(still.settings.integrator, IntegratorKind::Whitted);
        // --width alone keeps 16:9.
        let o = StillOptions {
            width: Some(320),
            ..StillOptions::default()
        };
        let still = resolve(ball_file(SceneDialect::WavefrontObj), &o).unwrap();
        assert_eq!((still.camera.width, still.camera.height), (320, 180));
    }

    #[test]
    fn smooth_and_up_axis_options_reach_the_scene_and_the_default_view() {
        let mut file = ball_file(SceneDialect::Ply);
        // Two triangles of a fold, without normals.
        file.scene.push_shape(
            Shape::Triangle(crate::scene::Triangle {
                v: [Vec3::ZERO, Vec3::X, Vec3::Y],
            }),
            0,
        );
        file.scene.push_shape(
            Shape::Triangle(crate::scene::Triangle {
                v: [Vec3::ZERO, Vec3::Z, Vec3::X],
            }),
            0,
        );
        let o = StillOptions {
            smooth: true,
            up_axis: Some(Vec3::Z),
            ..StillOptions::default()
        };
        let still = resolve(file.clone(), &o).unwrap();
        assert_eq!(still.camera.up, Some(Vec3::Z));
        // The triangles (shapes 1 and 2) got shared normals; the sphere none.
        assert_eq!(still.scene.meshes.len(), 1);
        assert_eq!(
            (still.scene.meshes[0].first_shape, still.scene.meshes[0].len),
            (1, 2)
        );
        let plain = resolve(file, &StillOptions::default()).unwrap();
        assert!(plain.scene.meshes.is_empty());
        assert_eq!(plain.camera.up, Some(Vec3::Y));
    }

    #[test]
    fn options_win_over_the_file_and_the_2014_dialect_stays_classic() {
        let mut file = ball_file(SceneDialect::Objx2014);
        file.settings.seed = Some(5);
        file.settings.max_depth = Some(3);
        let o = StillOptions {
            seed: Some(9),
            ..StillOptions::default()
        };
        let still = resolve(file, &o).unwrap();
        assert_eq!(still.settings.seed, 9);
        assert_eq!(still.settings.max_depth, 3);
        assert_eq!(still.settings.integrator, IntegratorKind::Classic);
        assert_eq!(still.camera.up, Some(Vec3::Z));
    }

    #[test]
    fn look_at_options_aim_the_camera() {
        let o = StillOptions {
            look: LookAt {
                from: Some(Vec3::new(0.0, 1.0, 10.0)),
                at: Some(Vec3::new(0.0, 1.0, 0.0)),
                fov: Some(90.0),
                up: None,
            },
            ..StillOptions::default()
        };
        let still = resolve(ball_file(SceneDialect::WavefrontObj), &o).unwrap();
        let f = still.camera.frame();
        assert!((f.forward + Vec3::Z).length() < 1e-6);
        assert!((f.right - Vec3::X).length() < 1e-6);
        let half = still.camera.retina_scale * still.camera.width as f32;
        assert!((half - 1.0).abs() < 1e-5);
        let bad = StillOptions {
            look: LookAt {
                from: Some(Vec3::ONE),
                at: Some(Vec3::ONE),
                ..LookAt::default()
            },
            ..StillOptions::default()
        };
        assert!(resolve(ball_file(SceneDialect::WavefrontObj), &bad).is_err());
    }
}
