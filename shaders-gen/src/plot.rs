//! The tradeoff plot: error against time per frame, one point per row, the presets drawn
//! large and named, the Pareto front as a staircase through the points nothing beats.

use nimbus_output::TEXT_MARKER;
use plotters::prelude::*;

/// One point of the plot.
pub(crate) struct Point<'a> {
    pub label: &'a str,
    pub ms: f64,
    pub error: f64,
    pub preset: bool,
}

/// The SVG plot, its first line a comment with Nimbus's text signature; `front` lists
/// indices of `points` on the Pareto front in order of time.
pub(crate) fn svg_plot(
    title: &str,
    error_name: &str,
    points: &[Point<'_>],
    front: &[usize],
) -> Result<String, Box<dyn std::error::Error>> {
    let mut svg = String::new();
    draw(&mut svg, title, error_name, points, front)?;
    Ok(format!("<!-- {TEXT_MARKER}: nimbus tradeoff -->\n{svg}"))
}

fn draw(
    out: &mut String,
    title: &str,
    error_name: &str,
    points: &[Point<'_>],
    front: &[usize],
) -> Result<(), Box<dyn std::error::Error>> {
    let max_ms = points.iter().map(|p| p.ms).fold(0.0, f64::max) * 1.15;
    let max_err = points.iter().map(|p| p.error).fold(0.0, f64::max) * 1.15;
    let root = SVGBackend::with_string(out, (900, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(16)
        .x_label_area_size(40)
        .y_label_area_size(64)
        .build_cartesian_2d(0f64..max_ms.max(1e-9), 0f64..max_err.max(1e-9))?;
    chart
        .configure_mesh()
        .x_desc("time per frame (ms)")
        .y_desc(error_name)
        .draw()?;
    // The front as a staircase: each front point holds its error until the next is reached.
    let mut stairs = Vec::new();
    for (k, &i) in front.iter().enumerate() {
        let p = &points[i];
        stairs.push((p.ms, p.error));
        if let Some(&j) = front.get(k + 1) {
            stairs.push((points[j].ms, p.error));
        } else {
            stairs.push((max_ms, p.error));
        }
    }
    chart
        .draw_series(LineSeries::new(stairs, BLUE.stroke_width(2)))?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE.stroke_width(2)));
    let grey = RGBColor(120, 120, 120);
    chart.draw_series(points.iter().filter(|p| !p.preset).map(|p| {
        EmptyElement::at((p.ms, p.error))
            + Circle::new((0, 0), 3, grey.filled())
            + Text::new(
                p.label.to_string(),
                (5, -12),
                ("sans-serif", 11).into_font().color(&grey),
            )
    }))?;
    chart
        .draw_series(points.iter().filter(|p| p.preset).map(|p| {
            EmptyElement::at((p.ms, p.error))
                + Circle::new((0, 0), 6, RED.filled())
                + Text::new(p.label.to_string(), (8, 4), ("sans-serif", 14).into_font())
        }))?
        .label("quality presets")
        .legend(|(x, y)| Circle::new((x + 10, y), 5, RED.filled()));
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.9))
        .draw()?;
    root.present()?;
    Ok(())
}
