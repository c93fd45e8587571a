//! Unit tests of `vk::context`.

use super::*;

#[test]
fn a_device_without_tessellation_is_rejected_with_the_reason() {
    let properties = vk::PhysicalDeviceProperties { api_version: vk::API_VERSION_1_3, ..Default::default() };
    let mut features = vk::PhysicalDeviceFeatures::default();
    let reason = unsuitability(&properties, &features).expect("rejected");
    assert!(reason.contains("tessellationShader"), "{reason}");
    features.tessellation_shader = vk::TRUE;
    assert_eq!(unsuitability(&properties, &features), None);
    let old = vk::PhysicalDeviceProperties { api_version: vk::API_VERSION_1_1, ..Default::default() };
    assert!(unsuitability(&old, &features).expect("rejected").contains("1.3 is needed"));
}
