//! An [`Animation`] as one self-contained HTML page: the data inline as JSON, the drawing and
//! the player in a few hundred lines of plain JavaScript on two canvases — no network, no
//! external script (docs/animation.md says what is drawn and what the colours mean).

use crate::animation::{Animation, Track};

/// The page's template; `__TITLE__` and `__DATA__` are filled in.
const TEMPLATE: &str = include_str!("animation.html");

/// Poses are written to 1 µm (m) and 1 µrad: far below a pixel of any drawing.
const POSE_DIGITS: f64 = 1e6;

/// The page playing `animation`.
///
/// # Panics
/// Never: the animation serializes to JSON (no map keys that are not strings).
pub fn page(animation: &Animation) -> String {
    let rounded = Animation {
        tracks: animation
            .tracks
            .iter()
            .map(|track| Track {
                poses: track
                    .poses
                    .iter()
                    .map(|frame| frame.iter().map(|p| p.map(|v| (v * POSE_DIGITS).round() / POSE_DIGITS)).collect())
                    .collect(),
                errors: track.errors.as_ref().map(|e| e.iter().map(|&v| significant(v, 4)).collect()),
                ..track.clone()
            })
            .collect(),
        ..animation.clone()
    };
    let data = serde_json::to_string(&rounded).expect("an animation serializes to JSON");
    // Inside a <script> element, "</" must not appear.
    let data = data.replace("</", "<\\/");
    TEMPLATE.replacen("__TITLE__", &escape(&animation.title), 1).replacen("__DATA__", &data, 1)
}

/// `value` to `digits` significant digits (non-finite values as they are: serialized as null).
fn significant(value: f64, digits: i32) -> f64 {
    if value == 0.0 || !value.is_finite() {
        return value;
    }
    let scale = 10f64.powi(digits - 1 - value.abs().log10().floor() as i32);
    (value * scale).round() / scale
}

/// Text for HTML.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::significant;

    #[test]
    fn errors_keep_four_significant_digits() {
        assert_eq!(significant(1.234567e-9, 4), 1.235e-9);
        assert_eq!(significant(-98765.0, 4), -98770.0);
        assert_eq!(significant(0.0, 4), 0.0);
    }
}
