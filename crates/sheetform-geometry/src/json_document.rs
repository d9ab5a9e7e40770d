//! JSON documents (scenes, annotations) read with errors that name the field: the path
//! from the document's top (`regions[0].curve.type`), what is wrong and what is accepted,
//! then the line and column, so that `"units": "furlong"` is reported at `units` and not
//! only at "line 3, column 19".

use crate::message_text::{quoted_token, shortened_message};
use serde::de::DeserializeOwned;
use serde_path_to_error::Segment;

/// Why a JSON document could not be read: the field and what is wrong with it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JsonFieldError {
    /// JSON path of the field from the document's top (`regions[1].curve.control_points[3]`);
    /// `(document)` when the document as a whole is wrong (not an object, empty).
    pub field: String,
    /// What is wrong and, where serde says, what is accepted; the line and column last,
    /// in parentheses.
    pub message: String,
}

/// The field named for an error in the document as a whole.
pub const WHOLE_DOCUMENT: &str = "(document)";

/// Reads a `T` from JSON `text` (a byte-order mark first is skipped: editors on Windows
/// write one).
///
/// # Errors
/// [`JsonFieldError`] naming the field path of the first problem, with serde's message
/// ("unknown field `colour`, expected one of ...", "missing field `regions`"): for an
/// unknown or a missing field the path ends in that field; for an unknown tag of an
/// internally tagged enum (`{"type": "spline"}`) in the tag's key.
pub fn json_from_text<T: DeserializeOwned>(text: &str) -> Result<T, JsonFieldError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut deserializer = serde_json::Deserializer::from_str(text);
    let value =
        serde_path_to_error::deserialize(&mut deserializer).map_err(|e| field_error(text, e.path(), e.inner()))?;
    // Characters after the document.
    deserializer
        .end()
        .map_err(|e| field_error(text, &serde_path_to_error::Track::new().path(), &e))?;
    Ok(value)
}

fn field_error(text: &str, path: &serde_path_to_error::Path, inner: &serde_json::Error) -> JsonFieldError {
    let (line, column) = (inner.line(), inner.column());
    let mut message = inner.to_string();
    if line > 0 {
        if let Some(stripped) = message.strip_suffix(&format!(" at line {line} column {column}")) {
            message = stripped.to_string();
        }
    }
    let mut segments: Vec<String> = Vec::new();
    let mut keys: Vec<PathKey> = Vec::new();
    for segment in path.iter() {
        match segment {
            Segment::Seq { index } => {
                segments.push(format!("[{index}]"));
                keys.push(PathKey::Index(*index));
            }
            Segment::Map { key } | Segment::Enum { variant: key } => {
                segments.push(format!(".{}", quoted_token(key)));
                keys.push(PathKey::Key(key.clone()));
            }
            Segment::Unknown => {
                segments.push(".?".into());
                keys.push(PathKey::Unknown);
            }
        }
    }
    // serde names the field of an unknown-field or missing-field error in its message
    // (kept as it is: "missing field `regions`"); a missing one at the path of the object
    // that lacks it: the path ends in the field.
    for prefix in ["unknown field `", "missing field `"] {
        if let Some((name, _)) = message.strip_prefix(prefix).and_then(|rest| rest.split_once('`')) {
            if !matches!(keys.last(), Some(PathKey::Key(last)) if last == name) {
                segments.push(format!(".{}", quoted_token(name)));
            }
            break;
        }
    }
    // An internally tagged enum (`{"type": "spline", ...}`) reports an unknown tag at the
    // object: name the key that holds it.
    if let Some(rest) = message.strip_prefix("unknown variant `") {
        if let Some((variant, _)) = rest.split_once('`') {
            if let Ok(document) = serde_json::from_str::<serde_json::Value>(text) {
                if let Some(serde_json::Value::Object(object)) = value_at(&document, &keys) {
                    if let Some((tag, _)) = object.iter().find(|(_, v)| v.as_str() == Some(variant)) {
                        segments.push(format!(".{}", quoted_token(tag)));
                    }
                }
            }
        }
    }
    // Inside an internally tagged enum (`{"type": "bspline", "degree": "three"}`) serde
    // reads the object whole and loses the path at it: a wrong value is found again in
    // the object by what the message says of it, and named when it is the only match.
    if let Ok(document) = serde_json::from_str::<serde_json::Value>(text) {
        if let Some(object @ serde_json::Value::Object(_)) = value_at(&document, &keys) {
            if object.get("type").is_some_and(serde_json::Value::is_string) {
                if let Some(inner) = offending_value_path(object, &message) {
                    segments.push(inner);
                }
            }
        }
    }
    let mut field = segments.concat();
    if let Some(stripped) = field.strip_prefix('.') {
        field = stripped.to_string();
    }
    if field.is_empty() {
        field = WHOLE_DOCUMENT.to_string();
    }
    let mut message = shortened_message(&message);
    if line > 0 {
        message.push_str(&format!(" (line {line}, column {column})"));
    }
    JsonFieldError { field, message }
}

/// The path (`.degree`, `.control_points[1]`) inside `object` of the one value serde's
/// `message` describes: `invalid type: string "three", ...` (a string, integer, floating
/// point or boolean value, found by its value) or `invalid length 2, ...` (an array of
/// that length); `None` when the message names no value or several match.
fn offending_value_path(object: &serde_json::Value, message: &str) -> Option<String> {
    use serde_json::Value;
    let matches: Box<dyn Fn(&Value) -> bool> = if let Some(rest) = message.strip_prefix("invalid length ") {
        let length: usize = rest.split(',').next()?.trim().parse().ok()?;
        Box::new(move |v: &Value| v.as_array().is_some_and(|a| a.len() == length))
    } else {
        let rest = message
            .strip_prefix("invalid type: ")
            .or_else(|| message.strip_prefix("invalid value: "))?;
        let (unexpected, _) = rest.split_once(", expected")?;
        if let Some(text) = unexpected.strip_prefix("string ") {
            let text: String = serde_json::from_str(text).ok()?;
            Box::new(move |v: &Value| v.as_str() == Some(text.as_str()))
        } else if let Some(number) = unexpected
            .strip_prefix("integer `")
            .or_else(|| unexpected.strip_prefix("floating point `"))
        {
            let number: f64 = number.strip_suffix('`')?.parse().ok()?;
            Box::new(move |v: &Value| v.as_f64() == Some(number))
        } else if let Some(flag) = unexpected.strip_prefix("boolean `") {
            let flag: bool = flag.strip_suffix('`')?.parse().ok()?;
            Box::new(move |v: &Value| v.as_bool() == Some(flag))
        } else {
            return None;
        }
    };
    let mut found = Vec::new();
    let mut stack = vec![(String::new(), object)];
    while let Some((path, value)) = stack.pop() {
        if !path.is_empty() && matches(value) {
            found.push(path.clone());
        }
        match value {
            Value::Object(map) => {
                for (key, inner) in map {
                    if key != "type" {
                        stack.push((format!("{path}.{}", quoted_token(key)), inner));
                    }
                }
            }
            Value::Array(items) => {
                for (i, inner) in items.iter().enumerate() {
                    stack.push((format!("{path}[{i}]"), inner));
                }
            }
            _ => {}
        }
    }
    match found.as_slice() {
        [one] => Some(one.clone()),
        _ => None,
    }
}

/// One step of a path into a JSON value.
enum PathKey {
    Index(usize),
    Key(String),
    Unknown,
}

fn value_at<'a>(document: &'a serde_json::Value, keys: &[PathKey]) -> Option<&'a serde_json::Value> {
    let mut value = document;
    for key in keys {
        value = match key {
            PathKey::Index(i) => value.get(*i)?,
            PathKey::Key(k) => value.get(k.as_str())?,
            PathKey::Unknown => return None,
        };
    }
    Some(value)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Scene {
        units: Units,
        regions: Vec<Region>,
    }

    #[derive(Debug, Deserialize)]
    #[serde(rename_all = "snake_case")]
    enum Units {
        Mm,
        Cm,
    }

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Region {
        flat_start: [f64; 2],
        curve: Curve,
    }

    #[derive(Debug, Deserialize)]
    #[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
    #[allow(dead_code)]
    enum Curve {
        Bezier { control_points: Vec<[f64; 3]> },
        Helix { radius: f64 },
    }

    fn error(text: &str) -> JsonFieldError {
        json_from_text::<Scene>(text).unwrap_err()
    }

    const GOOD_REGION: &str = r#"{"flat_start": [0, 0], "curve": {"type": "helix", "radius": 2}}"#;

    /// Issue 35: serde errors named only "(line 3, column 19)"; every kind of error names
    /// the field path, what is accepted, and keeps the line and column after it.
    #[test]
    fn errors_name_the_field_path_and_what_is_accepted() {
        let e = error(&format!(
            "{{\n  \"regions\": [{GOOD_REGION}],\n  \"units\": \"furlong\"\n}}"
        ));
        assert_eq!(e.field, "units");
        assert!(
            e.message
                .starts_with("unknown variant `furlong`, expected `mm` or `cm`")
                && e.message.ends_with("(line 3, column 20)"),
            "{e:?}"
        );
        let e = error(r#"{"units": "mm", "regions": [{"flat_start": [0, 0], "curve": {"type": "spline"}}]}"#);
        assert_eq!(e.field, "regions[0].curve.type");
        assert!(e.message.contains("expected `bezier` or `helix`"), "{e:?}");
        let e = error(&format!(
            r#"{{"units": "mm", "regions": [{GOOD_REGION}, {{"flat_start": [0, "x"]}}]}}"#
        ));
        assert_eq!(e.field, "regions[1].flat_start[1]");
        assert!(
            e.message
                .starts_with("invalid type: string \"x\", expected f64 (line 1"),
            "{e:?}"
        );
        let e = error(r#"{"units": "mm", "regions": [{"flat_start": [0, 0], "bogus": 1}]}"#);
        assert_eq!(e.field, "regions[0].bogus");
        assert!(
            e.message
                .starts_with("unknown field `bogus`, expected `flat_start` or `curve`"),
            "{e:?}"
        );
        let e = error(r#"{"units": "mm", "regions": [{"flat_start": [0, 0]}]}"#);
        assert_eq!(e.field, "regions[0].curve");
        assert!(e.message.starts_with("missing field `curve` (line 1"), "{e:?}");
        let e = error(r#"{"units": "mm"}"#);
        assert_eq!(e.field, "regions");
        // Malformed JSON: the place the reader reached, and the line and column.
        let e = error(&format!("{{\"units\": \"mm\",\n \"regions\": [{GOOD_REGION},]}}"));
        assert_eq!(e.field, "regions");
        assert!(
            e.message.starts_with("trailing comma") && e.message.ends_with("(line 2, column 78)"),
            "{e:?}"
        );
        for (text, problem) in [
            ("[]", "expected struct Scene"),
            ("", "EOF"),
            ("{\"units\": \"mm\", \"regions\": []} x", "trailing characters"),
        ] {
            let e = error(text);
            assert_eq!(e.field, WHOLE_DOCUMENT, "{text}");
            assert!(e.message.contains(problem), "{e:?}");
        }
    }

    /// Issue 35: inside an internally tagged enum serde loses the path at the object; the
    /// wrong value is named when it is the only one the message describes.
    #[test]
    fn a_wrong_value_inside_a_tagged_object_is_named() {
        let region =
            |curve: &str| format!(r#"{{"units": "mm", "regions": [{{"flat_start": [0, 0], "curve": {curve}}}]}}"#);
        let e = error(&region(r#"{"type": "helix", "radius": "two"}"#));
        assert_eq!(e.field, "regions[0].curve.radius", "{e:?}");
        assert!(
            e.message.starts_with("invalid type: string \"two\", expected f64"),
            "{e:?}"
        );
        let e = error(&region(
            r#"{"type": "bezier", "control_points": [[0, 0, 0], [1, 2], [3, 4, 5]]}"#,
        ));
        assert_eq!(e.field, "regions[0].curve.control_points[1]", "{e:?}");
        let e = error(&region(r#"{"type": "helix", "radius": true}"#));
        assert_eq!(e.field, "regions[0].curve.radius", "{e:?}");
        // Two values the message could mean: the object is named, not a guess.
        let e = error(&region(r#"{"type": "bezier", "control_points": [[0, 0], [1, 2]]}"#));
        assert_eq!(e.field, "regions[0].curve", "{e:?}");
    }

    #[test]
    fn a_byte_order_mark_is_skipped_and_long_keys_are_cut() {
        assert!(json_from_text::<Scene>("\u{feff}{\"units\": \"cm\", \"regions\": []}").is_ok());
        let key = "k".repeat(10_000);
        let e = error(&format!("{{\"units\": \"mm\", \"{key}\": 1}}"));
        assert!(e.field.len() < 100 && e.message.len() < 200, "{e:?}");
    }
}
