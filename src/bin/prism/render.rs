//! `prism render`: one still image from a scene (and a camera, when the scene has none
//! of its own and the default view will not do).

use clap::Args;
use prism::accel::AccelKind;
use prism::film::output::check_output_path;
use prism::film::tev::TevStream;
use prism::film::{ExrPrecision, OutputFile, PngBits};
use prism::format::SceneDialect;
use prism::job::{EnvironmentMap, JobOptions, LookAt};
use prism::math::Vec3;
use prism::options::{Filter, IntegratorKind, LightSampling, Region, RenderOptions, ToneMap};
use prism::render::Observer;
use std::path::PathBuf;

#[derive(Args)]
pub struct RenderArgs {
    /// Scene file: .objx (2014), .obj (Wavefront), .ply or .toml (Prism scene); paths
    /// inside it resolve against its folder.
    #[arg(required = true)]
    pub scene: Option<PathBuf>,
    /// [CAMERA] OUTPUT: an optional 2014 camera file (.cmr), then the output image;
    /// the extension picks the format.
    #[arg(required = true, num_args = 1..=2, value_name = "[CAMERA] OUTPUT")]
    pub paths: Vec<PathBuf>,
    #[command(flatten)]
    pub job: JobArgs,
    /// Show the image as it forms in the tev viewer listening at HOST:PORT (tev's
    /// default port is 14158), as well as writing it.
    #[arg(long, value_name = "HOST:PORT")]
    pub display: Option<String>,
    /// Passes written beside the image as layers of its OpenEXR file, for compositing
    /// and denoising: albedo, normal, depth, alpha, background (comma-separated).
    #[arg(long, value_name = "PASSES", value_delimiter = ',', value_parser = names_parser::<prism::options::Aov, 5>(prism::options::Aov::ALL.map(prism::options::Aov::name)))]
    pub aov: Vec<prism::options::Aov>,
    /// Denoise the image (Intel Open Image Denoise, guided by the albedo and normal
    /// passes) before it is developed and written; needs a Prism built with the `oidn`
    /// feature.
    #[arg(long)]
    pub denoise: bool,
    /// No progress bar and no warnings.
    #[arg(long, short)]
    pub quiet: bool,
    /// Print one line of figures: rays traced, seconds, million rays per second.
    #[arg(long)]
    pub stats: bool,
    #[command(flatten)]
    pub limits: crate::ReadLimits,
}

/// How a scene is rendered and developed: the options `prism render` and `prism
/// preview` share, resolved into the library's `JobOptions`.
#[derive(Args)]
pub struct JobArgs {
    /// Camera file (.cmr), over the scene's own camera.
    #[arg(long, value_name = "FILE")]
    pub camera: Option<PathBuf>,
    /// Put the camera here (a right-handed look-at camera).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3)]
    pub look_from: Option<Vec3>,
    /// Aim the camera at this point.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3)]
    pub look_at: Option<Vec3>,
    /// The image's vertical for --look-from/--look-at and the default view (default:
    /// 0,1,0; 0,0,1 for .objx scenes).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3)]
    pub up: Option<Vec3>,
    /// Horizontal field of view in degrees.
    #[arg(long, value_name = "DEGREES")]
    pub fov: Option<f32>,
    /// Shading model (default: classic for .objx, whitted otherwise).
    #[arg(long, value_parser = names_parser::<IntegratorKind, 3>(IntegratorKind::ALL.map(IntegratorKind::name)))]
    pub integrator: Option<IntegratorKind>,
    /// Read the scene file as this dialect, whatever its extension.
    #[arg(long, value_parser = SceneDialect::names())]
    pub dialect: Option<String>,
    /// Smooth vertex normals for meshes that have none (as `smooth = true` in a scene
    /// file).
    #[arg(long)]
    pub smooth: bool,
    /// The scene's up axis for the default view and look-at: y (default) or z (as
    /// Blender's PLY and OBJ exports keep it).
    #[arg(long, value_name = "AXIS", value_parser = ["y", "z"])]
    pub up_axis: Option<String>,
    /// The scene's camera of this name (glTF camera nodes), instead of its first.
    #[arg(long, value_name = "NAME")]
    pub camera_name: Option<String>,
    /// The scene's camera at this place among its cameras, from 0.
    #[arg(long, value_name = "N")]
    pub camera_index: Option<usize>,
    /// Image width in pixels; the field of view is kept (alone, the height follows the
    /// camera's aspect ratio).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels.
    #[arg(long)]
    pub height: Option<u32>,
    /// Render only the window X,Y,W,H of the full frame, written as a W x H image.
    #[arg(long, value_name = "X,Y,W,H")]
    pub region: Option<Region>,
    /// Anti-aliasing: render K times larger per axis and resample down.
    #[arg(long, value_name = "K")]
    pub aa: Option<u32>,
    /// Resampling filter for anti-aliasing (default: area; also --aa-filter).
    #[arg(long, alias = "aa-filter", value_name = "FILTER", value_parser = names_parser::<Filter, 5>(Filter::ALL.map(|f| f.name())))]
    pub filter: Option<Filter>,
    /// Samples (camera rays) per pixel; more than 1 turns on depth of field (also
    /// --dof-rays).
    #[arg(long, alias = "dof-rays", value_name = "N")]
    pub spp: Option<u32>,
    /// Whitted model: deepest reflection/refraction recursion (default 10).
    #[arg(long, value_name = "N")]
    pub max_depth: Option<u32>,
    /// Whitted model: rays whose weight falls below this are not traced (default 1/255).
    #[arg(long, value_name = "W")]
    pub min_weight: Option<f32>,
    /// Path model: shadow rays a vertex traces, toward every light (all), one chosen
    /// by its contribution (one) or one light drawn from a tree over the lights
    /// (tree); default auto: all up to 16 lights, tree above.
    #[arg(long, value_name = "HOW", value_parser = names_parser::<LightSampling, 4>(LightSampling::ALL.map(LightSampling::name)))]
    pub light_sampling: Option<LightSampling>,
    /// Exposure in stops for 8- and 16-bit outputs (+1 doubles the light).
    #[arg(long, value_name = "EV", allow_hyphen_values = true, value_parser = prism::film::develop::parse_exposure)]
    pub exposure: Option<f32>,
    /// Tone map for 8- and 16-bit outputs (default: clamp).
    #[arg(long, value_parser = names_parser::<ToneMap, 3>(ToneMap::ALL.map(ToneMap::name)))]
    pub tonemap: Option<ToneMap>,
    /// Bits per channel of PNG output.
    #[arg(long, value_name = "BITS", default_value = "8", value_parser = ["8", "16"])]
    pub png_bits: String,
    /// Precision of OpenEXR output.
    #[arg(long, default_value = "half", value_parser = ["half", "float"])]
    pub exr_precision: String,
    /// Intersector.
    #[arg(long, value_parser = crate::accel_parser())]
    pub accel: Option<AccelKind>,
    /// Worker threads (default: every core). The image does not depend on it.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Seed of the lens and light samples; the same seed gives the same image.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Memory budget (e.g. 512M, 4G): a render whose estimate is larger is refused
    /// before it starts. Default: half of the machine's memory.
    #[arg(long, value_name = "SIZE", value_parser = crate::parse_memory)]
    pub max_memory: Option<u64>,
    /// Light the scene with this equirectangular image (.hdr, .exr, or an 8-bit
    /// image read as sRGB), seen where rays leave the scene.
    #[arg(long, value_name = "FILE")]
    pub environment: Option<PathBuf>,
    /// Dress every shape in this MaterialX document's (first) OpenPBR material.
    #[arg(long, value_name = "FILE.mtlx")]
    pub material: Option<PathBuf>,
    /// Turn the environment about the scene's vertical by this many degrees.
    #[arg(
        long,
        value_name = "DEGREES",
        allow_hyphen_values = true,
        requires = "environment"
    )]
    pub environment_rotate: Option<f32>,
    /// Factor on the environment's radiance (default 1).
    #[arg(long, value_name = "K", requires = "environment")]
    pub environment_strength: Option<f32>,
}

impl JobArgs {
    /// The job options these flags say, with `camera_file` (a path or `--camera`).
    pub fn options(&self, camera_file: Option<PathBuf>) -> prism::Result<JobOptions> {
        let settings_error = prism::Error::Settings;
        Ok(JobOptions {
            render: RenderOptions {
                width: self.width,
                height: self.height,
                aa: self.aa,
                filter: self.filter,
                spp: self.spp,
                seed: self.seed,
                integrator: self.integrator,
                max_depth: self.max_depth,
                min_weight: self.min_weight,
                light_sampling: self.light_sampling,
                exposure: self.exposure,
                tonemap: self.tonemap,
                denoise: None,
            },
            dialect: self.dialect.as_deref().map(dialect_of),
            camera_file,
            camera_name: self.camera_name.clone(),
            camera_index: self.camera_index,
            look: LookAt {
                from: self.look_from,
                at: self.look_at,
                up: self.up,
                fov: self.fov,
            },
            region: self.region,
            threads: self.threads,
            accel: self.accel,
            max_memory: self.max_memory,
            smooth: self.smooth,
            up_axis: match self.up_axis.as_deref() {
                Some("z") => Some(Vec3::Z),
                Some(_) => Some(Vec3::Y),
                None => None,
            },
            png_bits: self.png_bits.parse::<PngBits>().map_err(settings_error)?,
            exr_precision: self
                .exr_precision
                .parse::<ExrPrecision>()
                .map_err(settings_error)?,
            material: self.material.clone(),
            environment: self.environment.clone().map(|file| EnvironmentMap {
                rotate: self.environment_rotate.unwrap_or(0.0),
                strength: self.environment_strength.unwrap_or(1.0),
                ..EnvironmentMap::new(file)
            }),
        })
    }

    /// A pool of `--threads` threads, checked before any starts; `None`: every core.
    pub fn pool(&self) -> prism::Result<Option<rayon::ThreadPool>> {
        prism::render::check_threads(self.threads)?;
        self.threads
            .map(|n| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .map_err(|e| prism::Error::Settings(format!("cannot start threads: {e}")))
            })
            .transpose()
    }
}

pub fn run(args: &RenderArgs, interrupt: &crate::Interrupt) -> prism::Result<()> {
    let Some(scene_path) = &args.scene else {
        unreachable!("clap requires the scene");
    };
    let (camera_file, output) = match args.paths.as_slice() {
        [output] => (args.job.camera.clone(), output),
        [camera, output] => {
            if args.job.camera.is_some() {
                return Err(prism::Error::Settings(
                    "a camera file is given twice: as a path and with --camera".into(),
                ));
            }
            (Some(camera.clone()), output)
        }
        _ => unreachable!("clap takes one or two paths"),
    };
    args.limits.apply()?;
    // Refuse a bad output path before spending time on the render.
    let format = check_output_path(output)?;
    if !args.aov.is_empty() && format != prism::film::OutputFormat::Exr {
        return Err(prism::Error::Settings(format!(
            "--aov writes its passes as layers of an OpenEXR file: give an .exr output, not {}",
            output.display()
        )));
    }
    let mut options = args.job.options(camera_file)?;
    if args.denoise {
        options.render.denoise = Some(true);
    }
    // Loading (texture images decode in parallel) and development run on the threads
    // the render is given, so `--threads 1` is one thread throughout.
    let pool = args.job.pool()?;
    let job = on_threads(pool.as_ref(), || prism::job::prepare(scene_path, &options))?;
    if !args.quiet {
        for w in &job.warnings {
            eprintln!("warning: {w}");
        }
    }
    let renderer = job.renderer()?;
    let region = renderer.region();
    // A denoised image exists only once the render is whole: its file is written then,
    // not encoded from the rows as they come.
    let file = if job.denoise {
        None
    } else {
        Some(OutputFile::create(
            output,
            region.width,
            region.height,
            &job.output,
        )?)
    };
    let tev = match &args.display {
        Some(address) => {
            let name = output.file_name().map_or_else(
                || output.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            );
            Some(TevStream::connect(
                address,
                &name,
                region.width,
                region.height,
            )?)
        }
        None => None,
    };
    let bar = crate::progress_bar(renderer.rows_to_trace(), args.quiet);
    let watch = Watch {
        bar: &bar,
        file: file.as_ref(),
        tev: tev.as_ref(),
        stop: &interrupt.stop,
    };
    let (image, stats) = renderer.render(&watch)?;
    bar.finish_and_clear();
    if interrupt.stop.load(std::sync::atomic::Ordering::Relaxed) {
        return Err(prism::Error::Interrupted);
    }
    let passes = renderer.render_aovs(&args.aov)?;
    let passes: Vec<_> = args.aov.iter().copied().zip(passes).collect();
    let denoising = std::time::Instant::now();
    let image = job.denoised(&renderer, image, &passes)?;
    let denoised_in = job.denoise.then(|| denoising.elapsed());
    if let Some(tev) = tev {
        if job.denoise {
            // tev showed the noisy image forming: it ends on the one written.
            tev.rows(0, &image.pixels);
        }
        if let Err(why) = tev.finish()
            && !args.quiet
        {
            eprintln!("warning: {why}");
        }
    }
    if passes.is_empty() {
        // Formats written from the finished image develop its rows in parallel.
        on_threads(pool.as_ref(), || match file {
            Some(file) => file.finish(&image),
            None => job.write(&image, output),
        })?;
    } else {
        prism::film::write_exr_with_passes(&image, &passes, output, &job.output)?;
    }
    if !args.quiet {
        eprintln!(
            "{}",
            finished_line(output, region.width, region.height, &stats, denoised_in)
        );
    }
    if args.stats {
        println!(
            "rays {}  seconds {:.3}  Mrays/s {:.2}",
            stats.rays,
            stats.elapsed.as_secs_f64(),
            stats.mrays_per_second()
        );
    }
    Ok(())
}

/// What the command watches of its render: the progress bar, the file (a PNG is
/// encoded as its rows finish, unless the image is to be denoised), tev (`--display`)
/// and Ctrl-C.
struct Watch<'a> {
    bar: &'a indicatif::ProgressBar,
    file: Option<&'a OutputFile>,
    tev: Option<&'a TevStream>,
    stop: &'a std::sync::atomic::AtomicBool,
}

impl Observer for Watch<'_> {
    fn progress(&self, rows: u64) {
        self.bar.inc(rows)
    }
    fn rows(&self, first_row: u32, pixels: &[[f32; 3]]) {
        if let Some(file) = self.file {
            file.rows(first_row, pixels);
        }
        if let Some(tev) = self.tev {
            tev.rows(first_row, pixels);
        }
    }
    fn cancelled(&self) -> bool {
        self.stop.load(std::sync::atomic::Ordering::Relaxed)
    }
}

/// What a finished render prints: the file, its size, the time and the ray rate, and
/// the time denoising took.
fn finished_line(
    output: &std::path::Path,
    width: u32,
    height: u32,
    stats: &prism::render::RenderStats,
    denoised_in: Option<std::time::Duration>,
) -> String {
    let bytes = std::fs::metadata(output).map_or(0, |m| m.len());
    let size = match bytes {
        b if b >= 1 << 20 => format!("{:.1} MB", b as f64 / f64::from(1 << 20)),
        b if b >= 1 << 10 => format!("{:.0} KB", b as f64 / 1024.0),
        b => format!("{b} bytes"),
    };
    let denoised = denoised_in.map_or(String::new(), |t| {
        format!("; denoised in {:.2} s", t.as_secs_f64())
    });
    format!(
        "wrote {} ({width}x{height}, {size}) in {:.2} s: {} rays, {:.2} Mrays/s{denoised}",
        output.display(),
        stats.elapsed.as_secs_f64(),
        stats.rays,
        stats.mrays_per_second()
    )
}

/// Runs `f` on `pool`, or on rayon's global pool (every core) without one.
fn on_threads<T: Send>(pool: Option<&rayon::ThreadPool>, f: impl FnOnce() -> T + Send) -> T {
    match pool {
        Some(pool) => pool.install(f),
        None => f(),
    }
}

fn dialect_of(name: &str) -> SceneDialect {
    SceneDialect::named(name).expect("clap accepts only listed names")
}

/// A parser of one of `names`, into the type they name.
fn names_parser<T, const N: usize>(
    names: [&'static str; N],
) -> impl clap::builder::TypedValueParser<Value = T>
where
    T: std::str::FromStr + Clone + Send + Sync + 'static,
    T::Err: std::fmt::Debug,
{
    use clap::builder::TypedValueParser as _;
    clap::builder::PossibleValuesParser::new(names)
        .map(|name| name.parse().expect("clap accepts only listed names"))
}

/// `X,Y,Z`: three finite numbers.
fn parse_vec3(text: &str) -> Result<Vec3, String> {
    let parts: Vec<f32> = text
        .split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("expected X,Y,Z (three numbers), found `{text}`"))?;
    match parts.as_slice() {
        &[x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => Ok(Vec3::new(x, y, z)),
        _ => Err(format!(
            "expected X,Y,Z (three finite numbers), found `{text}`"
        )),
    }
}
