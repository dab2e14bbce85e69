use charts::{
    CategoryMap, Chart, ChartError, Scale, Series, Style, write_category_map, write_chart,
    write_stacked,
};

fn sample_chart() -> Chart {
    let mut chart = Chart::new("speed–thrust", "speed (m/s)", "thrust (N)");
    chart.series.push(Series::new(
        "curve",
        vec![(0.0, 3.5), (0.5, 2.0), (1.0, 0.0)],
        Style::LineMarkers,
    ));
    chart.series.push(Series::new(
        "bound",
        vec![(0.0, 4.0), (1.1, 0.0)],
        Style::Dashed,
    ));
    chart.shaded_x.push((0.2, 0.4));
    chart
}

#[test]
fn chart_is_written_as_svg_and_png_next_to_each_other() {
    let dir = tempfile::tempdir().unwrap();
    let files = write_chart(&sample_chart(), &dir.path().join("curve")).unwrap();
    assert_eq!(files[0], dir.path().join("curve.svg"));
    let svg = std::fs::read_to_string(&files[0]).unwrap();
    assert!(
        svg.contains("<svg") && svg.contains("speed"),
        "svg should hold the axis label"
    );
    if let Some(png) = files.get(1) {
        let bytes = std::fs::read(png).unwrap();
        assert_eq!(&bytes[1..4], b"PNG", "png magic bytes");
    }
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(
        leftovers.is_empty(),
        "temporary files left behind: {leftovers:?}"
    );
}

#[test]
fn log_chart_without_positive_data_is_refused() {
    let mut chart = Chart::new("error", "time (s)", "error").log_log();
    chart.series.push(Series::new(
        "zero",
        vec![(0.0, 0.0), (-1.0, 1.0)],
        Style::Line,
    ));
    let dir = tempfile::tempdir().unwrap();
    let result = write_chart(&chart, &dir.path().join("bad"));
    assert!(
        matches!(result, Err(ChartError::NoData { .. })),
        "got {result:?}"
    );
    assert!(
        !dir.path().join("bad.svg").exists(),
        "no file for a refused chart"
    );
}

#[test]
fn stacked_panels_share_one_file() {
    let dir = tempfile::tempdir().unwrap();
    let mut second = sample_chart();
    second.title = "second".into();
    let files = write_stacked(&[sample_chart(), second], &dir.path().join("history")).unwrap();
    let svg = std::fs::read_to_string(&files[0]).unwrap();
    assert!(svg.contains("second"), "both panel titles in one svg");
}

#[test]
fn category_map_checks_its_grid() {
    let dir = tempfile::tempdir().unwrap();
    let mut map = CategoryMap {
        title: "stability".into(),
        x_label: "dt (s)".into(),
        y_label: "v_reg (m/s)".into(),
        x_scale: Scale::Log,
        y_scale: Scale::Linear,
        xs: vec![1e-10, 1e-9, 1e-8],
        ys: vec![0.0, 1.0],
        cells: vec![vec![0, 0, 1], vec![0, 1, 2]],
        categories: vec!["stable".into(), "oscillating".into(), "diverged".into()],
    };
    write_category_map(&map, &dir.path().join("map")).unwrap();
    map.cells[1].pop();
    let result = write_category_map(&map, &dir.path().join("map2"));
    assert!(
        matches!(result, Err(ChartError::BadGrid { .. })),
        "ragged grid must be refused: {result:?}"
    );
}
