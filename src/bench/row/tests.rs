//! Tests of `bench`: timing statistics and the CSV layout.

use super::*;

#[test]
fn percentiles_interpolate_between_order_statistics() {
    let timing = Timing::of(&[5.0, 1.0, 4.0, 2.0, 3.0]);
    assert_eq!(timing.median, 3.0);
    assert!((timing.p10 - 1.4).abs() < 1e-12);
    assert!((timing.p90 - 4.6).abs() < 1e-12);
    assert_eq!(Timing::of(&[7.0]).p90, 7.0);
    assert!(Timing::of(&[]).median.is_nan());
}

#[test]
fn csv_quotes_fields_with_commas() {
    assert_eq!(quoted("a,b"), "\"a,b\"");
    assert_eq!(quoted("say \"x\", y"), "\"say \"\"x\"\", y\"");
    assert_eq!(quoted("plain"), "plain");
    let columns: Vec<&str> = CSV_HEADER.split(',').collect();
    let unique: std::collections::HashSet<&str> = columns.iter().copied().collect();
    assert_eq!(unique.len(), columns.len(), "a column named twice: {CSV_HEADER}");
    for step in PrePassStep::ALL {
        let column = format!("{}_ms_median", step.name());
        assert!(CSV_HEADER.split(',').any(|c| c == column), "{column}");
    }
    let draw_columns: Vec<String> =
        DrawPart::ALL.iter().map(|part| format!("draw_{}_ms_median", part.name())).collect();
    let header_draw_columns: Vec<&str> = columns.iter().copied().filter(|c| c.starts_with("draw_")).collect();
    assert_eq!(header_draw_columns, draw_columns, "the draws' parts in `DrawPart::ALL`'s order");
}

#[test]
fn the_share_of_the_saving_runs_from_pixel_to_the_floor() {
    let at = |row_ms| Trade::of(row_ms, 80.0, 20.0);
    assert_eq!(at(20.0).saving_share, 1.0, "at the floor");
    assert_eq!(at(80.0).saving_share, 0.0, "at pixel's time");
    assert_eq!(at(50.0).saving_share, 0.5);
    assert!(at(95.0).saving_share < 0.0, "slower than pixel");
    assert_eq!((at(50.0).floor_ms, at(50.0).ceiling), (20.0, 4.0));
}
