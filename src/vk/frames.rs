//! Frames in flight for offscreen loops (measurement): a command buffer and a fence per slot,
//! so the CPU records and submits frame i + 1 while the GPU still runs frame i, and waits only
//! when it comes back to a slot whose frame has not finished.

use super::context::Context;
use crate::error::{Result, VkContext};
use ash::vk;
use std::sync::Arc;

struct Slot {
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    in_flight: bool,
}

/// A ring of command buffers and fences.
pub struct FrameRing {
    context: Arc<Context>,
    pool: vk::CommandPool,
    slots: Vec<Slot>,
}

impl FrameRing {
    /// `count` slots (frames that may be in flight at once).
    pub fn new(context: &Arc<Context>, count: usize) -> Result<FrameRing> {
        let device = &context.device;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(context.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid create info; destroyed in `Drop`.
        let pool = unsafe { device.create_command_pool(&pool_info, None) }
            .while_("creating the frame command pool")?;
        let mut ring = FrameRing { context: context.clone(), pool, slots: Vec::with_capacity(count) };
        let alloc_info = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(count as u32);
        // SAFETY: the pool was created above; the buffers are freed with it.
        let buffers = unsafe { device.allocate_command_buffers(&alloc_info) }
            .while_("allocating frame command buffers")?;
        for cmd in buffers {
            // SAFETY: plain fence creation; destroyed in `Drop`.
            let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
                .while_("creating a frame fence")?;
            ring.slots.push(Slot { cmd, fence, in_flight: false });
        }
        Ok(ring)
    }

    pub fn len(&self) -> usize {
        self.slots.len()
    }

    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }

    /// Waits until the frame last submitted in `slot` has finished; false if none was in
    /// flight there.
    pub fn wait(&mut self, slot: usize) -> Result<bool> {
        let device = &self.context.device;
        let entry = &mut self.slots[slot];
        if !entry.in_flight {
            return Ok(false);
        }
        // SAFETY: the fence was submitted with the slot's last frame.
        unsafe { device.wait_for_fences(&[entry.fence], true, u64::MAX) }.while_("waiting for a frame")?;
        // SAFETY: the fence is signalled and no longer used by pending work.
        unsafe { device.reset_fences(&[entry.fence]) }.while_("resetting a frame fence")?;
        entry.in_flight = false;
        Ok(true)
    }

    /// Records a frame with `record` into `slot` and submits it. Call `wait(slot)` first.
    pub fn submit(&mut self, slot: usize, record: impl FnOnce(vk::CommandBuffer)) -> Result<()> {
        let device = &self.context.device;
        let entry = &mut self.slots[slot];
        assert!(!entry.in_flight, "wait for slot {slot} before reusing it");
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the slot's previous frame finished (asserted above), so its command buffer
        // may be reset and recorded again.
        unsafe {
            device
                .reset_command_buffer(entry.cmd, vk::CommandBufferResetFlags::empty())
                .while_("resetting a frame command buffer")?;
            device.begin_command_buffer(entry.cmd, &begin).while_("beginning a frame")?;
        }
        record(entry.cmd);
        // SAFETY: recording began above.
        unsafe { device.end_command_buffer(entry.cmd) }.while_("ending a frame")?;
        let cmd_info = [vk::CommandBufferSubmitInfo::default().command_buffer(entry.cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmd_info)];
        self.context.submit(&submit, entry.fence)?;
        entry.in_flight = true;
        Ok(())
    }
}

impl Drop for FrameRing {
    fn drop(&mut self) {
        let device = &self.context.device;
        // SAFETY: waiting first makes every fence and command buffer idle before destruction.
        unsafe {
            let pending: Vec<vk::Fence> =
                self.slots.iter().filter(|s| s.in_flight).map(|s| s.fence).collect();
            if !pending.is_empty() {
                let _ = device.wait_for_fences(&pending, true, u64::MAX);
            }
            for slot in &self.slots {
                device.destroy_fence(slot.fence, None);
            }
            device.destroy_command_pool(self.pool, None);
        }
    }
}
