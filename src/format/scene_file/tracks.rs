//! `[[track]]` in a scene file: the animation tracks of docs/animation.md, whose targets
//! name the scene file's own things (`object:NAME`, `light:NAME`, `material:NAME`,
//! `camera`). Checked here so a scene with a misspelt target fails when it is read.

use super::raw::RawTrack;
use super::source::Source;
use crate::error::Result;
use toml::Spanned;

pub const MOTIONS: [&str; 4] = ["translate", "rotate", "orbit", "look_at"];

/// The names a track may target.
pub struct Names<'a> {
    pub objects: Vec<&'a str>,
    pub lights: Vec<&'a str>,
    pub materials: Vec<&'a str>,
}

pub fn check(source: &Source, t: &Spanned<RawTrack>, names: &Names) -> Result<()> {
    let raw = t.get_ref();
    let target = raw.target.get_ref().as_str();
    let unknown =
        |why: String| source.error(&raw.target, format!("unknown target \"{target}\": {why}"));
    let known = |list: &[&str]| {
        if list.is_empty() {
            "there are none".to_string()
        } else {
            list.join(", ")
        }
    };
    if target != "camera" {
        let (kind, name) = target.split_once(':').ok_or_else(|| {
            unknown("expected camera, object:NAME, light:NAME or material:NAME".into())
        })?;
        let (list, what) = match kind {
            "object" => (&names.objects, "named objects"),
            "light" => (&names.lights, "named lights"),
            "material" => (&names.materials, "materials"),
            _ => {
                return Err(unknown(
                    "expected camera, object:NAME, light:NAME or material:NAME".into(),
                ));
            }
        };
        if !list.contains(&name) {
            if list.is_empty() {
                return Err(unknown(format!("the scene has no {what}")));
            }
            let mut sorted = list.clone();
            sorted.sort_unstable();
            sorted.truncate(12);
            return Err(unknown(format!("the {what} are: {}", known(&sorted))));
        }
    }
    let motion = raw.motion.get_ref().as_str();
    if !MOTIONS.contains(&motion) {
        return Err(source.error(
            &raw.motion,
            format!("unknown motion \"{motion}\": expected translate, rotate, orbit or look_at"),
        ));
    }
    if motion == "look_at" && target != "camera" {
        return Err(source.error(&raw.motion, "only the camera can look_at"));
    }
    Ok(())
}
