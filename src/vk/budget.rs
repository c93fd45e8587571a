//! Memory in use, for the soaks and their reports: the device's heaps as its driver counts them
//! (`VK_EXT_memory_budget`, where the device has it; Debian 12's lavapipe, Mesa 22.3, does
//! not), the device memory the allocator holds and has handed out, and the
//! process's resident set (Linux, `/proc/self/status`). On a CPU device such as lavapipe,
//! device memory is host memory, so the resident set includes it.

use super::context::Context;
use ash::vk;

/// Memory figures taken at one moment.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MemoryUse {
    /// The process's resident set in bytes; None where `/proc/self/status` is not readable.
    pub resident: Option<u64>,
    /// The driver's usage summed over the device's heaps, in bytes; None without
    /// `VK_EXT_memory_budget`.
    pub device: Option<u64>,
    /// The bytes of the device-memory blocks the allocator holds (every buffer and image of
    /// the renderer lives in one; swapchain images are the driver's).
    pub allocator_blocks: u64,
    /// The bytes of the live allocations within them.
    pub allocated: u64,
}

impl MemoryUse {
    /// The figures now.
    pub fn now(context: &Context) -> MemoryUse {
        let (allocator_blocks, allocated) = context
            .allocator
            .lock()
            .map(|allocator| {
                let report = allocator.generate_report();
                (report.total_capacity_bytes, report.total_allocated_bytes)
            })
            .unwrap_or((0, 0));
        MemoryUse {
            resident: resident_set_bytes(),
            device: device_heap_usage(context),
            allocator_blocks,
            allocated,
        }
    }
}

/// The process's resident set size in bytes (`VmRSS`), where the system reports it.
pub fn resident_set_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_vm_rss(&status)
}

/// `VmRSS` of a `/proc/<pid>/status` text, in bytes.
fn parse_vm_rss(status: &str) -> Option<u64> {
    let line = status.lines().find(|line| line.starts_with("VmRSS:"))?;
    let mut words = line["VmRSS:".len()..].split_whitespace();
    let value: u64 = words.next()?.parse().ok()?;
    match words.next() {
        Some("kB") => Some(value * 1024),
        _ => None,
    }
}

/// The driver's heap usage summed over the device's heaps, in bytes, where the device has
/// `VK_EXT_memory_budget` (enabled by [`Context`] when present).
pub fn device_heap_usage(context: &Context) -> Option<u64> {
    if !context.features.memory_budget {
        return None;
    }
    let mut budget = vk::PhysicalDeviceMemoryBudgetPropertiesEXT::default();
    let mut properties = vk::PhysicalDeviceMemoryProperties2::default().push_next(&mut budget);
    // SAFETY: a plain query on the context's physical device, which supports the extension
    // whose structure is chained; both structures outlive the call.
    unsafe {
        context.instance.get_physical_device_memory_properties2(context.physical_device, &mut properties)
    };
    let heaps = properties.memory_properties.memory_heap_count as usize;
    Some(budget.heap_usage.iter().take(heaps).sum())
}

/// Growth from `start` to `end` as a fraction of `start` (negative when it shrank); None when
/// `start` is zero.
pub fn growth(start: u64, end: u64) -> Option<f64> {
    (start > 0).then(|| (end as f64 - start as f64) / start as f64)
}

#[cfg(test)]
mod tests;
