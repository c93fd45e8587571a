//! Unit tests of `vk::budget`.

use super::*;

#[test]
fn the_resident_set_is_read_from_the_status_text() {
    let status = "Name:\tmultirate\nVmHWM:\t  9000 kB\nVmRSS:\t  123456 kB\nThreads:\t3\n";
    assert_eq!(parse_vm_rss(status), Some(123_456 * 1024));
    assert_eq!(parse_vm_rss("Name:\tx\n"), None);
    assert_eq!(parse_vm_rss("VmRSS:\t12 MB\n"), None, "only kB is known");
    assert!(resident_set_bytes().is_none_or(|bytes| bytes > 0));
}

#[test]
fn growth_is_a_fraction_of_the_start() {
    assert_eq!(growth(200, 202), Some(0.01));
    assert_eq!(growth(200, 100), Some(-0.5));
    assert_eq!(growth(0, 5), None);
}
