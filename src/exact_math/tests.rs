//! The elementary functions against f64 libm.

use super::*;

/// The estimator's own elementary functions against f64 libm.
#[test]
fn elementary_functions_are_accurate() {
    let mut worst = [0.0f64; 6];
    for i in 0..=200_000 {
        let x = -1.0 + 8.5 * f64::from(i) / 200_000.0; // [−1, 7.5] rad
        let xf = x as f32;
        let xd = f64::from(xf);
        worst[0] = worst[0].max((f64::from(est_sin(xf)) - xd.sin()).abs());
        worst[1] = worst[1].max((f64::from(est_cos(xf)) - xd.cos()).abs());
        let t = (-3.0 + 6.0 * f64::from(i) / 200_000.0) as f32; // [−3, 3]
        let (y, z) = (t.abs(), 1.0 - 0.5 * t);
        let exact = f64::from(y).atan2(f64::from(z));
        worst[2] = worst[2].max((f64::from(est_atan2(y, z)) - exact).abs());
        let c = (f64::from(i) / 200_000.0) as f32; // [0, 1]
        worst[3] = worst[3].max((f64::from(est_acos(c)) - f64::from(c).acos()).abs());
        worst[4] =
            worst[4].max((f64::from(est_asin(c.min(0.999_999))) - f64::from(c.min(0.999_999)).asin()).abs());
        if c > 0.0 {
            for e in [0.5f32, 2.0, 63.0, 1.0e4] {
                let exact = f64::from(c).powf(f64::from(e));
                if exact > 1.0e-30 {
                    // Relative error, in units of the exponent (the error of log2 is amplified by e).
                    let rel = (f64::from(est_pow(c, e)) / exact - 1.0).abs() / f64::from(e).max(1.0);
                    worst[5] = worst[5].max(rel);
                }
            }
        }
    }
    println!("max errors: sin {:.2e}, cos {:.2e}, atan2 {:.2e}, acos {:.2e}, asin {:.2e} (rad); pow relative / exponent {:.2e}", worst[0], worst[1], worst[2], worst[3], worst[4], worst[5]);
    assert!(worst[..5].iter().all(|&w| w < 5.0e-7), "{worst:?}");
    assert!(worst[5] < 1.0e-6, "{worst:?}");
    assert_eq!(est_pow(0.3, 0.0), 1.0);
    assert_eq!(est_pow(0.3, 1.0), 0.3);
    assert_eq!(est_pow(0.0, 2.0), 0.0);
    assert_eq!(est_atan2(0.0, 0.0), 0.0);
    assert_eq!(est_atan2(0.0, -1.0), PI);
    assert_eq!(est_acos(1.0), 0.0);
}
