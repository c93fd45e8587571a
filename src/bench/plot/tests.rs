//! Tests of `bench::plot`: the Pareto front.

use super::*;

#[test]
fn pareto_front_keeps_undominated_points() {
    let points = [(0.0, 10.0), (0.1, 4.0), (0.2, 5.0), (0.05, 12.0), (0.3, 1.0), (0.3, 2.0)];
    assert_eq!(pareto_front(&points), vec![(0.0, 10.0), (0.1, 4.0), (0.3, 1.0)]);
}
