//! `cargo xtask check-figures DIR`: what a machine can check of every SVG figure under DIR.
//!
//! A figure fails when a text of it reads "us" for microseconds, or when a number it prints
//! (a tick label) has more than six significant digits ("9.999999999999999e-10"). The other
//! rules of a readable figure hold by construction in [`crate::plot`]: the legend has a column
//! of its own, sixteen series get sixteen styles, an axis label names its unit.

use crate::files::say;
use anyhow::Context;
use std::path::{Path, PathBuf};

/// The most significant digits a printed number may have.
const MAX_DIGITS: usize = 6;

/// The texts of an SVG (the content of its `<text>` elements, entities left as they are).
fn texts(svg: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = svg;
    while let Some(open) = rest.find("<text") {
        let Some(start) = rest[open..].find('>').map(|i| open + i + 1) else { break };
        let Some(end) = rest[start..].find("</text>").map(|i| start + i) else { break };
        out.push(rest[start..end].trim());
        rest = &rest[end..];
    }
    out
}

/// Significant digits of `text` if it is a plain number ("-0.0125", "2.5e-6"), else `None`.
fn significant_digits(text: &str) -> Option<usize> {
    text.parse::<f64>().ok()?;
    let mantissa = text.trim_start_matches('-').split(['e', 'E']).next()?;
    let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    let trimmed = digits.trim_start_matches('0');
    Some(trimmed.len().max(1))
}

/// What is wrong with the figure `svg`, one line each.
pub(crate) fn problems(svg: &str) -> Vec<String> {
    let mut out = Vec::new();
    for text in texts(svg) {
        if text.split(|c: char| !c.is_alphanumeric()).any(|word| word == "us") {
            out.push(format!("\"{text}\": microseconds are µs"));
        }
        if significant_digits(text).is_some_and(|d| d > MAX_DIGITS) {
            out.push(format!("\"{text}\": more than {MAX_DIGITS} significant digits"));
        }
    }
    out
}

fn svgs(dir: &Path, found: &mut Vec<PathBuf>) -> anyhow::Result<()> {
    for entry in std::fs::read_dir(dir).with_context(|| format!("cannot read {}", dir.display()))? {
        let path = entry?.path();
        if path.is_dir() {
            svgs(&path, found)?;
        } else if path.extension().is_some_and(|e| e == "svg") {
            found.push(path);
        }
    }
    Ok(())
}

/// Checks every SVG under `dir`; prints each problem; false when there is one.
pub(crate) fn run(dir: &Path) -> anyhow::Result<bool> {
    let mut found = Vec::new();
    svgs(dir, &mut found)?;
    found.sort();
    let mut clean = true;
    for path in &found {
        let svg = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        for p in problems(&svg) {
            say!("{}: {p}", path.display())?;
            clean = false;
        }
    }
    say!(
        "{} figure(s) checked under {}: {}",
        found.len(),
        dir.display(),
        if clean { "readable" } else { "problems above" }
    )?;
    Ok(clean)
}

#[cfg(test)]
mod tests {
    use super::{problems, significant_digits};

    #[test]
    fn a_figure_with_long_ticks_or_us_fails() {
        let bad = r#"<svg><text x="1">9.999999999999999e-10</text><text>time (us)</text><text>0.09999999999999998</text></svg>"#;
        assert_eq!(problems(bad).len(), 3, "{:?}", problems(bad));
        let good = r#"<svg><text x="1">1e-9</text><text>time (µs)</text><text>0.10</text><text>users</text></svg>"#;
        assert!(problems(good).is_empty(), "{:?}", problems(good));
        assert_eq!(significant_digits("-0.0125"), Some(3));
        assert_eq!(significant_digits("2.5e-6"), Some(2));
        assert_eq!(significant_digits("1400"), Some(4));
        assert_eq!(significant_digits("force (N)"), None);
    }
}
