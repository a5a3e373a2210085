//! Times e^A with j Fréchet derivatives (expm_frechet_many) and one MEM iteration of the
//! modal test family against N, and draws docs/performance-scaling.svg (log–log).
//! `cargo run --release -p memid-benches --example plot_scaling`

use faer::Mat;
use plotters::prelude::*;
use std::time::Instant;

fn median(reps: usize, mut f: impl FnMut()) -> f64 {
    f();
    let mut t: Vec<f64> = (0..reps)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[reps / 2]
}

fn main() {
    let sizes = [8usize, 16, 32, 64, 128, 256, 512];
    let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for j in [1usize, 5, 20] {
        let mut points = Vec::new();
        for &n in &sizes {
            let fam = test_problems::ModalFamily::new(n / 2, 2, 1, 42);
            let a = fam.a(&fam.p_nominal) * faer::Scale(1.0 / 12.8);
            let es: Vec<Mat<f64>> = (0..j).map(|k| test_problems::gaussian(n, n, k as u64)).collect();
            let refs: Vec<_> = es.iter().map(|e| e.as_ref()).collect();
            let reps = if n >= 256 { 3 } else { 15 };
            let t = median(reps, || {
                std::hint::black_box(expm::expm_frechet_many(a.as_ref(), &refs).unwrap());
            });
            println!("expm_frechet j={j} N={n}: {:.3} ms", t * 1e3);
            points.push((n as f64, t));
        }
        series.push((format!("e^A and {j} Fréchet derivative(s)"), points));
    }
    let mut iteration = Vec::new();
    for &n in &sizes[..6] {
        let fam = test_problems::ModalFamily::new(n / 2, 5, 4, 2026);
        let model = mem::LinearResponse(fam.clone());
        let data = test_problems::simulate_measurement(&model, &fam.p_nominal, 1.0 / 12.8, 2000, 0.01, 1);
        let experiments =
            mem::Problem::unnamed(vec![mem::Experiment::normalized(&model, &data)], &fam.p_nominal).unwrap();
        let t = median(if n >= 128 { 3 } else { 11 }, || {
            std::hint::black_box(mem::gauss_newton_step(&experiments, &fam.p_nominal, 1e-10).unwrap());
        });
        println!("mem iteration j=5 p=4 K=2000 N={n}: {:.3} ms", t * 1e3);
        iteration.push((n as f64, t));
    }
    series.push(("MEM iteration, j = 5, p = 4, K = 2000".into(), iteration));
    let _ = plotters::style::register_font(
        "sans-serif",
        FontStyle::Normal,
        include_bytes!("../../crates/memid/assets/DejaVuSans.ttf"),
    );
    let docs = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs");
    let svg = docs.join("performance-scaling.svg");
    draw(SVGBackend::new(&svg, (900, 560)).into_drawing_area(), &series);
    println!("wrote {}", svg.display());
    let png = docs.join("performance-scaling.png");
    draw(BitMapBackend::new(&png, (900, 560)).into_drawing_area(), &series);
    println!("wrote {}", png.display());
}

/// The log–log chart of every series, on any plotters backend.
fn draw<B: DrawingBackend>(root: DrawingArea<B, plotters::coord::Shift>, series: &[(String, Vec<(f64, f64)>)])
where
    B::ErrorType: 'static,
{
    root.fill(&WHITE).unwrap();
    let mut chart = ChartBuilder::on(&root)
        .caption("Time against the number of states N (this machine, 2 cores)", ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d((6.0f64..600.0).log_scale(), (1e-6f64..10.0).log_scale())
        .unwrap();
    chart
        .configure_mesh()
        .x_desc("N (states)")
        .y_desc("seconds")
        .label_style(("sans-serif", 14))
        .draw()
        .unwrap();
    let colors = [RGBColor(30, 100, 200), RGBColor(200, 60, 40), RGBColor(40, 150, 60), RGBColor(30, 30, 30)];
    for ((label, points), color) in series.iter().zip(colors) {
        chart
            .draw_series(LineSeries::new(points.iter().copied(), color.stroke_width(2)))
            .unwrap()
            .label(label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
        chart.draw_series(points.iter().map(|p| Circle::new(*p, 3, color.filled()))).unwrap();
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .unwrap();
    root.present().unwrap();
}
