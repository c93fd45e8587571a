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
    assert_eq!(CSV_HEADER.split(',').count(), 39);
    for step in PrePassStep::ALL {
        let column = format!("{}_ms_median", step.name());
        assert!(CSV_HEADER.split(',').any(|c| c == column), "{column}");
    }
}
