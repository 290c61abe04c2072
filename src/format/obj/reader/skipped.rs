//! The statements Prism knows and skips, and what each is counted as.

/// Statements Prism knows and skips, counted under their own name; anything else is
/// counted as `unknown`.
const SKIPPED_KEYWORDS: &[&str] = &[
    "l",
    "p",
    "curv",
    "curv2",
    "surf",
    "t",
    "vp",
    "cstype",
    "deg",
    "bmat",
    "step",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
    "mg",
    "bevel",
    "c_interp",
    "d_interp",
    "lod",
    "shadow_obj",
    "trace_obj",
    "ctech",
    "stech",
    "maplib",
    "usemap",
    "call",
    "csh",
    "vw",
];

/// What a statement Prism does not read is counted as.
pub(super) fn skipped_kind(keyword: &[u8]) -> &'static str {
    std::str::from_utf8(keyword)
        .ok()
        .and_then(|k| SKIPPED_KEYWORDS.iter().find(|&&known| known == k))
        .copied()
        .unwrap_or("unknown")
}
