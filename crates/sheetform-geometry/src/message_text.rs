//! Numbers and tokens as they appear in messages for people (short, whatever the input),
//! and user text (names, labels) as it goes into XML files.

use std::fmt;

/// A number in at most six significant digits: `12.5`, `0.001`, `3.2e-7`, `1e300`,
/// `NaN`, `inf` (Rust's `{}` prints `1e300` as 301 digits).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShortNumber(pub f64);

impl fmt::Display for ShortNumber {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if !x.is_finite() {
            return write!(f, "{x}");
        }
        let magnitude = x.abs();
        if x == 0.0 {
            return f.write_str("0");
        }
        if (1e-4..1e6).contains(&magnitude) {
            // Six significant digits, trailing zeros dropped.
            let decimals = (5 - magnitude.log10().floor() as i32).clamp(0, 9) as usize;
            let text = format!("{x:.decimals$}");
            let text = if text.contains('.') {
                text.trim_end_matches('0').trim_end_matches('.')
            } else {
                &text
            };
            f.write_str(text)
        } else {
            let text = format!("{x:.5e}");
            let (mantissa, exponent) = text.split_once('e').expect("scientific notation");
            let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
            write!(f, "{mantissa}e{exponent}")
        }
    }
}

/// `x` in at most six significant digits ([`ShortNumber`]).
pub fn short_number(x: f64) -> ShortNumber {
    ShortNumber(x)
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
