//! The scope's plots (plotters): one panel per unit, stacked, time in ms on x, a legend
//! with the variables' names, the trigger as a red line. SVG or PNG by the extension.

use std::path::Path;

use anyhow::{Result, anyhow};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::Recording;

/// DejaVu Sans cut down to ASCII, °, ² and µ (src/scope/DejaVuSans-LICENSE.txt): plotters
/// lays text out with it in both backends, so no plot depends on the fonts installed.
const FONT: &[u8] = include_bytes!("DejaVuSans-scope.ttf");

const WIDTH: u32 = 1200;
const PANEL_HEIGHT: u32 = 260;

/// Makes the embedded font plotters' "sans-serif" (every plot of the binary uses it).
pub fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
            .unwrap_or_else(|_| panic!("the embedded font is a valid TrueType font"));
    });
}

fn plot_error(e: impl std::fmt::Display) -> anyhow::Error {
    anyhow!("plot: {e}")
}

/// The units in the order their first variable was named.
fn units(recording: &Recording) -> Vec<&'static str> {
    let mut units = Vec::new();
    for var in &recording.vars {
        if !units.contains(&var.unit()) {
            units.push(var.unit());
        }
    }
    units
}

/// The runs of rows without a gap in their cycles (one decimation step apart).
fn runs(recording: &Recording) -> impl Iterator<Item = &[(u64, Vec<f64>)]> {
    let step = recording.decimate;
    recording.rows.chunk_by(move |a, b| b.0 - a.0 <= step)
}

pub fn draw(recording: &Recording, path: &Path) -> Result<()> {
    register_font();
    let panels = units(recording).len() as u32;
    let size = (WIDTH, PANEL_HEIGHT * panels + 40);
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
        draw_on(BitMapBackend::new(path, size).into_drawing_area(), recording)
    } else {
        draw_on(SVGBackend::new(path, size).into_drawing_area(), recording)
    }
}

fn draw_on<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, recording: &Recording) -> Result<()> {
    root.fill(&WHITE).map_err(plot_error)?;
    let title = match recording.trigger {
        Some(cycle) => format!("luamotion scope, trigger at {} ms", recording.time_ms(cycle)),
        None => "luamotion scope".to_string(),
    };
    let root = root.titled(&title, ("sans-serif", 22)).map_err(plot_error)?;
    let units = units(recording);
    let times = recording.rows.iter().map(|(cycle, _)| recording.time_ms(*cycle));
    let (t0, t1) = times.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| (lo.min(t), hi.max(t)));
    let (t0, t1) = if t0 < t1 { (t0, t1) } else { (0.0, 1.0) };
    for (panel, unit) in root.split_evenly((units.len(), 1)).iter().zip(&units) {
        let columns: Vec<usize> = (0..recording.vars.len()).filter(|&i| recording.vars[i].unit() == *unit).collect();
        let values = recording.rows.iter().flat_map(|(_, row)| columns.iter().map(|&i| row[i]));
        let (lo, hi) = values
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
        // A flat or empty trace still gets a readable axis.
        let (lo, hi) = if lo < hi {
            (lo, hi)
        } else if lo.is_finite() {
            (lo - 1.0, lo + 1.0)
        } else {
            (-1.0, 1.0)
        };
        let margin = (hi - lo) * 0.05;
        let mut chart = ChartBuilder::on(panel)
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(90)
            .build_cartesian_2d(t0..t1, lo - margin..hi + margin)
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_desc("time [ms]")
            .y_desc(*unit)
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
            .draw()
            .map_err(plot_error)?;
        for &column in &columns {
            let color = Palette99::pick(column).to_rgba();
            // A pause (SetHMIScope(0), rows lost) breaks the line rather than bridging it.
            for (n, run) in runs(recording).enumerate() {
                let points = run.iter().map(|(cycle, row)| (recording.time_ms(*cycle), row[column]));
                let series = chart.draw_series(LineSeries::new(points, color.stroke_width(2))).map_err(plot_error)?;
                if n == 0 {
                    series
                        .label(recording.vars[column].name())
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(3)));
                }
            }
        }
        if let Some(cycle) = recording.trigger {
            let t = recording.time_ms(cycle);
            chart
                .draw_series(LineSeries::new([(t, lo - margin), (t, hi + margin)], RED.stroke_width(1)))
                .map_err(plot_error)?;
        }
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(plot_error)?;
    }
    root.present().map_err(plot_error)?;
    Ok(())
}
