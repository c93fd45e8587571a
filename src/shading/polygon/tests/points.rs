//! The fixed low-discrepancy point set.

use super::*;

#[test]
fn sample_points_form_a_net() {
    for m in 0..=10u32 {
        let count = 1u32 << m;
        let points: Vec<[f32; 2]> = (0..count).map(|i| sample_point(i, count)).collect();
        assert!(points.iter().all(|p| p.iter().all(|x| (0.0..1.0).contains(x))));
        // Every dyadic box of area 1/count holds exactly one point
        for a in 0..=m {
            let b = m - a;
            let mut occupied = vec![0u32; count as usize];
            for p in &points {
                let i = (p[0] * (1u32 << a) as f32) as usize;
                let k = (p[1] * (1u32 << b) as f32) as usize;
                occupied[i << b | k] += 1;
            }
            assert!(occupied.iter().all(|&n| n == 1), "count {count}, boxes {a}+{b}");
        }
    }
    // Any count: the first coordinate is stratified
    let count = 1000;
    let mut strata = vec![0; count as usize];
    for i in 0..count {
        let p = sample_point(i, count);
        assert!(p.iter().all(|x| (0.0..1.0).contains(x)));
        strata[(p[0] * count as f32) as usize] += 1;
    }
    assert!(strata.iter().all(|&n| n == 1));
    assert!(sample_point(1 << 24, 1 << 24)[0] < 1.0);
}
