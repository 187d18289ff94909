//! The page: one HTML file with the style, three.js, the viewer's script and the data inlined.

use super::ViewData;

const PAGE: &str = include_str!("../assets/view/page.html");
const STYLE: &str = include_str!("../assets/view/view.css");
const THREE: &str = include_str!("../assets/view/three.min.js");
const SCRIPT: &str = include_str!("../assets/view/view.js");

/// Text safe inside a `<script>` element: `</` cannot close it (`<\/` means the same in
/// JavaScript strings and JSON), and `<!--` cannot open a comment state.
fn script_safe(s: &str) -> String {
    s.replace("</", "<\\/").replace("<!--", "<\\!--")
}

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The self-contained page of `view`: opens from `file://` in any browser with no network.
///
/// ```
/// use stance_view::{render, scene_view, SceneViewOptions};
/// let scene = stance_contact::examples::single_support_flat();
/// let v = scene_view(&scene, "single-support", &SceneViewOptions::default()).unwrap();
/// let html = render(&v);
/// assert!(html.starts_with("<!DOCTYPE html>"));
/// assert!(!html.contains("src=\"http")); // nothing fetched
/// assert!(html.contains("single-support"));
/// ```
pub fn render(view: &ViewData) -> String {
    let data = serde_json::to_string(view).expect("the view data serializes");
    let parts = [
        ("{{TITLE}}", html_escape(&view.title)),
        ("{{STYLE}}", STYLE.to_string()),
        ("{{THREE}}", script_safe(THREE)),
        ("{{SCRIPT}}", script_safe(SCRIPT)),
        ("{{DATA}}", script_safe(&data)),
    ];
    // One pass over the template: a marker inside inserted text is never replaced.
    let mut out = String::with_capacity(PAGE.len() + THREE.len() + SCRIPT.len() + data.len());
    let mut rest = PAGE;
    while let Some((at, (marker, text))) = parts
        .iter()
        .filter_map(|(m, t)| rest.find(m).map(|at| (at, (m, t))))
        .min_by_key(|(at, _)| *at)
    {
        out.push_str(&rest[..at]);
        out.push_str(text);
        rest = &rest[at + marker.len()..];
    }
    out.push_str(rest);
    out
}
