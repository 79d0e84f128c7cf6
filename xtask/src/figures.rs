//! `cargo xtask check-figures DIR`: what a machine can check of every SVG figure under DIR.
//!
//! The figures come from [`crate::plot`] (and the stress map of [`crate::plots`]), drawn by
//! plotters, whose SVG the checks read: texts with their anchor, position and size, lines
//! (`<polyline>`) with their colour and width, markers (`<circle>`). A figure fails when
//! - a text reads "us" for microseconds, or a number it prints (a tick label) has more than six
//!   significant digits ("9.999999999999999e-10");
//! - an axis title (a centred text other than the figure's title, which is the topmost) does not
//!   end with its unit in parentheses ("time (µs)", "restitution (-)");
//! - a legend entry (a label anchored at its start, with its line sample on the left) is crossed
//!   by a plotted series' line or covers one of its markers;
//! - a legend entry has no line sample, or two entries share colour, dash, width and marker.

use crate::files::say;
use anyhow::Context;
use std::path::{Path, PathBuf};

/// The most significant digits a printed number may have.
const MAX_DIGITS: usize = 6;

/// A `<text>`: its content (entities left as they are), anchor, position and font size (px).
struct Label<'a> {
    content: &'a str,
    anchor: &'a str,
    x: f64,
    y: f64,
    size: f64,
}

/// A line of a series or of a legend sample: `<polyline>` wider than the axes' 1 px.
struct Stroke<'a> {
    colour: &'a str,
    width: f64,
    points: Vec<(f64, f64)>,
}

/// A filled marker, `<circle>`.
struct Marker<'a> {
    colour: &'a str,
    centre: (f64, f64),
    radius: f64,
}

/// The value of attribute `name` in the tag `tag` (`<text x="1" ...>`).
fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let len = tag[start..].find('"')?;
    Some(&tag[start..start + len])
}

fn number(tag: &str, name: &str) -> f64 {
    attribute(tag, name).and_then(|v| v.parse().ok()).unwrap_or(f64::NAN)
}

/// The tags `<element ...>` of an SVG, each with what follows it up to the next tag.
fn tags<'a>(svg: &'a str, element: &str) -> Vec<(&'a str, &'a str)> {
    let open = format!("<{element} ");
    svg.match_indices(open.as_str())
        .filter_map(|(at, _)| {
            let end = svg[at..].find('>')? + at;
            let after = &svg[end + 1..];
            let body = after.find('<').map_or(after, |i| &after[..i]);
            Some((&svg[at..=end], body))
        })
        .collect()
}

fn labels(svg: &str) -> Vec<Label<'_>> {
    tags(svg, "text")
        .into_iter()
        // An empty text draws nothing (a logarithmic axis leaves its ticks between 1, 2 and 5
        // of a decade unlabelled).
        .filter(|(_, body)| !body.trim().is_empty())
        .map(|(tag, body)| Label {
            content: body.trim(),
            anchor: attribute(tag, "text-anchor").unwrap_or("start"),
            x: number(tag, "x"),
            y: number(tag, "y"),
            size: number(tag, "font-size"),
        })
        .collect()
}

fn strokes(svg: &str) -> Vec<Stroke<'_>> {
    tags(svg, "polyline")
        .into_iter()
        .map(|(tag, _)| Stroke {
            colour: attribute(tag, "stroke").unwrap_or(""),
            width: number(tag, "stroke-width"),
            points: attribute(tag, "points")
                .unwrap_or("")
                .split_whitespace()
                .filter_map(|p| {
                    let (x, y) = p.split_once(',')?;
                    Some((x.parse().ok()?, y.parse().ok()?))
                })
                .collect(),
        })
        .filter(|s| s.width > 1.0)
        .collect()
}

fn markers(svg: &str) -> Vec<Marker<'_>> {
    tags(svg, "circle")
        .into_iter()
        .map(|(tag, _)| Marker {
            colour: attribute(tag, "fill").unwrap_or(""),
            centre: (number(tag, "cx"), number(tag, "cy")),
            radius: number(tag, "r"),
        })
        .collect()
}

/// Significant digits of `text` if it is a plain number ("-0.0125", "2.5e-6"), else `None`.
fn significant_digits(text: &str) -> Option<usize> {
    text.parse::<f64>().ok()?;
    let mantissa = text.trim_start_matches('-').split(['e', 'E']).next()?;
    let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    let trimmed = digits.trim_start_matches('0');
    Some(trimmed.len().max(1))
}

/// An axis-aligned box: x0, x1, y0, y1 (px, y down).
#[derive(Clone, Copy)]
struct Area(f64, f64, f64, f64);

impl Area {
    fn contains(&self, (x, y): (f64, f64)) -> bool {
        (self.0..=self.1).contains(&x) && (self.2..=self.3).contains(&y)
    }

    /// Whether the segment from `a` to `b` passes through the box (Liang-Barsky clipping).
    fn crossed_by(&self, a: (f64, f64), b: (f64, f64)) -> bool {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
        for (p, q) in
            [(-dx, a.0 - self.0), (dx, self.1 - a.0), (-dy, a.1 - self.2), (dy, self.3 - a.1)]
        {
            if p == 0.0 {
                if q < 0.0 {
                    return false;
                }
            } else {
                let t = q / p;
                if p < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
        }
        t0 <= t1
    }
}

/// The legend's geometry as [`crate::plot`] draws it: a label's top left at (x, y), its line
/// sample left of it on the label's middle row, a marker on the sample's middle.
const SAMPLE_SPAN: f64 = crate::plot::LEGEND_SAMPLE as f64 + 16.0;

/// One legend entry: its label, the box of its sample and of its label.
struct Entry<'a> {
    label: &'a str,
    sample: Area,
    text: Area,
}

fn entries<'a>(labels: &[Label<'a>]) -> Vec<Entry<'a>> {
    labels
        .iter()
        .filter(|l| l.anchor == "start" && significant_digits(l.content).is_none())
        .map(|l| {
            // A sans-serif glyph is about 0.6 em wide on average.
            let width = 0.6 * l.size * l.content.chars().count() as f64;
            let (top, bottom) = (l.y - 2.0, l.y + 1.2 * l.size);
            Entry {
                label: l.content,
                sample: Area(l.x - SAMPLE_SPAN, l.x - 1.0, top, bottom),
                text: Area(l.x, l.x + width, top, bottom),
            }
        })
        .collect()
}

/// What is wrong with the figure `svg`, one line each.
pub(crate) fn problems(svg: &str) -> Vec<String> {
    let mut out = Vec::new();
    let labels = labels(svg);
    for text in labels.iter().map(|l| l.content) {
        if text.split(|c: char| !c.is_alphanumeric()).any(|word| word == "us") {
            out.push(format!("\"{text}\": microseconds are µs"));
        }
        if significant_digits(text).is_some_and(|d| d > MAX_DIGITS) {
            out.push(format!("\"{text}\": more than {MAX_DIGITS} significant digits"));
        }
    }
    // Axis titles: the centred words below the topmost text (the figure's title).
    let centred: Vec<&Label<'_>> = labels
        .iter()
        .filter(|l| l.anchor == "middle" && significant_digits(l.content).is_none())
        .collect();
    let title_y = centred.iter().map(|l| l.y).fold(f64::INFINITY, f64::min);
    let axes: Vec<&str> = centred.iter().filter(|l| l.y > title_y).map(|l| l.content).collect();
    if axes.len() < 2 {
        out.push(format!("{} axis title(s), expected one on each axis", axes.len()));
    }
    for axis in axes {
        let unit = axis.strip_suffix(')').and_then(|a| a.rsplit_once('(')).map(|(_, u)| u.trim());
        if unit.is_none_or(str::is_empty) {
            out.push(format!("axis \"{axis}\": no unit in parentheses at its end"));
        }
    }
    // The legend: each entry's sample, then what crosses it.
    let entries = entries(&labels);
    let strokes = strokes(svg);
    let markers = markers(svg);
    let mut styles = Vec::new();
    for entry in &entries {
        let sample: Vec<&Stroke<'_>> =
            strokes.iter().filter(|s| s.points.iter().all(|p| entry.sample.contains(*p))).collect();
        let marker = markers.iter().find(|m| entry.sample.contains(m.centre));
        let Some(first) = sample.first() else {
            out.push(format!("legend entry \"{}\": no line sample", entry.label));
            continue;
        };
        // A dashed line is drawn as one polyline per dash.
        styles.push((
            entry.label,
            first.colour,
            sample.len() > 1,
            first.width,
            marker.map(|m| m.colour),
        ));
    }
    for (i, a) in styles.iter().enumerate() {
        if let Some(b) = styles[..i].iter().find(|b| (b.1, b.2, b.3, b.4) == (a.1, a.2, a.3, a.4)) {
            out.push(format!(
                "legend entries \"{}\" and \"{}\": the same colour and line",
                b.0, a.0
            ));
        }
    }
    let in_a_sample = |p: (f64, f64)| entries.iter().any(|e| e.sample.contains(p));
    for stroke in strokes.iter().filter(|s| !s.points.iter().all(|p| in_a_sample(*p))) {
        for entry in &entries {
            let (whole, label) =
                (Area(entry.sample.0, entry.text.1, entry.text.2, entry.text.3), entry.label);
            if stroke.points.windows(2).any(|w| whole.crossed_by(w[0], w[1]))
                || (stroke.points.len() == 1 && whole.contains(stroke.points[0]))
            {
                out.push(format!(
                    "legend entry \"{label}\": a series' line ({}) passes under it",
                    stroke.colour
                ));
            }
        }
    }
    for marker in markers.iter().filter(|m| !in_a_sample(m.centre)) {
        for entry in &entries {
            let r = marker.radius;
            let near =
                Area(entry.sample.0 - r, entry.text.1 + r, entry.text.2 - r, entry.text.3 + r);
            if near.contains(marker.centre) {
                out.push(format!(
                    "legend entry \"{}\": covers a marker ({})",
                    entry.label, marker.colour
                ));
            }
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
    #![allow(clippy::unwrap_used)] // a test stops on a broken fixture
    use super::{problems, significant_digits};
    use crate::plot::{Chart, Series};

    /// An SVG text as plotters writes it.
    fn text(x: u32, y: u32, anchor: &str, content: &str) -> String {
        format!(
            "<text x=\"{x}\" y=\"{y}\" dy=\"0.76em\" text-anchor=\"{anchor}\" font-size=\"12.1\">\n{content}\n</text>\n"
        )
    }

    fn line(colour: &str, points: &str) -> String {
        format!("<polyline fill=\"none\" stroke=\"{colour}\" stroke-width=\"2\" points=\"{points} \"/>\n")
    }

    /// A title, two axis titles and a legend entry "a" at (866, 62) with its sample.
    fn figure(extra: &str, x_axis: &str) -> String {
        let mut svg = String::from("<svg>\n");
        svg += &text(410, 23, "middle", "A title");
        svg += &text(18, 269, "middle", "force (N)");
        svg += &text(450, 542, "middle", x_axis);
        svg += &text(88, 477, "end", "0.5");
        svg += &text(866, 62, "start", "a");
        svg += &line("#0072B2", "824,70 858,70");
        svg += &line("#0072B2", "100,400 700,300");
        svg + extra + "</svg>\n"
    }

    #[test]
    fn each_rule_finds_what_it_is_for() {
        assert!(
            problems(&figure("", "time (µs)")).is_empty(),
            "{:?}",
            problems(&figure("", "time (µs)"))
        );
        let cases = [
            (
                figure(&text(88, 416, "end", "0.09999999999999998"), "time (µs)"),
                "significant digits",
            ),
            (figure("", "time (us)"), "microseconds are µs"),
            (figure("", "time"), "no unit in parentheses"),
            (figure("", "time ()"), "no unit in parentheses"),
            // A curve through the label, and one through the sample only.
            (figure(&line("#E69F00", "840,300 870,40"), "time (s)"), "passes under it"),
            (figure(&line("#E69F00", "830,50 830,90"), "time (s)"), "passes under it"),
            (
                figure("<circle cx=\"870\" cy=\"68\" r=\"4\" fill=\"#E69F00\"/>\n", "time (s)"),
                "covers a marker",
            ),
            (
                figure(
                    &(text(866, 84, "start", "b") + &line("#0072B2", "824,92 858,92")),
                    "time (s)",
                ),
                "the same colour and line",
            ),
            (figure(&text(866, 84, "start", "b"), "time (s)"), "no line sample"),
        ];
        for (svg, expected) in cases {
            let found = problems(&svg);
            assert!(
                found.len() == 1 && found[0].contains(expected),
                "expected one \"{expected}\", found {found:?}"
            );
        }
        // A dashed sample of the same colour is another style.
        let dashed = text(866, 84, "start", "b")
            + &line("#0072B2", "824,92 832,92")
            + &line("#0072B2", "837,92 845,92");
        assert!(problems(&figure(&dashed, "time (s)")).is_empty());
        assert_eq!(significant_digits("-0.0125"), Some(3));
        assert_eq!(significant_digits("2.5e-6"), Some(2));
        assert_eq!(significant_digits("1400"), Some(4));
        assert_eq!(significant_digits("force (N)"), None);
    }

    #[test]
    fn a_chart_of_sixteen_series_with_markers_and_a_reference_passes() {
        let dir = std::env::temp_dir().join(format!("xtask-figures-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let series = (0..16)
            .map(|i| Series {
                label: format!("series {i} with a long label"),
                points: (0..200)
                    .map(|k| {
                        let t = f64::from(k) * 1e-6;
                        (t * 1e6, (f64::from(i) + 1.0) * (t * 3e4).sin() + 1e-3 * t)
                    })
                    .collect(),
            })
            .collect();
        let chart = Chart {
            title: "sixteen",
            x_label: "time (µs)",
            y_label: "force (kN)",
            series,
            markers: true,
            reference_first: true,
        };
        chart.write(&dir, "sixteen").unwrap();
        let svg = std::fs::read_to_string(dir.join("sixteen.svg")).unwrap();
        std::fs::remove_dir_all(&dir).ok();
        assert!(problems(&svg).is_empty(), "{:?}", problems(&svg));
    }
}
