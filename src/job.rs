//! The one job: what a front end was told (a scene file, maybe a camera file or a
//! look-at, option overrides), resolved once into everything a render is — the scene,
//! the camera, the render settings, and how the image is developed and written. The
//! CLI, Python, the cluster runner and animations all go through here, so a scene
//! renders, develops and writes the same whichever way it is asked for.
//!
//! Precedence, highest first: the caller's options, the scene file's `[render]` and
//! `[camera]`, the camera file, then defaults (for a model with no camera: a
//! three-quarter view of its bounds with a key and a fill light).

use crate::accel::AccelKind;
use crate::error::{Error, Result};
use crate::film::{ExrPrecision, Image, OutputOptions, PngBits};
use crate::format::{self, SceneDialect, SceneFile};
use crate::math::Vec3;
use crate::options::{Aov, IntegratorKind, Region, RenderOptions};
use crate::render::{Observer, RenderSettings, RenderStats, Renderer};
use crate::scene::framing::{self, DEFAULT_SIZE};
use crate::scene::{Camera, Scene};
use std::path::{Path, PathBuf};

/// A look-at camera given on the command line (or from Python).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LookAt {
    /// The eye; `None` keeps the camera's.
    pub from: Option<Vec3>,
    /// The point looked at; `None` keeps the camera's direction.
    pub at: Option<Vec3>,
    /// The image's vertical; `None` keeps the camera's, else the scene's up axis.
    pub up: Option<Vec3>,
    /// Horizontal field of view in degrees; `None` keeps the camera's.
    pub fov: Option<f32>,
}

impl LookAt {
    /// Whether nothing is given (the camera stays as it is).
    pub fn is_empty(&self) -> bool {
        *self == LookAt::default()
    }
}

/// Everything a caller may say about a job. `None` defers to the file.
#[derive(Clone, Debug, Default)]
pub struct JobOptions {
    /// Render and development settings, over the scene file's `[render]`.
    pub render: RenderOptions,
    /// Read the scene as this dialect, whatever its extension.
    pub dialect: Option<SceneDialect>,
    /// A 2014 `.cmr` camera, over the scene file's own.
    pub camera_file: Option<PathBuf>,
    /// The file's camera of this name (glTF camera nodes), instead of its first.
    pub camera_name: Option<String>,
    /// The file's camera at this place among its cameras, from 0.
    pub camera_index: Option<usize>,
    /// A look-at over the camera.
    pub look: LookAt,
    /// Render only this window of the full frame.
    pub region: Option<Region>,
    /// Worker threads; `None`: every core. The image does not depend on it.
    pub threads: Option<usize>,
    /// The intersector (every one gives the same image); `None`: the BVH, with its
    /// leaves' triangles copied for the path model where the scene is small enough
    /// ([`COPIED_LEAVES_UP_TO`]).
    pub accel: Option<AccelKind>,
    /// Memory budget in bytes (`--max-memory`); `None`: half the machine's memory.
    pub max_memory: Option<u64>,
    /// Smooth vertex normals for the triangles that have none (`--smooth`).
    pub smooth: bool,
    /// The scene's vertical for the default view and look-at (`--up-axis z` for
    /// Blender's +z up exports); `None`: the dialect's (+y, +z for the 2014 files).
    pub up_axis: Option<Vec3>,
    /// Bits per channel of a PNG.
    pub png_bits: PngBits,
    /// Sample type of an OpenEXR file.
    pub exr_precision: ExrPrecision,
    /// An environment image to light the scene with, in place of its background.
    pub environment: Option<EnvironmentMap>,
    /// A MaterialX document whose (first) material every shape wears (`--material`).
    pub material: Option<PathBuf>,
}

/// An equirectangular image that lights the scene from every direction
/// (`--environment`): its centre looks along -z, turned about the scene's vertical.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    /// The image: `.hdr` and `.exr` are read as linear radiance, others as sRGB.
    pub file: PathBuf,
    /// Turn about the vertical, in degrees (positive: counter-clockwise seen from above).
    pub rotate: f32,
    /// Factor on the image's radiance.
    pub strength: f32,
}

impl EnvironmentMap {
    /// The image `file` unturned at strength 1.
    pub fn new(file: PathBuf) -> EnvironmentMap {
        EnvironmentMap {
            file,
            rotate: 0.0,
            strength: 1.0,
        }
    }
}

/// Dresses every shape of `scene` in the first material of the MaterialX document
/// `path`; emissive meshes stop being lights. Returns the document's warnings.
fn wear(scene: &mut Scene, path: &Path) -> Result<Vec<String>> {
    let bytes = crate::util::file::read_regular(path, 1 << 24)
        .map_err(|e| Error::file(path, format!("cannot read: {e}")))?;
    if !format::materialx::is_materialx(&bytes) {
        return Err(Error::file(
            path,
            "expected a MaterialX document (XML) for --material",
        ));
    }
    let m = format::materialx::load(path, None)?;
    let base = scene.images.len() as u32;
    scene.images.extend(m.images);
    let mut surface = m.surface;
    for slot in surface.image_slots_mut() {
        slot.image += base;
    }
    scene.materials = vec![m.material];
    scene.surfaces = vec![surface];
    scene.material_of.iter_mut().for_each(|k| *k = 0);
    scene
        .lights
        .retain(|l| !matches!(l.kind, crate::scene::LightKind::Mesh { .. }));
    Ok(m.warnings)
}

/// Sets `scene`'s background to the environment `env`, about the vertical `up`.
fn light_with(scene: &mut Scene, env: &EnvironmentMap, up: Vec3) -> Result<()> {
    if !(env.strength.is_finite() && env.strength >= 0.0 && env.rotate.is_finite()) {
        return Err(Error::Settings(format!(
            "expected an environment strength >= 0 and a finite rotation, found {} and {}",
            env.strength, env.rotate
        )));
    }
    let linear = env
        .file
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("hdr") || e.eq_ignore_ascii_case("exr"));
    let encoding = if linear {
        format::image_file::Encoding::Linear
    } else {
        format::image_file::Encoding::Srgb
    };
    let image = format::image_file::read_texture(&env.file, encoding)
        .map_err(|e| Error::Settings(format!("{}: {e}", env.file.display())))?;
    let up = crate::math::normalize(up);
    // -z made perpendicular to `up` (+x where up is along z), then turned about it.
    let mut forward = Vec3::NEG_Z - up * up.dot(Vec3::NEG_Z);
    if forward.length_squared() < 1e-6 {
        forward = Vec3::X - up * up.x;
    }
    let forward = crate::math::normalize(forward);
    let side = crate::math::cross(up, forward);
    let (sin, cos) = crate::math::sin_cos(env.rotate.to_radians());
    scene.images.push(image);
    scene.background = crate::scene::Background::Environment {
        image: (scene.images.len() - 1) as u32,
        up,
        forward: crate::math::normalize(forward * cos + side * sin),
        intensity: env.strength,
    };
    Ok(())
}

/// Lights a model that brings no light: the default studio around `camera`, which
/// lights the path model, and for the models that gather light from lights alone the
/// key and fill where its softboxes are.
fn light_unlit(scene: &mut Scene, camera: &Camera, up: Vec3, integrator: IntegratorKind) {
    framing::add_studio(scene, camera, up);
    if integrator != IntegratorKind::Path {
        framing::add_default_lights(scene, camera);
    }
}

/// A scene ready to render and write: the scene (with default lights added if it needed
/// them), the camera, the render settings and the output's development.
#[derive(Clone, Debug)]
pub struct Job {
    /// The scene, lit by default if it had no light of its own.
    pub scene: Scene,
    /// The camera, with the caller's look-at applied.
    pub camera: Camera,
    /// What to render.
    pub settings: RenderSettings,
    /// How the image becomes a file: exposure, tone map, the integrator's transfer
    /// curve, PNG bits, EXR precision.
    pub output: OutputOptions,
    /// The dialect the scene was read as.
    pub dialect: SceneDialect,
    /// What the readers found but did not understand (`file:line: message`).
    pub warnings: Vec<String>,
    /// Whether the image is denoised once rendered ([`Job::denoised`]); a job that asks
    /// is refused by a Prism that cannot ([`crate::film::denoise::check_available`]).
    pub denoise: bool,
}

impl Job {
    /// The renderer of this job (settings checked against the camera).
    pub fn renderer(&self) -> Result<Renderer<'_>> {
        Renderer::new(&self.scene, &self.camera, self.settings.clone())
    }

    /// Renders the job's image (linear values) on the job's threads, denoised when the
    /// job asks.
    pub fn render(&self) -> Result<(Image, RenderStats)> {
        let renderer = self.renderer()?;
        let (image, stats) = renderer.render(&())?;
        Ok((self.denoised(&renderer, image, &[])?, stats))
    }

    /// `image`, a render of this job by `renderer`, denoised when the job asks (with
    /// the albedo and normal passes: those among `passes` that were rendered already,
    /// the others now, [`Renderer::denoise`]); as it is otherwise.
    pub fn denoised(
        &self,
        renderer: &Renderer,
        image: Image,
        passes: &[(Aov, Image)],
    ) -> Result<Image> {
        if self.denoise {
            renderer.denoise(&image, passes)
        } else {
            Ok(image)
        }
    }

    /// The passes that guide the denoiser, rendered by `renderer` (made of this job)
    /// with `accel` (its [`Renderer::build_accel`]) for a job that asks to be
    /// denoised, none for one that does not: for a front end that denoises several
    /// images of one view (sample passes), which do not change them, so they are
    /// rendered once. `observer` may cancel them.
    pub fn denoise_guides(
        &self,
        renderer: &Renderer,
        accel: &crate::accel::Accel,
        observer: &dyn Observer,
    ) -> Result<Vec<(Aov, Image)>> {
        if !self.denoise {
            return Ok(Vec::new());
        }
        const GUIDES: [Aov; 2] = [Aov::Albedo, Aov::Normal];
        let images = renderer.render_aovs_with(accel, &GUIDES, observer)?;
        Ok(GUIDES.into_iter().zip(images).collect())
    }

    /// Writes `image` to `path` as this job develops it, in the format the extension
    /// names.
    pub fn write(&self, image: &Image, path: &Path) -> Result<()> {
        crate::film::write_image(image, path, &self.output)
    }

    /// The job's camera as a look-at: the eye, a point ahead at the distance of the
    /// scene's centre, the image's vertical and the horizontal field of view.
    pub fn look(&self) -> LookAt {
        let c = &self.camera;
        let f = c.frame();
        let centre = self.scene.bounds().center();
        let ahead = (centre - c.eye).dot(f.forward);
        let dist = if ahead.is_finite() && ahead > 1e-3 {
            ahead
        } else {
            1.0
        };
        LookAt {
            from: Some(c.eye),
            at: Some(c.eye + f.forward * dist),
            up: Some(c.up.unwrap_or(-f.down)),
            fov: Some(horizontal_fov(c)),
        }
    }

    /// The job's camera with `look` laid over it, as `--look-from`, `--look-at`, `--up`
    /// and `--fov` lay it (a preview's camera in hand).
    pub fn camera_looking(&self, look: &LookAt) -> Result<Camera> {
        let up = self.camera.up.unwrap_or(Vec3::Y);
        look_at_over(&self.camera, look, up)
    }
}

/// A camera's horizontal field of view in degrees.
fn horizontal_fov(camera: &Camera) -> f32 {
    let half = camera.retina_scale * camera.width as f32 / camera.screen_distance;
    2.0 * half.atan().to_degrees()
}

/// Loads `scene_path` and resolves the job.
pub fn prepare(scene_path: &Path, options: &JobOptions) -> Result<Job> {
    let file = match options.dialect {
        Some(d) => format::load_as(scene_path, d)?,
        None => format::load(scene_path)?,
    };
    resolve(file, options)
}

/// Shapes up to which the path model copies triangles into the BVH's leaves: its rays
/// are incoherent, so a leaf's triangles read in one place pay (1.3x on the Cornell
/// box), and below this the copies cost at most a few hundred megabytes.
pub const COPIED_LEAVES_UP_TO: usize = 4_000_000;

/// Resolves the camera, the settings and the development of a loaded scene file.
pub fn resolve(file: SceneFile, options: &JobOptions) -> Result<Job> {
    let SceneFile {
        dialect,
        mut scene,
        camera: file_camera,
        cameras,
        settings: file_settings,
        warnings,
        ..
    } = file;
    let o = options.render.over(&file_settings);
    // The vertical the files mean: z for the 2014 dialect, y for the rest, unless told.
    let default_up = options.up_axis.unwrap_or(match dialect {
        SceneDialect::Objx2014 => Vec3::Z,
        _ => Vec3::Y,
    });
    if options.smooth {
        crate::scene::mesh::smooth_all(&mut scene);
    }
    if let Some(env) = &options.environment {
        light_with(&mut scene, env, default_up)?;
    }
    let mut warnings = warnings;
    if let Some(material) = &options.material {
        warnings.extend(wear(&mut scene, material)?);
    }
    // The path model is lit by an environment it is given; the whitted model, which
    // gathers light from lights only, keeps the default key and fill beside it.
    let integrator = o.integrator.unwrap_or(dialect.default_integrator());
    let lit_by_environment = options.environment.is_some() && integrator == IntegratorKind::Path;
    let needs_lights =
        |scene: &Scene| scene.lights.is_empty() && !has_emission(scene) && !lit_by_environment;
    let file_camera = match chosen_camera(&cameras, options)? {
        Some(c) => Some(c),
        None => file_camera,
    };
    let mut camera = match (&options.camera_file, file_camera) {
        (Some(path), _) => format::load_camera(path)?,
        (None, Some(c)) => {
            // A model with a camera of its own but no lights (glTF) is lit as one
            // without, from that camera.
            if dialect == SceneDialect::Gltf && needs_lights(&scene) {
                light_unlit(&mut scene, &c, default_up, integrator);
            }
            c
        }
        (None, None) => {
            let (w, h) = default_size(o.width, o.height);
            let up = options.look.up.unwrap_or(default_up);
            let c = framing::three_quarter_view(scene.bounds(), up, w, h);
            if needs_lights(&scene) {
                light_unlit(&mut scene, &c, up, integrator);
            }
            c
        }
    };
    if !options.look.is_empty() {
        camera = look_at_over(&camera, &options.look, default_up)?;
    }
    let settings = RenderSettings {
        width: o.width,
        height: o.height,
        aa: o.aa,
        filter: o.filter.unwrap_or_default(),
        spp: o.spp,
        region: options.region,
        seed: o.seed.unwrap_or(0),
        threads: options.threads,
        accel: options.accel.unwrap_or(match integrator {
            crate::options::IntegratorKind::Path if scene.shapes.len() <= COPIED_LEAVES_UP_TO => {
                AccelKind::BvhCopied
            }
            _ => AccelKind::Bvh,
        }),
        integrator,
        max_depth: o.max_depth.unwrap_or(integrator.default_max_depth()),
        min_weight: o.min_weight.unwrap_or(crate::render::DEFAULT_MIN_WEIGHT),
        light_sampling: o.light_sampling.unwrap_or_default(),
        max_memory: options.max_memory,
    };
    let denoise = o.denoise.unwrap_or(false);
    if denoise {
        // Refused now, before anything is rendered.
        crate::film::denoise::check_available()?;
    }
    let output = OutputOptions {
        develop: crate::film::Develop {
            exposure: o.exposure.unwrap_or(0.0),
            tonemap: o.tonemap.unwrap_or_default(),
            transfer: integrator.transfer(),
        },
        png_bits: options.png_bits,
        exr_precision: options.exr_precision,
    };
    Ok(Job {
        scene,
        camera,
        settings,
        output,
        dialect,
        warnings,
        denoise,
    })
}

/// The camera `--camera-name` or `--camera-index` picks among the file's, if either
/// is given.
fn chosen_camera(cameras: &[format::NamedCamera], options: &JobOptions) -> Result<Option<Camera>> {
    let listed = || {
        if cameras.is_empty() {
            "the scene has no cameras".to_string()
        } else {
            let names: Vec<String> = cameras
                .iter()
                .enumerate()
                .map(|(i, c)| match &c.name {
                    Some(n) => format!("{i}: {}", crate::util::text::shown(n)),
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
                    crate::util::text::shown(name),
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
        None => horizontal_fov(camera),
    };
    let mut c = Camera::look_at(from, at, up, fov, camera.width, camera.height);
    c.aa = camera.aa;
    c.spp = camera.spp;
    c.medium_ior = camera.medium_ior;
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::options::{IntegratorKind, RenderOptions, ToneMap};
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
            settings: RenderOptions::default(),
            warnings: vec![],
            counts: Default::default(),
        }
    }

    #[test]
    fn a_model_without_camera_gets_the_default_view_and_lights() {
        let still = resolve(
            ball_file(SceneDialect::WavefrontObj),
            &JobOptions::default(),
        )
        .unwrap();
        assert_eq!((still.camera.width, still.camera.height), DEFAULT_SIZE);
        assert_eq!(still.camera.up, Some(Vec3::Y));
        assert_eq!(still.scene.lights.len(), 2);
        assert_eq!(still.settings.integrator, IntegratorKind::Whitted);
        // --width alone keeps 16:9.
        let o = JobOptions {
            render: crate::options::RenderOptions {
                width: Some(320),
                ..Default::default()
            },
            ..JobOptions::default()
        };
        let still = resolve(ball_file(SceneDialect::WavefrontObj), &o).unwrap();
        assert_eq!((still.camera.width, still.camera.height), (320, 180));
    }

    #[test]
    fn an_environment_lights_the_scene_turned_about_the_vertical() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("sky.png");
        image::RgbImage::from_pixel(8, 4, image::Rgb([255, 128, 0]))
            .save(&file)
            .unwrap();
        let path = |rotate: f32, strength: f32| JobOptions {
            render: crate::options::RenderOptions {
                integrator: Some(IntegratorKind::Path),
                ..Default::default()
            },
            environment: Some(EnvironmentMap {
                file: file.clone(),
                rotate,
                strength,
            }),
            ..JobOptions::default()
        };
        let job = resolve(ball_file(SceneDialect::WavefrontObj), &path(90.0, 2.0)).unwrap();
        let crate::scene::Background::Environment {
            image,
            up,
            forward,
            intensity,
        } = &job.scene.background
        else {
            panic!("{:?}", job.scene.background);
        };
        assert_eq!((*up, *intensity), (Vec3::Y, 2.0));
        // -z turned a quarter counter-clockwise seen from above is -x.
        assert!(
            (*forward - Vec3::NEG_X).abs().max_element() < 1e-6,
            "{forward}"
        );
        // Read as sRGB: 128 is 0.2158 in linear light.
        let texel = job.scene.images[*image as usize]
            .sample_slot(&crate::scene::TextureSlot::new(*image), [0.5, 0.5]);
        assert!((texel.y - 0.2158605).abs() < 1e-4, "{texel}");
        // The path model is lit by it alone; the whitted model keeps the key and fill.
        assert!(job.scene.lights.is_empty());
        let mut whitted = path(0.0, 1.0);
        whitted.render.integrator = Some(IntegratorKind::Whitted);
        let job = resolve(ball_file(SceneDialect::WavefrontObj), &whitted).unwrap();
        assert_eq!(job.scene.lights.len(), 2);
        // A missing image, a negative strength: errors naming what is wrong.
        let mut missing = path(0.0, 1.0);
        missing.environment.as_mut().unwrap().file = dir.path().join("none.hdr");
        let e = resolve(ball_file(SceneDialect::WavefrontObj), &missing).unwrap_err();
        assert!(e.to_string().contains("none.hdr"), "{e}");
        let e = resolve(ball_file(SceneDialect::WavefrontObj), &path(0.0, -1.0)).unwrap_err();
        assert!(e.to_string().contains("strength"), "{e}");
    }

    #[test]
    fn an_unlit_model_is_shown_in_the_studio_which_alone_lights_the_path_model() {
        let studio = |integrator| {
            let o = JobOptions {
                render: RenderOptions {
                    integrator: Some(integrator),
                    ..RenderOptions::default()
                },
                ..JobOptions::default()
            };
            resolve(ball_file(SceneDialect::WavefrontObj), &o).unwrap()
        };
        let path = studio(IntegratorKind::Path);
        assert!(path.scene.lights.is_empty(), "{:?}", path.scene.lights);
        let crate::scene::Background::Environment { image, .. } = path.scene.background else {
            panic!("{:?}", path.scene.background);
        };
        assert_eq!(path.scene.images[image as usize].name, "the default studio");
        let whitted = studio(IntegratorKind::Whitted);
        assert_eq!(whitted.scene.lights.len(), 2, "the key and the fill");
        assert_eq!(whitted.scene.background, path.scene.background);
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
        let o = JobOptions {
            smooth: true,
            up_axis: Some(Vec3::Z),
            ..JobOptions::default()
        };
        let still = resolve(file.clone(), &o).unwrap();
        assert_eq!(still.camera.up, Some(Vec3::Z));
        // The triangles (shapes 1 and 2) got shared normals; the sphere none.
        assert_eq!(still.scene.meshes.len(), 1);
        assert_eq!(
            (still.scene.meshes[0].first_shape, still.scene.meshes[0].len),
            (1, 2)
        );
        let plain = resolve(file, &JobOptions::default()).unwrap();
        assert!(plain.scene.meshes.is_empty());
        assert_eq!(plain.camera.up, Some(Vec3::Y));
    }

    #[test]
    fn options_win_over_the_file_and_the_2014_dialect_stays_classic() {
        let mut file = ball_file(SceneDialect::Objx2014);
        file.settings.seed = Some(5);
        file.settings.max_depth = Some(3);
        let o = JobOptions {
            render: crate::options::RenderOptions {
                seed: Some(9),
                ..Default::default()
            },
            ..JobOptions::default()
        };
        let still = resolve(file, &o).unwrap();
        assert_eq!(still.settings.seed, 9);
        assert_eq!(still.settings.max_depth, 3);
        assert_eq!(still.settings.integrator, IntegratorKind::Classic);
        assert_eq!(still.camera.up, Some(Vec3::Z));
    }

    /// The job carries the development: the integrator's transfer curve, the file's
    /// exposure and tone map unless the caller gives theirs, and the writers' formats.
    #[test]
    fn the_job_develops_as_its_integrator_and_the_layers_say() {
        let whitted = resolve(
            ball_file(SceneDialect::WavefrontObj),
            &JobOptions::default(),
        )
        .unwrap();
        assert_eq!(whitted.output.develop, crate::film::Develop::display());
        let mut file = ball_file(SceneDialect::WavefrontObj);
        file.settings.exposure = Some(-1.0);
        file.settings.tonemap = Some(ToneMap::Reinhard);
        let o = JobOptions {
            render: RenderOptions {
                integrator: Some(IntegratorKind::Classic),
                tonemap: Some(ToneMap::Aces),
                ..Default::default()
            },
            png_bits: PngBits::Sixteen,
            ..JobOptions::default()
        };
        let job = resolve(file, &o).unwrap();
        let d = job.output.develop;
        assert_eq!(
            (d.exposure, d.tonemap, d.transfer),
            (-1.0, ToneMap::Aces, crate::film::Transfer::Classic)
        );
        assert_eq!(job.output.png_bits, PngBits::Sixteen);
        // A classic job writes the 2014 program's values: a grey of 0.5 one stop down
        // is 0.25, stored as 64 (the sRGB curve would make it 137).
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("grey.png");
        let mut plain = job.clone();
        plain.output.develop.tonemap = ToneMap::Clamp;
        plain.output.png_bits = PngBits::Eight;
        plain.write(&Image::new(1, 1, vec![[0.5; 3]]), &p).unwrap();
        let img = image::open(&p).unwrap().to_rgb8();
        assert_eq!(img.get_pixel(0, 0).0, [64; 3]);
    }

    /// Denoising is the caller's to ask for, layered as every option is; a Prism that
    /// cannot denoise refuses the job as it is resolved, before anything renders.
    #[test]
    fn a_job_denoises_only_when_asked_and_only_where_it_can() {
        let plain = resolve(
            ball_file(SceneDialect::WavefrontObj),
            &JobOptions::default(),
        )
        .unwrap();
        assert!(!plain.denoise);
        let asked = JobOptions {
            render: RenderOptions {
                denoise: Some(true),
                ..Default::default()
            },
            ..JobOptions::default()
        };
        let resolved = resolve(ball_file(SceneDialect::WavefrontObj), &asked);
        assert_eq!(resolved.is_ok(), crate::film::denoise::AVAILABLE);
        match resolved {
            Ok(job) => assert!(job.denoise),
            Err(e) => assert!(matches!(e, Error::Denoise(_)), "{e}"),
        }
    }

    #[test]
    fn look_at_options_aim_the_camera() {
        let o = JobOptions {
            look: LookAt {
                from: Some(Vec3::new(0.0, 1.0, 10.0)),
                at: Some(Vec3::new(0.0, 1.0, 0.0)),
                fov: Some(90.0),
                up: None,
            },
            ..JobOptions::default()
        };
        let still = resolve(ball_file(SceneDialect::WavefrontObj), &o).unwrap();
        let f = still.camera.frame();
        assert!((f.forward + Vec3::Z).length() < 1e-6);
        assert!((f.right - Vec3::X).length() < 1e-6);
        let half = still.camera.retina_scale * still.camera.width as f32;
        assert!((half - 1.0).abs() < 1e-5);
        let bad = JobOptions {
            look: LookAt {
                from: Some(Vec3::ONE),
                at: Some(Vec3::ONE),
                ..LookAt::default()
            },
            ..JobOptions::default()
        };
        assert!(resolve(ball_file(SceneDialect::WavefrontObj), &bad).is_err());
    }
}
