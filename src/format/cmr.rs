//! The 2014 camera file (`.cmr`).
//!
//! All non-comment lines are joined and read as exactly 14 numbers, in this order:
//!
//! | # | value | rule |
//! |---|---|---|
//! | 1–3 | eye x y z | finite |
//! | 4–5 | theta, phi (degrees) | finite |
//! | 6 | refractive index of the camera's medium | > 0 |
//! | 7 | screen distance d | > 0 |
//! | 8–9 | image width (columns), height (rows) | positive integers |
//! | 10 | retina scale s | > 0 |
//! | 11 | focal length f | >= 0 |
//! | 12 | aperture a | >= 0 |
//! | 13 | rays per pixel n | positive integer |
//! | 14 | anti-aliasing factor k | positive integer |
//!
//! Line breaks carry no meaning (the seed files put each group on its own line after a
//! comment). Errors point at the line of the offending value.

use std::path::Path;

use super::text::{At, data_lines, last_line, read_text, shown};
use crate::error::Result;
use crate::math::Vec3;
use crate::scene::Camera;

/// Short names of the 14 values, to say which are missing.
const NAMES: [&str; 14] = [
    "eye x",
    "eye y",
    "eye z",
    "theta",
    "phi",
    "ior",
    "distance",
    "width",
    "height",
    "retina scale",
    "focal length",
    "aperture",
    "rays per pixel",
    "anti-aliasing",
];

/// The whole list, as the count error shows it.
const LIST: &str = "eye x y z, theta, phi, ior, distance, width, height, retina scale, \
    focal length, aperture, rays per pixel, anti-aliasing";

/// What each value is, as a message about its content names it.
const DESCRIPTIONS: [&str; 14] = [
    "the eye x coordinate",
    "the eye y coordinate",
    "the eye z coordinate",
    "theta",
    "phi",
    "the refractive index of the camera's medium",
    "the screen distance",
    "the image width",
    "the image height",
    "the retina scale",
    "the focal length",
    "the aperture",
    "the rays per pixel",
    "the anti-aliasing factor",
];

/// Reads a camera file.
pub fn load(path: &Path) -> Result<Camera> {
    parse(&read_text(path)?, path)
}

/// Parses the text of a camera file; `path` is only used in error messages.
pub fn parse(text: &str, path: &Path) -> Result<Camera> {
    // Every value with the line it came from, so errors can point at it.
    let values: Vec<(&str, usize)> = data_lines(text)
        .flat_map(|line| line.tokens.into_iter().map(move |t| (t, line.number)))
        .collect();

    // A word among the numbers (a stray title line) is the error, at its own line:
    // counting past it would blame the end of the file.
    if let Some((i, &(token, line))) = values
        .iter()
        .enumerate()
        .take(NAMES.len() + 1)
        .find(|(_, (t, _))| t.parse::<f64>().is_err())
    {
        let what = DESCRIPTIONS.get(i).copied().unwrap_or("a camera value");
        return Err(At { path, line }.error(format!(
            "expected a number for {what}, found {} (a .cmr file holds {} numbers: {LIST})",
            shown(token),
            NAMES.len()
        )));
    }
    if values.len() < NAMES.len() {
        let at = At {
            path,
            line: last_line(text),
        };
        return Err(at.error(format!(
            "expected {} camera values ({}), found {}: missing {}",
            NAMES.len(),
            LIST,
            values.len(),
            NAMES[values.len()..].join(", ")
        )));
    }
    if let Some(&(token, line)) = values.get(NAMES.len()) {
        let at = At { path, line };
        return Err(at.error(format!(
            "expected {} camera values, found more: {} after the anti-aliasing factor",
            NAMES.len(),
            shown(token)
        )));
    }

    // Each reader checks value `i` with its line number in messages.
    let at = |i: usize| At {
        path,
        line: values[i].1,
    };
    let any = |i: usize| -> Result<f32> { Ok(at(i).number(values[i].0, DESCRIPTIONS[i])? as f32) };
    let above = |i: usize, strict: bool| -> Result<f32> {
        Ok(at(i).number_above(values[i].0, DESCRIPTIONS[i], 0.0, strict)? as f32)
    };
    let count = |i: usize| at(i).positive_integer(values[i].0, DESCRIPTIONS[i]);
    // The image's sides, checked here so the message names this file and line.
    let side = |i: usize| -> Result<u32> {
        let v = count(i)?;
        if v > crate::util::limits::MAX_SIDE {
            return Err(at(i).error(format!(
                "expected {} of at most {}, found {v}",
                DESCRIPTIONS[i],
                crate::util::limits::MAX_SIDE
            )));
        }
        Ok(v)
    };

    Ok(Camera {
        eye: Vec3::new(any(0)?, any(1)?, any(2)?),
        theta_deg: any(3)?,
        phi_deg: any(4)?,
        medium_ior: above(5, true)?,
        screen_distance: above(6, true)?,
        width: side(7)?,
        height: side(8)?,
        retina_scale: above(9, true)?,
        focal_length: above(10, false)?,
        aperture: above(11, false)?,
        spp: count(12)?,
        aa: count(13)?,
        up: None,
        projection: crate::scene::Projection::Perspective,
        shift: [0.0, 0.0],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_oversized_image_is_an_error_naming_the_camera_file() {
        let text = "0 0 0 90 0 1 1 100000 2 0.5 1 0 1 1\n";
        let e = parse(text, Path::new("c.cmr")).unwrap_err().to_string();
        assert!(
            e.starts_with("c.cmr:1: expected the image width of at most 65536, found 100000"),
            "{e}"
        );
    }
    use proptest::prelude::*;

    const SEED0: &str = "#view point\n0 0 50\n#direction of view, angle theta and phi\n90 0\n\
        #default refractiveIndex\n1\n#distance of retina from view point\n15\n\
        #resolution ratio\n3840 2160\n#retina scale\n0.00125\n#focal length of the camera\n900\n\
        #aperture size of the camera\n5\n#number of rays\n128\n#anti-aliasing parameter\n4\n";

    fn parse_str(text: &str) -> Result<Camera> {
        parse(text, Path::new("c.cmr"))
    }

    fn err(text: &str) -> String {
        parse_str(text).unwrap_err().to_string()
    }

    #[test]
    fn reads_every_field_of_the_seed_camera() {
        let c = parse_str(SEED0).unwrap();
        assert_eq!(
            c,
            Camera {
                eye: Vec3::new(0.0, 0.0, 50.0),
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
        );
    }

    #[test]
    fn line_breaks_and_whitespace_do_not_matter() {
        let one_line = "-1.5 2 3\t45 -30 1.33 10 640 480 0.01 0 0 1 1 \r\n";
        let c = parse_str(one_line).unwrap();
        assert_eq!(c.eye, Vec3::new(-1.5, 2.0, 3.0));
        assert_eq!((c.theta_deg, c.phi_deg, c.medium_ior), (45.0, -30.0, 1.33));
        assert_eq!((c.width, c.height, c.spp, c.aa), (640, 480, 1, 1));
        assert_eq!((c.focal_length, c.aperture), (0.0, 0.0));
    }

    #[test]
    fn too_few_values_is_reported_at_the_last_line_with_what_is_missing() {
        let text = "0 0 50\n90 0\n1\n15\n3840 2160\n0.00125\n900\n5\n";
        assert_eq!(
            err(text),
            "c.cmr:8: expected 14 camera values (eye x y z, theta, phi, ior, distance, width, \
             height, retina scale, focal length, aperture, rays per pixel, anti-aliasing), \
             found 12: missing rays per pixel, anti-aliasing"
        );
        assert!(err("").starts_with("c.cmr:1: expected 14 camera values"));
    }

    #[test]
    fn too_many_values_is_reported_at_the_fifteenth() {
        let text = format!("{SEED0}\n# extra\n7 8\n");
        assert_eq!(
            err(&text),
            "c.cmr:23: expected 14 camera values, found more: `7` after the anti-aliasing factor"
        );
    }

    #[test]
    fn a_stray_word_is_reported_at_its_own_line() {
        let text = format!("my camera\n{SEED0}\n");
        let e = err(&text);
        assert!(
            e.starts_with("c.cmr:1: expected a number for the eye x coordinate, found `my`"),
            "{e}"
        );
    }

    /// Replaces value `i` of a valid one-line camera and returns the error.
    fn with_value(i: usize, token: &str) -> String {
        let mut values: Vec<&str> = "0 0 50 90 0 1 15 3840 2160 0.00125 900 5 128 4"
            .split(' ')
            .collect();
        values[i] = token;
        // One value per line so the line number tells which value was blamed.
        err(&values.join("\n"))
    }

    #[test]
    fn each_value_is_validated_at_its_own_line() {
        assert_eq!(
            with_value(7, "12.5"),
            "c.cmr:8: expected a positive integer for the image width, found `12.5`"
        );
        assert!(
            with_value(8, "0")
                .starts_with("c.cmr:9: expected a positive integer for the image height")
        );
        assert!(with_value(12, "-3").starts_with("c.cmr:13: expected a positive integer"));
        assert!(with_value(13, "2.0").starts_with("c.cmr:14: "));
        assert_eq!(
            with_value(6, "0"),
            "c.cmr:7: expected the screen distance > 0, found `0`"
        );
        assert!(with_value(9, "-1").starts_with("c.cmr:10: expected the retina scale > 0"));
        assert!(with_value(5, "0").starts_with("c.cmr:6: expected the refractive index"));
        assert!(with_value(10, "-0.5").starts_with("c.cmr:11: expected the focal length >= 0"));
        assert!(with_value(11, "-5").starts_with("c.cmr:12: expected the aperture >= 0"));
        assert!(
            with_value(0, "nan")
                .starts_with("c.cmr:1: expected a finite number for the eye x coordinate")
        );
        assert!(
            with_value(4, "abc").starts_with("c.cmr:5: expected a number for phi, found `abc`")
        );
        assert!(with_value(3, "1e40").starts_with("c.cmr:4: "));
    }

    proptest! {
        #[test]
        fn arbitrary_text_never_panics(text in "\\PC{0,200}") {
            let _ = parse_str(&text);
        }

        #[test]
        fn arbitrary_number_like_tokens_never_panic(
            tokens in prop::collection::vec(
                prop_oneof![
                    "-?[0-9]{1,12}(\\.[0-9]{0,4})?",
                    "nan|inf|-inf|1e400|1e-400|\\+|-|#x",
                    "\\PC{0,4}",
                ],
                0..18,
            ),
            newline_every in 1usize..5,
        ) {
            let text: String = tokens
                .chunks(newline_every)
                .map(|c| c.join(" "))
                .collect::<Vec<_>>()
                .join("\n");
            let _ = parse_str(&text);
        }
    }
}
