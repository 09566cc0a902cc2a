//! The report's colours: light fills for faces, strong hues for curves (a qualitative
//! palette that stays readable in print and for most colour-blind readers), and the
//! inks of edges, ellipses, bands and plot lines. Colours go by entity index, so the same
//! mesh always gets the same colours.

const FACES: [&str; 8] =
    ["#cfe3f7", "#fbe3c8", "#d6efd0", "#e8dcf4", "#fbf0bf", "#d2eef0", "#f6d6e2", "#e2e2e2"];
const CURVES: [&str; 10] = [
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2",
    "#bcbd22", "#7f7f7f",
];

/// Fill of topological face `i`.
pub(super) fn face(i: usize) -> &'static str {
    FACES[i % FACES.len()]
}

/// Stroke of topological curve `i`.
pub(super) fn curve(i: usize) -> &'static str {
    CURVES[i % CURVES.len()]
}

/// Marker of tagged topological point `i`: the curves' hues, shifted so that a corner
/// and the curves meeting there seldom share one (the marker's shape tells them apart).
pub(super) fn point(i: usize) -> &'static str {
    CURVES[(i + 4) % CURVES.len()]
}

/// Mesh edges.
pub(super) const EDGE: &str = "#3a3a3a";
/// Size ellipses.
pub(super) const ELLIPSE: &str = "#c2185b";
/// Frames of the zoom windows.
pub(super) const FRAME: &str = "#111111";
/// The conforming band of the edge-length histogram.
pub(super) const BAND: &str = "#c8e6c9";
/// Histogram bars.
pub(super) const BAR: &str = "#5c7cba";
/// Bars inside the conforming band.
pub(super) const BAR_OK: &str = "#2e7d32";
/// Axes and ticks.
pub(super) const AXIS: &str = "#444444";
/// Muted text.
pub(super) const MUTED: &str = "#666666";
/// First series of the history plot (vertices).
pub(super) const SERIES_A: &str = "#1f77b4";
/// Second series (conforming share).
pub(super) const SERIES_B: &str = "#e65100";
/// Third series (mean quality).
pub(super) const SERIES_C: &str = "#2e7d32";
