//! Tests of `render::cost_model`: the break-even area and the calibration store.

use super::*;

#[test]
fn the_break_even_area_weighs_an_estimate_against_its_pixels() {
    let model = CostModel {
        calibration: Calibration {
            estimate: LinearCost { fixed_ns: 1000.0, per_light_ns: 500.0 },
            pixel: LinearCost { fixed_ns: 50.0, per_light_ns: 25.0 },
            measured_with: String::new(),
        },
        source: String::new(),
    };
    // 1500 ns against 75 ns a pixel: 20 pixels, and the three corners level 1 shades.
    assert_eq!(model.min_estimated_area(1), 23.0);
    assert_eq!(model.min_estimated_area(2), 2000.0 / 100.0 + 3.0);
    let line = LinearCost::through((1, 1500.0), (8, 5000.0));
    assert_eq!((line.fixed_ns, line.per_light_ns), (1000.0, 500.0));
    let free = LinearCost { fixed_ns: -5.0, per_light_ns: 0.0 };
    assert!(free.at(3) > 0.0, "a measured cost below zero stays a finite ratio");
}

#[test]
fn calibrations_are_stored_per_device_and_read_back() {
    let folder = std::env::temp_dir().join(format!("multirate-cost-model-{}", std::process::id()));
    let path = folder.join("nested").join("cost_model.toml");
    let mut calibration = CostModel::lavapipe().calibration;
    CostModel::store(&path, "device A", &calibration).unwrap();
    calibration.estimate.fixed_ns = 42.0;
    CostModel::store(&path, "device B", &calibration).unwrap();
    let store = load_store(&path).unwrap();
    assert_eq!(store.devices.len(), 2);
    assert_eq!(store.devices["device B"].estimate.fixed_ns, 42.0);
    assert_eq!(store.devices["device A"], CostModel::lavapipe().calibration);
    std::fs::write(&path, "devices = 3").unwrap();
    let error = CostModel::store(&path, "device C", &calibration).unwrap_err().to_string();
    assert!(error.contains("cost_model.toml") && error.contains("not a cost-model store"), "{error}");
    std::fs::remove_dir_all(&folder).unwrap();
}
