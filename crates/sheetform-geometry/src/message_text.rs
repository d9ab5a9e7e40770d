//! Numbers and tokens as they appear in messages for people (short, whatever the input),
//! and user text (names, labels) as it goes into XML files.

use std::fmt;

/// A number in at most six significant digits: `12.5`, `0.001`, `3.2e-7`, `1e300`,
/// `NaN`, `inf` (Rust's `{}` prints `1e300` as 301 digits).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShortNumber(pub f64);

impl fmt::Display for ShortNumber {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&significant(self.0, SHORT_DIGITS))
    }
}

/// Significant digits of a [`ShortNumber`].
const SHORT_DIGITS: usize = 6;

/// `x` in at most `digits` significant digits, trailing zeros dropped: plain between
/// 1e-4 and 1e6, else in scientific notation (`1e300`, `-2.5e-7`).
fn significant(x: f64, digits: usize) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == 0.0 {
        return "0".into();
    }
    let magnitude = x.abs();
    if (1e-4..1e6).contains(&magnitude) {
        let decimals = (digits as i32 - 1 - magnitude.log10().floor() as i32).clamp(0, digits as i32 + 3) as usize;
        let text = format!("{x:.decimals$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        }
    } else {
        let precision = digits - 1;
        let text = format!("{x:.precision$e}");
        let (mantissa, exponent) = text.split_once('e').expect("scientific notation");
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        format!("{mantissa}e{exponent}")
    }
}

/// `x` in at most six significant digits ([`ShortNumber`]).
pub fn short_number(x: f64) -> ShortNumber {
    ShortNumber(x)
}

/// A `value` refused for lying outside `bounds`, for a message that names the bounds:
/// as short as [`short_number`], but with as many more significant digits (up to 17,
/// which tell any two numbers apart) as it takes to differ from every bound written
/// the same way, so that 100.0001 against "at most 100" is never shown as `100`.
pub fn refused_number(value: f64, bounds: &[f64]) -> String {
    (SHORT_DIGITS..=17)
        .map(|digits| significant(value, digits))
        .enumerate()
        .find(|(k, text)| {
            let digits = SHORT_DIGITS + k;
            bounds.iter().all(|&b| b == value || significant(b, digits) != *text)
        })
        .map_or_else(|| format!("{value:e}"), |(_, text)| text)
}

/// `value` and the computed `bound` it is refused against, both in the same number of
/// significant digits (six or more) that tells them apart: `[value, bound]`. For bounds
/// that are not round constants, whose short form could hide on which side the value
/// lies (0.30000004 against a bound of 0.3000001 printed `0.3`).
pub fn numbers_apart(value: f64, bound: f64) -> [String; 2] {
    (SHORT_DIGITS..=17)
        .map(|digits| [significant(value, digits), significant(bound, digits)])
        .find(|[a, b]| a != b || value == bound)
        .unwrap_or_else(|| [format!("{value:e}"), format!("{bound:e}")])
}

/// Why the constrained Delaunay triangulation (spade) refused a point, in words for a
/// message (spade's own text is its variant's name: `TooLarge`, `TooSmall`, `NAN`).
pub fn triangulation_problem(error: &spade::InsertionError) -> String {
    match error {
        spade::InsertionError::TooSmall => format!(
            "a coordinate is nearer to zero than {} without being zero, which the triangulation cannot take",
            short_number(spade::MIN_ALLOWED_VALUE)
        ),
        spade::InsertionError::TooLarge => format!(
            "a coordinate is larger than {}, which the triangulation cannot take",
            short_number(spade::MAX_ALLOWED_VALUE)
        ),
        spade::InsertionError::NAN => "a coordinate is not a number".to_string(),
    }
}

/// Most characters of a token quoted in a message.
pub const QUOTED_TOKEN_CHARS: usize = 40;

/// `token` for a message: at most [`QUOTED_TOKEN_CHARS`] characters (then `…` and how
/// many more), control characters shown as escapes, so that a 1 MB line or a binary
/// file never floods the terminal.
pub fn quoted_token(token: &str) -> String {
    let count = token.chars().count();
    let mut text: String = token
        .chars()
        .take(QUOTED_TOKEN_CHARS)
        .flat_map(|c| {
            if c.is_control() {
                c.escape_default().collect::<Vec<_>>()
            } else {
                vec![c]
            }
        })
        .collect();
    if count > QUOTED_TOKEN_CHARS {
        text.push_str(&format!("… ({} more characters)", count - QUOTED_TOKEN_CHARS));
    }
    text
}

/// `message` with every word (run of non-space characters) longer than
/// [`QUOTED_TOKEN_CHARS`] cut by [`quoted_token`]: for messages built by other crates
/// (serde's quote the token they stopped at, whole: a 1 MB key made a 1 MB error).
pub fn shortened_message(message: &str) -> String {
    let mut out = String::with_capacity(message.len().min(4096));
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        if word.chars().count() > QUOTED_TOKEN_CHARS + 20 {
            out.push_str(&quoted_token(word));
        } else {
            out.push_str(word);
        }
        word.clear();
    };
    for c in message.chars() {
        if c.is_whitespace() {
            flush(&mut word, &mut out);
            out.push(c);
        } else {
            word.push(c);
        }
    }
    flush(&mut word, &mut out);
    out
}

/// `text` as XML character data or attribute text (SVG): markup characters escaped,
/// every control character as a space (XML 1.0 forbids all but tab, line feed and
/// carriage return, and those have no place in a one-line name), so that no scene name
/// or label can make a document invalid.
pub fn xml_escaped(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c if c.is_control() => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short() {
        for (x, text) in [
            (0.0, "0"),
            (12.5, "12.5"),
            (-3.0, "-3"),
            (0.001, "0.001"),
            (1.0 / 3.0, "0.333333"),
            (123456.7, "123457"),
            (1e300, "1e300"),
            (-2.5e-7, "-2.5e-7"),
            (f64::MAX, "1.79769e308"),
            (5e-324, "4.94066e-324"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
            (-1e-12, "-1e-12"),
        ] {
            assert_eq!(short_number(x).to_string(), text, "{x:e}");
        }
    }

    /// Issue 35: "must be between 0 and 100, got 100" for 100.0001. A refused value is
    /// printed with the digits that tell it from its bounds, and no longer than that.
    #[test]
    fn refused_numbers_differ_from_their_bounds() {
        for (value, bounds, text) in [
            (100.0001, &[0.0, 100.0][..], "100.0001"),
            (100.000_000_1, &[100.0][..], "100.0000001"),
            (100.0 + 1e-12, &[100.0][..], "100.000000000001"),
            (f64::from_bits(100f64.to_bits() + 1), &[100.0][..], "100.00000000000001"),
            (0.009_999_999_9, &[0.01, 10.0][..], "0.0099999999"),
            (-1e-300, &[0.0, 1.0][..], "-1e-300"),
            (1e308, &[1e6][..], "1e308"),
            (1_000_000.5, &[1e6][..], "1.0000005e6"),
            (250.0, &[100.0][..], "250"),
            (0.0, &[0.0][..], "0"),
            (f64::NAN, &[1.0][..], "NaN"),
        ] {
            let refused = refused_number(value, bounds);
            assert_eq!(refused, text, "{value:e}");
            for &b in bounds {
                assert!(
                    b == value || refused.parse::<f64>().unwrap() != b,
                    "{refused} reads as {b}"
                );
            }
        }
    }

    #[test]
    fn numbers_apart_share_their_digits() {
        assert_eq!(numbers_apart(0.300_000_04, 0.300_000_1), ["0.3", "0.3000001"]);
        assert_eq!(
            numbers_apart(251.327_412_3, 251.327_412_287),
            ["251.3274123", "251.32741229"]
        );
        assert_eq!(numbers_apart(1e308, 2.5), ["1e308", "2.5"]);
        assert_eq!(numbers_apart(2.0, 2.0), ["2", "2"]);
    }

    #[test]
    fn triangulation_problems_are_words() {
        for e in [
            spade::InsertionError::TooSmall,
            spade::InsertionError::TooLarge,
            spade::InsertionError::NAN,
        ] {
            let text = triangulation_problem(&e);
            assert!(
                text.starts_with("a coordinate") && !text.contains(&format!("{e:?}")),
                "{text}"
            );
        }
    }

    #[test]
    fn xml_text_is_escaped_and_has_no_control_characters() {
        assert_eq!(
            xml_escaped("a<b & \"c\">\0\u{1b}\n"),
            "a&lt;b &amp; &quot;c&quot;&gt;   "
        );
    }

    #[test]
    fn long_words_of_a_message_are_cut() {
        let message = format!("unknown field `{}`, expected one of `name`", "A".repeat(1_000_000));
        let short = shortened_message(&message);
        assert!(short.len() < 200 && short.starts_with("unknown field `AAAA"), "{short}");
        assert!(short.ends_with("expected one of `name`"), "{short}");
        assert_eq!(shortened_message("a  b\nc"), "a  b\nc");
    }

    #[test]
    fn tokens_are_cut_and_escaped() {
        assert_eq!(quoted_token("abc"), "abc");
        assert_eq!(quoted_token("a\nb\0"), "a\\nb\\u{0}");
        let long = "x".repeat(1_000_000);
        let quoted = quoted_token(&long);
        assert!(
            quoted.len() < 100 && quoted.ends_with("(999960 more characters)"),
            "{quoted}"
        );
    }
}
