//! Reading input files (scenes, retimings, motions): JSON, or TOML when the extension is
//! `.toml`, strictly (unknown keys are rejected by the types themselves). One reader for the
//! command line, the Python package and the facade's loaders, so that a file means the same
//! everywhere.

use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;

use crate::strict::Strict;

use crate::StanceError;

/// Parses JSON text into `T` as input files are read: named fields only (the array form of a
/// struct is refused at any depth) and nothing after the value. For inputs that do not come
/// from a file (the Python package's dicts).
///
/// ```
/// use stance_contact::FrictionModel;
/// assert!(stance_motion::input::from_json_str::<FrictionModel>(r#"{"sides": 4}"#).is_ok());
/// assert!(stance_motion::input::from_json_str::<FrictionModel>("[4]").is_err());
/// ```
pub fn from_json_str<T: DeserializeOwned>(text: &str) -> Result<T, String> {
    let mut de = serde_json::Deserializer::from_str(text);
    // The key an error is about, from the root (`contacts[0].position`): serde_json's own
    // message gives only a line and column, which in a file written on one line is no help.
    let v = serde_path_to_error::deserialize(Strict(&mut de)).map_err(|e| {
        let inner = e.inner().to_string();
        format!("{}{inner}", key_prefix(e.path(), &inner))
    })?;
    de.end().map_err(|e| e.to_string())?;
    Ok(v)
}

/// "key `contacts[0].position`: " for the key an error is about (empty at the root). An
/// unknown field's message names it: then the path is its parent's.
fn key_prefix(path: &serde_path_to_error::Path, message: &str) -> String {
    let segments: Vec<String> = path.iter().map(|s| s.to_string()).collect();
    let keep = if message.starts_with("unknown field") {
        segments.len().saturating_sub(1)
    } else {
        segments.len()
    };
    let path =
        segments[..keep]
            .iter()
            .filter(|s| s.as_str() != "?")
            .fold(String::new(), |mut p, s| {
                if !(p.is_empty() || s.starts_with('[')) {
                    p.push('.');
                }
                p.push_str(s);
                p
            });
    if path.is_empty() {
        path
    } else {
        format!("key `{path}`: ")
    }
}

/// A TOML error on one line: where (line, column and the line itself, shortened), the key,
/// then the message.
fn toml_message(text: &str, e: &toml::de::Error, key: &str) -> String {
    let place = e
        .span()
        .map(|r| r.start.min(text.len()))
        .filter(|&start| text.is_char_boundary(start))
        .map_or(String::new(), |start| {
            let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
            let line = text[line_start..].lines().next().unwrap_or("").trim();
            format!(
                "line {}, column {} (`{}`): ",
                text[..start].matches('\n').count() + 1,
                text[line_start..start].chars().count() + 1,
                shorten_lines(line)
            )
        });
    format!("{place}{key}{}", e.message().trim())
}

/// Reads a JSON file, or a TOML file when its extension is `.toml`, into `T`.
///
/// ```
/// let dir = std::env::temp_dir().join(format!("stance-input-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let path = dir.join("scene.toml");
/// std::fs::write(&path, "mass = 40\n[[contacts]]\nname = \"LF\"\nposition = [0, 0, 0]\n\
///     friction = 0.7\nshape = { rectangle = { half_length = 0.11, half_width = 0.065 } }\n").unwrap();
/// let scene: stance_contact::Scene = stance_motion::input::read_file(&path).unwrap();
/// assert_eq!(scene.contacts.len(), 1);
/// let err = stance_motion::input::read_file::<stance_contact::Scene>(&dir.join("none.json"));
/// assert!(err.unwrap_err().to_string().contains("cannot read input file"));
/// ```
pub fn read_file<T: DeserializeOwned>(path: &Path) -> Result<T, StanceError> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        StanceError::File(format!("cannot read input file {}: {e}", path.display()))
    })?;
    // A UTF-8 byte-order mark (some editors write one) is not part of the JSON or TOML.
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    if text.trim().is_empty() {
        return Err(StanceError::File(format!(
            "input file {} is empty",
            path.display()
        )));
    }
    let is_toml = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
    if is_toml {
        let bad = |m: String| StanceError::File(format!("invalid TOML in {}: {m}", path.display()));
        let de = toml::Deserializer::parse(text).map_err(|e| bad(toml_message(text, &e, "")))?;
        serde_path_to_error::deserialize(Strict(de)).map_err(|e| {
            let key = key_prefix(e.path(), e.inner().message());
            bad(toml_message(text, e.inner(), &key))
        })
    } else {
        from_json_str(text).map_err(|e| {
            // Every input file is an object of named fields: say so when it is something else.
            let hint = match text.trim_start().chars().next() {
                Some('{') | None => "",
                Some('[') => {
                    " (the file holds a bare array: every input is an object with named \
                              fields, such as {\"generators\": [...]})"
                }
                Some(_) => " (every input is a JSON object with named fields, {...})",
            };
            StanceError::File(format!("invalid JSON in {}: {e}{hint}", path.display()))
        })
    }
}

/// Longest line of an error message quoting its input (a TOML error quotes the offending line,
/// which may be a whole file written on one line).
pub const MAX_QUOTED_LINE: usize = 200;

/// `text` with every line longer than [`MAX_QUOTED_LINE`] characters cut, saying how much was
/// left out.
///
/// ```
/// let long = format!("at line 1\n{}\n^", "[".repeat(100_000));
/// let short = stance_motion::input::shorten_lines(&long);
/// assert!(short.len() < 400 && short.contains("99800 more characters"));
/// ```
pub fn shorten_lines(text: &str) -> String {
    text.lines()
        .map(|l| {
            let n = l.chars().count();
            if n > MAX_QUOTED_LINE {
                let head: String = l.chars().take(MAX_QUOTED_LINE).collect();
                format!("{head}... ({} more characters)", n - MAX_QUOTED_LINE)
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// A scene from a file (JSON or TOML) or a built-in example by name
/// ([`stance_contact::examples::NAMES`]); a path that exists wins over a name.
///
/// ```
/// assert_eq!(stance_motion::input::scene("stairs").unwrap().contacts.len(), 2);
/// assert!(stance_motion::input::scene("moon").unwrap_err().to_string().contains("stairs"));
/// ```
pub fn scene(source: &str) -> Result<stance_contact::Scene, StanceError> {
    let path = Path::new(source);
    if path.is_file() {
        return read_file(path);
    }
    stance_contact::examples::by_name(source).ok_or_else(|| {
        StanceError::unknown_name(source, "scene", &stance_contact::examples::NAMES, true)
    })
}

/// A motion from a file (JSON or TOML; with its folder, against which relative paths in it are
/// resolved) or a built-in motion by name ([`crate::experiments::NAMES`]); a path that
/// exists wins over a name.
///
/// ```
/// let (spec, dir) = stance_motion::input::motion("small-sway").unwrap();
/// assert!(dir.is_none());
/// assert!(stance_motion::input::motion("moonwalk").unwrap_err().to_string().contains("small-sway"));
/// ```
pub fn motion(source: &str) -> Result<(crate::spec::MotionSpec, Option<PathBuf>), StanceError> {
    use crate::experiments;
    let path = Path::new(source);
    if path.is_file() {
        let spec = read_file(path)?;
        return Ok((spec, path.parent().map(Path::to_path_buf)));
    }
    if experiments::NAMES.contains(&source) {
        return Ok((experiments::by_name(source)?, None));
    }
    Err(StanceError::unknown_name(
        source,
        "motion",
        &experiments::NAMES,
        true,
    ))
}
